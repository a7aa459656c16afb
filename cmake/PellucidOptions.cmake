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
# Sanitizers for every target of the build, as a comma-separated -fsanitize= list, e.g.
# "address,undefined" (what `make sanitize` uses). Empty: none. Any finding aborts the process
# (no recovery), so a test that triggers one fails.
set(PELLUCID_SANITIZE "" CACHE STRING "Sanitizers to build with, e.g. address,undefined (empty: none)")
if(PELLUCID_SANITIZE)
  add_compile_options(-fsanitize=${PELLUCID_SANITIZE} -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_link_options(-fsanitize=${PELLUCID_SANITIZE})
endif()
# The SIMD targets the path tracer and its lane tests are built for, as a list (x86-64: avx512, avx2,
# sse4; arm64: neon); empty: every target of the processor family. The scalar target is always
# built, and the run time picks the widest built target the CPU runs. `make sanitize` builds "avx2"
# on x86-64 (Makefile).
set(PELLUCID_KERNEL_TARGETS "" CACHE STRING "SIMD targets to build, e.g. avx2;sse4 (empty: all of this processor family)")
# A diagnostic build of the path tracer (bench/dispatch_stats.py): each masked call of a packet
# form records its active lanes and its time stamp-counter cycles, printed when the process exits.
# Off in every other build, where the counting compiles to nothing.
option(PELLUCID_DISPATCH_STATS "Count the path tracer's packet-form calls, their active lanes and cycles" OFF)
if(PELLUCID_DISPATCH_STATS)
  add_compile_definitions(PELLUCID_DISPATCH_STATS=1)
endif()
