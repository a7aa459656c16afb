# INTERFACE target carrying pellucid's warning flags (linked PRIVATE by our own targets only).
# SPDX-License-Identifier: Apache-2.0
add_library(pellucid_warnings INTERFACE)
if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
  target_compile_options(pellucid_warnings INTERFACE -Wall -Wextra -Wno-unused-parameter)
endif()
