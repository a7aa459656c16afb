// The registry: ONE explicit table per object family, from "type" name to builder function
// (Tungsten's BsdfFactory style; no static self-registration).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <map>
#include <string>
#include <vector>

#include "pellucid/geometry/mesh.h"
#include "pellucid/image/filter.h"
#include "pellucid/material/material.h"
#include "pellucid/scene/properties.h"
#include "pellucid/texture/texture.h"

namespace pellucid {

/// What a shape builder produces: a world-space mesh, or an analytic sphere.
struct ShapeGeometry {
    bool is_sphere = false;
    TriangleMesh mesh;
    Point3f center{0.f};
    float radius = 1.f;
    bool flip_normals = false;
    /// Per-face materials (OBJ `usemtl`, resolved to scene materials by scene/build.cpp): the
    /// distinct names, and per triangle an index into them or ObjMesh::kNoMaterial. Both empty
    /// when the shape has one material.
    std::vector<std::string> face_material_names;
    std::vector<uint32_t> face_material;
    /// The shape's `materials` renames: usemtl name -> scene material id.
    std::vector<std::pair<std::string, std::string>> material_renames;
};

class TextureBuilder;
struct MaterialTextures;

/// Context for builders: file resolution, and (during scene building) where textured material
/// parameters go. `textures`/`material_textures` are null where no scene is being built
/// (pellucid.bsdf): a textured parameter is then an error.
struct BuildContext {
    std::string source;
    std::string base_dir;
    TextureBuilder* textures = nullptr;
    MaterialTextures* material_textures = nullptr;
    /// Resolve a path relative to the scene file's directory.
    std::string resolve(const std::string& path) const;
};

using MaterialBuilder = Material (*)(Properties&, const BuildContext&);
using ShapeBuilder = ShapeGeometry (*)(Properties&, const BuildContext&);
using FilterBuilder = Filter (*)(Properties&);
using TextureBuilderFn = Texture (*)(Properties&, TextureBuilder&);

const std::map<std::string, MaterialBuilder>& material_registry();
const std::map<std::string, ShapeBuilder>& shape_registry();
const std::map<std::string, FilterBuilder>& filter_registry();
const std::map<std::string, TextureBuilderFn>& texture_registry();
/// Every registered type per family ("materials", "shapes", "lights", "emitters", "filters",
/// "cameras", "integrators"), for documentation checks and error messages.
std::map<std::string, std::vector<std::string>> registry_types();
/// "a, b, c"
std::string join_names(const std::vector<std::string>& names);
/// The error for a "type" that `family` ("material", "shape", "texture", "light", "filter") does not
/// register, with a hint: "unknown material type 'diffuse' (Mitsuba's 'diffuse' is 'lambertian' here;
/// known: ...)" for a Mitsuba plugin name, "(did you mean 'lambertian'? known: ...)" for a near miss.
std::string unknown_type_message(const std::string& family, const std::string& type,
                                 const std::vector<std::string>& known);
}  // namespace pellucid
