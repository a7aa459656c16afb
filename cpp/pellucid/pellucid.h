// Version and project-wide basic definitions.
// SPDX-License-Identifier: Apache-2.0
#pragma once

#ifndef PELLUCID_VERSION
#define PELLUCID_VERSION "0.0.0"
#endif

namespace pellucid {
using Float = float;

}  // namespace pellucid
