// Parameter updates: a built scene's parameters by key path, as the scene format and its errors name
// them ("materials.red.reflectance", "lights[0].radiance", "camera.fov"), and updates that change
// the scene in place, rebuilding only what depends on the changed values (pellucid.parameters).
//
// Everything works on the scene description (scene_desc.h) the scene keeps: an update edits it
// and runs the scene builder (build.cpp) again on it into a new Scene, telling it which shapes keep
// their geometry, then moves the rebuilt parts into the scene. Nothing here knows how a material,
// texture or light stores its values.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "pellucid/scene/scene.h"
#include "pellucid/scene/scene_desc.h"

namespace pellucid {

/// One parameter of a scene description: its key path and its value there.
struct SceneParameter {
    std::string path;
    const Node* value = nullptr;
};

/// Every parameter of `desc`, in the description's order: each value that is not an object (a
/// number, string, boolean or array of numbers), by its key path. An object's "type" is not a
/// parameter; a `to_world` or `to_uv` is one parameter whatever its form (a matrix or a list of operations).
/// Objects are walked into, and so are arrays that hold objects (shapes, lights).
std::vector<SceneParameter> scene_parameters(const SceneDesc& desc);

/// Throw pellucid::Error ("<source>: <path>: unknown parameter (did you mean ...)") unless `path`
/// names a parameter of `desc`, or, with `allow_new`, a key that one of its typed objects (a
/// material, texture, light, shape, emitter, the camera) or film, sampler or integrator leaves at
/// its default: such a key can be set too, and the builder then checks that the object takes it.
void check_parameter_path(const SceneDesc& desc, const std::string& path, bool allow_new = true);

/// What an update rebuilt.
struct UpdateReport {
    bool geometry = false;      ///< the BVH was built anew (some shape's geometry changed)
    bool full = false;          ///< everything was built from the description, meshes included
    size_t shapes_rebuilt = 0;  ///< shapes whose geometry was built anew
    double seconds = 0.0;
};

/// Set each key path of `edits` to its value in the scene's description and rebuild from it, in
/// place: film, sampler, integrator, camera, textures, materials and lights (with the
/// light-selection distribution) and media always; the geometry only of the shapes whose keys other
/// than material, emitter, interior and exterior changed (to_world, center, radius, positions,
/// filename, ...), and then the BVH.
/// Unchanged meshes are kept (copied into the new BVH when one is built), never read again. When a
/// change could renumber the materials (a shape's `material` becomes or stops being inline, or is
/// added), everything is built anew from the description.
/// Errors are the scene builder's, naming the key path and value; unknown key paths get a
/// "did you mean". On any error the edits are undone and the scene is left unchanged. Not
/// thread-safe with a render of the same scene.
UpdateReport update_scene(Scene& scene, const std::vector<std::pair<std::string, Node>>& edits);
}  // namespace pellucid
