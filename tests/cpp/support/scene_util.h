// Helpers shared by the scene-level tests: building a scene from a JSON string, the two-sided normal
// quantile for z-tests, and capturing log warnings.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "pellucid/api.h"
#include "pellucid/scene/json_io.h"
#include "pellucid/util/log.h"

namespace pellucid::test {

/// A JSON "camera" member: 40° perspective on the origin from (0, 0, 5), for the analytic-scene tests.
inline const char* const kFrontCamera = R"("camera": {"type": "perspective", "fov": 40,
    "to_world": [{"look_at": {"origin": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0]}}]})";

/// Build a scene from JSON text; relative files resolve against `base`. Errors start with "test".
inline std::shared_ptr<const Scene> scene_from(const std::string& json, const std::string& base = ".") {
    SceneDesc d;
    d.root = parse_json(json, "test");
    d.source = "test";
    d.base_dir = base;
    return load_desc(d);
}

/// |z| whose two-sided normal tail probability is alpha (bisection on erfc: exact enough for test
/// thresholds).
inline double z_two_sided(double alpha) {
    double lo = 0, hi = 40;
    for (int i = 0; i < 200; ++i) {
        double mid = 0.5 * (lo + hi);
        (std::erfc(mid / std::sqrt(2.0)) > alpha ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

/// Captures log warnings while alive.
struct LogCapture {
    std::vector<std::string> warnings;
    LogCapture() {
        set_log_sink([this](LogLevel l, const std::string& m) {
            if (l == LogLevel::Warning) warnings.push_back(m);
        });
    }
    ~LogCapture() { set_log_sink(nullptr); }
    LogCapture(const LogCapture&) = delete;
    LogCapture& operator=(const LogCapture&) = delete;
    bool has(const std::string& s) const {
        for (const auto& w : warnings)
            if (w.find(s) != std::string::npos) return true;
        return false;
    }
};
}  // namespace pellucid::test
