// The registry tables and the builders for shapes and filters (material builders: material/builders.cpp).
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/scene/registry.h"

#include <cmath>
#include <filesystem>

#include "pellucid/geometry/mesh_io.h"
#include "pellucid/material/builders.h"
#include "pellucid/scene/texture_builder.h"
#include "pellucid/util/error.h"

namespace pellucid {

std::string BuildContext::resolve(const std::string& path) const {
    std::filesystem::path p(path);
    if (p.is_absolute()) return path;
    return (std::filesystem::path(base_dir) / p).lexically_normal().string();
}

std::string join_names(const std::vector<std::string>& names) {
    std::string s;
    for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
    return s;
}

namespace {
// ---- shapes -------------------------------------------------------------------------------------
ShapeGeometry build_mesh(Properties& p, const BuildContext&) {
    ShapeGeometry g;
    std::vector<float> pos = p.get_float_array("positions");
    std::vector<int64_t> idx = p.get_int_array("indices");
    std::vector<float> nrm = p.get_float_array("normals");
    std::vector<float> uv = p.get_float_array("uvs");
    if (pos.empty() || pos.size() % 3) p.fail("positions", "expected a non-empty flat array of x,y,z triples");
    if (idx.empty() || idx.size() % 3) p.fail("indices", "expected a non-empty flat array of index triples");
    if (!nrm.empty() && nrm.size() != pos.size()) p.fail("normals", "expected one normal per vertex");
    if (!uv.empty() && uv.size() / 2 != pos.size() / 3) p.fail("uvs", "expected one uv pair per vertex");
    size_t nv = pos.size() / 3;
    for (size_t i = 0; i < nv; ++i) g.mesh.positions.emplace_back(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]);
    for (size_t i = 0; i < nrm.size() / 3; ++i) g.mesh.normals.emplace_back(nrm[3 * i], nrm[3 * i + 1], nrm[3 * i + 2]);
    for (size_t i = 0; i < uv.size() / 2; ++i) g.mesh.uvs.emplace_back(uv[2 * i], uv[2 * i + 1]);
    for (size_t i = 0; i < idx.size(); ++i) {
        if (idx[i] < 0 || size_t(idx[i]) >= nv)
            p.fail(path_index("indices", i), "index " + std::to_string(idx[i]) + " out of range (mesh has " +
                                                 std::to_string(nv) + " vertices)");
        g.mesh.indices.push_back(uint32_t(idx[i]));
    }
    if (p.get_bool("smooth_normals", false)) g.mesh.compute_smooth_normals();
    return g;
}
// Meshes from files (geometry/mesh_io.h). Per-face OBJ materials are not mapped yet: the shape's
// `material` applies to every face.
ShapeGeometry build_mesh_file(Properties& p, const BuildContext& ctx, bool obj) {
    ShapeGeometry g;
    MeshLoadOptions o;
    std::string file = ctx.resolve(p.get_string("filename"));
    o.face_normals = p.get_bool("face_normals", false);
    o.smooth_normals = p.get_bool("smooth_normals", false);
    if (obj) o.flip_tex_coords = p.get_bool("flip_tex_coords", false);
    try {
        g.mesh = obj ? load_obj(file, o).mesh : load_ply(file, o);
    } catch (const Error& e) {
        p.fail("filename", e.what());
    }
    return g;
}
ShapeGeometry build_obj(Properties& p, const BuildContext& ctx) { return build_mesh_file(p, ctx, true); }
ShapeGeometry build_ply(Properties& p, const BuildContext& ctx) { return build_mesh_file(p, ctx, false); }
ShapeGeometry build_rectangle(Properties&, const BuildContext&) {
    ShapeGeometry g;
    g.mesh = TriangleMesh::rectangle();
    return g;
}
ShapeGeometry build_cube(Properties&, const BuildContext&) {
    ShapeGeometry g;
    g.mesh = TriangleMesh::cube();
    return g;
}
ShapeGeometry build_sphere(Properties& p, const BuildContext&) {
    ShapeGeometry g;
    g.is_sphere = true;
    g.center = p.get_vec3("center", Vec3f(0.f));
    g.radius = p.get_float("radius", 1.f);
    if (!(g.radius > 0.f)) p.fail("radius", "value " + std::to_string(g.radius) + " must be > 0");
    g.flip_normals = p.get_bool("flip_normals", false);
    return g;
}

// ---- filters ------------------------------------------------------------------------------------
Filter build_box(Properties& p) {
    float r = p.get_float("radius", 0.5f);
    p.check_range("radius", r, 1e-3f, 16.f);
    return BoxFilter{r};
}
Filter build_tent(Properties& p) {
    float r = p.get_float("radius", 1.f);
    p.check_range("radius", r, 1e-3f, 16.f);
    return TentFilter{r};
}
Filter build_gaussian(Properties& p) {
    float s = p.get_float("stddev", 0.5f);
    p.check_range("stddev", s, 1e-3f, 4.f);
    return GaussianFilter(s);
}
}  // namespace

const std::map<std::string, MaterialBuilder>& material_registry() {
    static const std::map<std::string, MaterialBuilder> table = {
        // Builders live in material/builders.cpp; parameter tables in the material headers.
        {"lambertian", build_lambertian},
        {"oren_nayar", build_oren_nayar},
        {"conductor", build_conductor},
        {"rough_conductor", build_rough_conductor},
        {"dielectric", build_dielectric},
        {"rough_dielectric", build_rough_dielectric},
        {"thin_dielectric", build_thin_dielectric},
        {"plastic", build_plastic},
        {"rough_plastic", build_rough_plastic},
        {"principled", build_principled},
    };
    return table;
}

const std::map<std::string, ShapeBuilder>& shape_registry() {
    static const std::map<std::string, ShapeBuilder> table = {
        {"mesh", build_mesh},
        {"obj", build_obj},
        {"ply", build_ply},
        {"rectangle", build_rectangle},
        {"cube", build_cube},
        {"sphere", build_sphere},
    };
    return table;
}

const std::map<std::string, FilterBuilder>& filter_registry() {
    static const std::map<std::string, FilterBuilder> table = {
        {"box", build_box}, {"tent", build_tent}, {"gaussian", build_gaussian}};
    return table;
}

const std::map<std::string, TextureBuilderFn>& texture_registry() {
    static const std::map<std::string, TextureBuilderFn> table = {
        // Builders live in scene/texture_builder.cpp; parameter tables in texture/texture.h.
        {"image", build_image_texture},
        {"checkerboard", build_checkerboard_texture},
        {"noise", build_noise_texture},
        {"scale", build_scale_texture},
        {"mix", build_mix_texture},
    };
    return table;
}

std::map<std::string, std::vector<std::string>> registry_types() {
    std::map<std::string, std::vector<std::string>> out;
    for (const auto& [k, v] : material_registry()) out["materials"].push_back(k);
    for (const auto& [k, v] : shape_registry()) out["shapes"].push_back(k);
    for (const auto& [k, v] : filter_registry()) out["filters"].push_back(k);
    for (const auto& [k, v] : texture_registry()) out["textures"].push_back(k);
    out["lights"] = {"constant", "directional", "envmap", "point", "spot"};
    out["emitters"] = {"area"};
    out["cameras"] = {"perspective"};
    out["integrators"] = {"aov", "path"};
    return out;
}
}  // namespace pellucid
