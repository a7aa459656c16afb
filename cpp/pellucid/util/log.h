// Levelled logging with a replaceable sink (the Python module routes it to `logging`).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <functional>
#include <string>

namespace pellucid {
enum class LogLevel { Debug = 10, Info = 20, Warning = 30, Error = 40 };
using LogSink = std::function<void(LogLevel, const std::string&)>;

/// Replace the sink (nullptr restores the default, which prints warnings and errors to stderr).
void set_log_sink(LogSink sink);
void log(LogLevel level, const std::string& msg);
inline void log_warning(const std::string& msg) { log(LogLevel::Warning, msg); }
inline void log_info(const std::string& msg) { log(LogLevel::Info, msg); }
}  // namespace pellucid
