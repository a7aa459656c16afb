// pellucid::Error helpers.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/util/error.h"

namespace pellucid {
void throw_error(const std::string& msg) { throw Error(msg); }
}  // namespace pellucid
