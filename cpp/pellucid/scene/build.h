// SceneDesc -> Scene: validation, name resolution, and errors that carry the key path.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <memory>
#include <set>
#include <string>

#include "pellucid/scene/scene.h"
#include "pellucid/scene/scene_desc.h"

namespace pellucid {
/// Build an immutable scene. Throws pellucid::Error "<source>: <key path>: <problem>".
/// The scene keeps a copy of `desc` (Scene::desc) for parameter updates; the second form moves it.
std::unique_ptr<Scene> build_scene(const SceneDesc& desc);
std::unique_ptr<Scene> build_scene(SceneDesc&& desc);

/// What a parameter update (scene/scene_update.h) keeps of the scene it rebuilds: every shape whose
/// key path is not in `changed` takes its geometry (record, mesh) from `prior` instead of from its
/// builder; its material and emitter are built anew. With `changed` empty the new scene gets no
/// meshes and no BVH (the update keeps the prior's). `prior` null: a full build.
struct GeometryReuse {
    const Scene* prior = nullptr;
    std::set<std::string> changed;  ///< key paths of the shapes built anew ("shapes[2]")
};
/// build_scene for a parameter update; the result keeps no description.
std::unique_ptr<Scene> build_scene(const SceneDesc& desc, const GeometryReuse& reuse);
}  // namespace pellucid
