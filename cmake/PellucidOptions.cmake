# Build options for pellucid.
# SPDX-License-Identifier: Apache-2.0
if(DEFINED SKBUILD)
  set(_py_default ON)
else()
  set(_py_default OFF)
endif()
option(PELLUCID_BUILD_PYTHON "Build the pellucid._core Python extension" ${_py_default})
option(PELLUCID_BUILD_TESTS "Build the GTest suite (ctest)" ON)
option(PELLUCID_BUILD_APP "Build the pellucid-render executable" ON)
# Builds run on the machine that renders (make, CI), so tuning for it is safe; turn off to package.
option(PELLUCID_NATIVE "Compile for the build machine's CPU (-march=native)" ON)
