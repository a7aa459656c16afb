// pellucid::Error, the one exception type, and check macros.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <stdexcept>
#include <string>

namespace pellucid {

/// Raised for every user-facing failure: bad scene, bad parameter, missing file, I/O error.
/// The message starts with where the problem is (file, key path, line) so it can be acted on.
class Error : public std::runtime_error {
public:
    explicit Error(const std::string& msg) : std::runtime_error(msg) {}
};

[[noreturn]] void throw_error(const std::string& msg);
}  // namespace pellucid

#define PELLUCID_CHECK(cond, msg)                                                          \
    do {                                                                                   \
        if (!(cond)) ::pellucid::throw_error(std::string("internal check failed: ") + #cond \
                                             + ": " + (msg));                              \
    } while (0)
