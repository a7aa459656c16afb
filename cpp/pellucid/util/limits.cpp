// Input limits.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/util/limits.h"

#include <cstdio>
#include <cstdlib>
#include <string>

#include "pellucid/util/error.h"

namespace pellucid {

int max_scene_depth() {
    static const int depth = [] {
        const char* s = std::getenv("PELLUCID_MAX_SCENE_DEPTH");
        if (!s || !*s) return kDefaultMaxSceneDepth;
        char* end = nullptr;
        long v = std::strtol(s, &end, 10);
        if (*end != '\0' || v < 1 || v > 100000)
            throw Error("environment variable PELLUCID_MAX_SCENE_DEPTH: expected an integer in [1, 100000], got '" +
                        std::string(s) + "'");
        return int(v);
    }();
    return depth;
}
std::string point_text(float x, float y, float z) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "[%g, %g, %g]", double(x), double(y), double(z));
    return buf;
}
}  // namespace pellucid
