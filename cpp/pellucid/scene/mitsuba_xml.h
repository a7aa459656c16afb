// Mitsuba 3 XML scenes -> SceneDesc (the same JSON-shaped IR as our JSON scenes; see
// docs/mitsuba-import.md for every mapping and every difference in definition). The only pugixml
// user.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <map>
#include <string>

#include "pellucid/scene/scene_desc.h"

namespace pellucid {

/// Read a Mitsuba 3.x XML scene file. `params` set `$name` substitutions and override the file's
/// `<default>` values. Errors (pellucid::Error) name the file and line:
/// `scene.xml:12: unsupported bsdf plugin 'hair'`. With `lenient`, unsupported plugins and
/// parameters are logged as warnings and skipped instead; malformed XML, unknown ids, missing
/// includes and bad values stay errors.
SceneDesc read_mitsuba_xml_file(const std::string& path, bool lenient,
                                const std::map<std::string, std::string>& params = {});

/// Parse Mitsuba XML text. `source` names it in errors (and is SceneDesc::source); relative file
/// names and includes resolve against `base_dir`.
SceneDesc parse_mitsuba_xml(const std::string& text, const std::string& source,
                            const std::string& base_dir, bool lenient,
                            const std::map<std::string, std::string>& params = {});
}  // namespace pellucid
