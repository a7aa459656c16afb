// SceneDesc -> Scene: validation, name resolution, and errors that carry the key path.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <memory>

#include "pellucid/scene/scene.h"
#include "pellucid/scene/scene_desc.h"

namespace pellucid {
/// Build an immutable scene. Throws pellucid::Error "<source>: <key path>: <problem>".
std::unique_ptr<Scene> build_scene(const SceneDesc& desc);
}  // namespace pellucid
