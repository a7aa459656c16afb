// The message of the pellucid::Error a call throws, for tests of error messages.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <string>

#include "pellucid/scene/build.h"
#include "pellucid/scene/json_io.h"
#include "pellucid/util/error.h"

namespace pellucid::test {

/// what() of the pellucid::Error that f() throws, or "" when it throws none.
template <class F>
std::string error_of_call(F&& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

/// The error of parsing and building a JSON scene read from "scene.json", or "".
inline std::string json_scene_error(const std::string& json) {
    return error_of_call([&] {
        SceneDesc d;
        d.source = "scene.json";
        d.root = parse_json(json, "scene.json");
        build_scene(d);
    });
}
}  // namespace pellucid::test
