// JSON text <-> SceneDesc (the only nlohmann_json user).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <string>

#include "pellucid/scene/scene_desc.h"

namespace pellucid {
/// Parse a JSON scene file. Errors name the file, and the line and column for syntax errors.
SceneDesc read_json_file(const std::string& path);
/// Parse JSON text; `source` names it in errors.
Node parse_json(const std::string& text, const std::string& source);
std::string to_json(const Node& node, int indent = 2);
}  // namespace pellucid
