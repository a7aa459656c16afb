// Input limits.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/util/limits.h"

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
}  // namespace pellucid
