// Shared helpers of the libFuzzer harnesses: a private scratch directory, writing an input to a
// file there, and the rule every harness enforces: the only acceptable failure is a
// pellucid::Error that is not an internal check. Anything else (another exception, a crash, a
// sanitizer report) stops the fuzzer with the input saved.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>
#include <string>

#include "pellucid/util/error.h"
#include "pellucid/util/log.h"

namespace fuzz {

/// A directory of this process's own, created once (under $TMPDIR, else /tmp).
inline const std::string& scratch_dir() {
    static const std::string dir = [] {
        const char* t = std::getenv("TMPDIR");
        std::string templ = std::string(t && *t ? t : "/tmp") + "/pellucid-fuzz-XXXXXX";
        if (!mkdtemp(templ.data())) {
            std::perror("mkdtemp");
            std::abort();
        }
        // Warnings are expected for most inputs; printing them would dominate the run time.
        pellucid::set_log_sink([](pellucid::LogLevel, const std::string&) {});
        return templ;
    }();
    return dir;
}

/// Write `data` to `name` in the scratch directory; returns the path.
inline std::string write_file(const std::string& name, const uint8_t* data, size_t size) {
    std::string path = scratch_dir() + "/" + name;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    return path;
}

/// Run `f`; a pellucid::Error is the expected outcome of a bad input, anything else is a finding.
template <class F>
void expect_only_errors(F&& f) {
    try {
        f();
    } catch (const pellucid::Error& e) {
        if (std::strncmp(e.what(), "internal", 8) == 0) {
            std::fprintf(stderr, "internal error: %s\n", e.what());
            std::abort();
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "unexpected exception (not pellucid::Error): %s\n", e.what());
        std::abort();
    } catch (...) {
        std::fprintf(stderr, "unexpected exception of unknown type\n");
        std::abort();
    }
}

/// True when the text names a device or process file: a scene may read any file it names, and
/// /dev/zero or /dev/stdin never end. Such inputs are skipped.
inline bool names_special_file(const uint8_t* data, size_t size) {
    std::string s(reinterpret_cast<const char*>(data), size);
    return s.find("/dev") != std::string::npos || s.find("/proc") != std::string::npos ||
           s.find("/sys") != std::string::npos;
}
}  // namespace fuzz
