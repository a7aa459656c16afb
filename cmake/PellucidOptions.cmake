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
# The path tracer picks its SIMD instruction set at run time (cpp/pellucid/integrator/simd_target.h),
# so the default build runs on any x86-64 or arm64 CPU; ON tunes the rest of the library to the
# build machine as well.
option(PELLUCID_NATIVE "Compile the library for the build machine's CPU (-march=native)" OFF)
