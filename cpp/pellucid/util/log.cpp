// Logging sink.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/util/log.h"

#include <cstdio>
#include <mutex>

namespace pellucid {
namespace {
std::mutex g_mutex;
LogSink g_sink;
}  // namespace

void set_log_sink(LogSink sink) {
    std::lock_guard<std::mutex> lock(g_mutex);
    g_sink = std::move(sink);
}

void log(LogLevel level, const std::string& msg) {
    std::lock_guard<std::mutex> lock(g_mutex);
    if (g_sink) {
        g_sink(level, msg);
        return;
    }
    if (level >= LogLevel::Warning)
        std::fprintf(stderr, "pellucid: %s: %s\n", level == LogLevel::Warning ? "warning" : "error",
                     msg.c_str());
}
}  // namespace pellucid
