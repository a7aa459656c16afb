// The registry tables and the builders for shapes and filters (material builders: material/builders.cpp).
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/scene/registry.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "pellucid/geometry/mesh_io.h"
#include "pellucid/material/builders.h"
#include "pellucid/scene/mitsuba_table.h"
#include "pellucid/scene/texture_builder.h"
#include "pellucid/util/error.h"
#include "pellucid/util/suggest.h"

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

std::string unknown_type_message(const std::string& family, const std::string& type,
                                 const std::vector<std::string>& known) {
    // The Mitsuba plugin kind whose names a user of this family may bring from Mitsuba's XML or dicts.
    static const std::map<std::string, std::string> kMitsubaKind = {
        {"material", "bsdf"}, {"shape", "shape"}, {"texture", "texture"}, {"light", "emitter"}, {"filter", "rfilter"}};
    std::string hint;
    auto kind = kMitsubaKind.find(family);
    const MitsubaPlugin* m = kind == kMitsubaKind.end() ? nullptr : find_mitsuba_plugin(kind->second, type);
    if (m && *m->ours && type != m->ours) {
        if (std::find(known.begin(), known.end(), m->ours) != known.end())
            hint = "Mitsuba's '" + type + "' is '" + m->ours + "' here; ";
        else if (family == "material")  // bumpmap, normalmap: a key of the material they wrap
            hint = "Mitsuba's '" + type + "' is the material key '" + std::string(m->ours) + "' here; ";
    }
    if (hint.empty()) {
        hint = did_you_mean(type, known);
        if (!hint.empty()) hint += " ";
    }
    return "unknown " + family + " type '" + type + "' (" + hint + "known: " + join_names(known) + ")";
}

namespace {
// ---- shapes -------------------------------------------------------------------------------------
// Mitsuba's `flip_normals` (every Mitsuba shape has it): applied in object space.
void read_flip_normals(Properties& p, TriangleMesh& m) {
    if (p.get_bool("flip_normals", false)) m.flip_normals();
}

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
    read_flip_normals(p, g.mesh);
    return g;
}
// Meshes from files (geometry/mesh_io.h). An OBJ's `usemtl` names become per-face materials: the
// builder keeps the names (renamed by the optional `materials` object) and scene/build.cpp maps
// them to scene materials. `usemtl: false` ignores them (the Mitsuba importer sets it: Mitsuba
// ignores usemtl).
ShapeGeometry build_mesh_file(Properties& p, const BuildContext& ctx, bool obj) {
    ShapeGeometry g;
    MeshLoadOptions o;
    std::string file = ctx.resolve(p.get_string("filename"));
    o.face_normals = p.get_bool("face_normals", false);
    o.smooth_normals = p.get_bool("smooth_normals", false);
    if (obj) o.flip_tex_coords = p.get_bool("flip_tex_coords", false);
    const bool usemtl = obj && p.get_bool("usemtl", true);
    const Node* renames = obj ? p.get_node("materials") : nullptr;
    if (renames && !usemtl) p.fail("materials", "renames usemtl names, but 'usemtl' is false");
    try {
        if (obj) {
            ObjMesh m = load_obj(file, o);
            g.mesh = std::move(m.mesh);
            if (usemtl) {
                g.face_material_names = std::move(m.material_names);
                g.face_material = std::move(m.face_material);
            }
        } else {
            g.mesh = load_ply(file, o);
        }
    } catch (const Error& e) {
        p.fail("filename", e.what());
    }
    if (renames) {
        if (!renames->is_object())
            p.fail("materials", std::string("expected an object {\"usemtl name\": \"material id\"}, got a ") +
                                    renames->kind_name());
        for (const auto& [name, target] : renames->members()) {
            const std::string key = path_join("materials", name);
            if (!target.is_string()) p.fail(key, std::string("expected a material id (string), got a ") + target.kind_name());
            const auto& names = g.face_material_names;
            if (std::find(names.begin(), names.end(), name) == names.end())
                p.fail(key, "mesh '" + p.get_string("filename") + "' has no usemtl '" + name + "' (its names: " +
                                (names.empty() ? std::string("none") : join_names(names)) + ")");
            g.material_renames.emplace_back(name, target.as_string());
        }
    }
    read_flip_normals(p, g.mesh);
    return g;
}
ShapeGeometry build_obj(Properties& p, const BuildContext& ctx) { return build_mesh_file(p, ctx, true); }
ShapeGeometry build_ply(Properties& p, const BuildContext& ctx) { return build_mesh_file(p, ctx, false); }
ShapeGeometry build_rectangle(Properties& p, const BuildContext&) {
    ShapeGeometry g;
    g.mesh = TriangleMesh::rectangle();
    read_flip_normals(p, g.mesh);
    return g;
}
ShapeGeometry build_cube(Properties& p, const BuildContext&) {
    ShapeGeometry g;
    g.mesh = TriangleMesh::cube();
    read_flip_normals(p, g.mesh);
    return g;
}
// Mitsuba's `disk`: the unit disk in the z = 0 plane, normal +z, triangulated as a fan of
// kDiskSegments triangles. The rim vertices sit at radius R = sqrt(2π / (N sin(2π/N))), so the
// N-gon's area (N/2)·R²·sin(2π/N) is exactly π, the disk's: emitted power and the area pdf of a
// disk emitter match the analytic disk (the rim deviates from the circle by at most
// (R − R·cos(π/N)) ≈ 2e-4 at N = 128). uv = (r, φ/2π) as Mitsuba's disk, with a separate centre
// vertex per triangle so that v interpolates without a seam.
constexpr int kDiskSegments = 128;
ShapeGeometry build_disk(Properties& p, const BuildContext&) {
    ShapeGeometry g;
    const double kTwoPi = 6.283185307179586, n = kDiskSegments;
    const float R = float(std::sqrt(kTwoPi / (n * std::sin(kTwoPi / n))));
    const bool flip = p.get_bool("flip_normals", false);
    const Vec3f normal(0.f, 0.f, flip ? -1.f : 1.f);
    TriangleMesh& m = g.mesh;
    for (int i = 0; i <= kDiskSegments; ++i) {  // rim, with the seam vertex repeated (v = 1)
        double phi = kTwoPi * i / n;
        m.positions.emplace_back(R * float(std::cos(phi)), R * float(std::sin(phi)), 0.f);
        m.normals.push_back(normal);
        m.uvs.emplace_back(1.f, float(i / n));
    }
    for (int i = 0; i < kDiskSegments; ++i) {
        uint32_t c = uint32_t(m.positions.size());
        m.positions.emplace_back(0.f, 0.f, 0.f);
        m.normals.push_back(normal);
        m.uvs.emplace_back(0.f, float((i + 0.5) / n));
        // Counter-clockwise seen from +z faces +z; flip_normals reverses the winding as well.
        if (flip) m.indices.insert(m.indices.end(), {c, uint32_t(i + 1), uint32_t(i)});
        else m.indices.insert(m.indices.end(), {c, uint32_t(i), uint32_t(i + 1)});
    }
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
    return GaussianFilter(s, p.get_bool("shift", false));
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
        {"subsurface", build_subsurface},
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
        {"disk", build_disk},
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
    // Families built inline by scene/build.cpp (keep in step with its "known:" error lists; the
    // Python docs test checks that they agree).
    out["lights"] = {"constant", "directional", "envmap", "point", "spot"};
    out["emitters"] = {"area"};
    out["cameras"] = {"perspective"};
    out["integrators"] = {"aov", "path"};
    out["samplers"] = {"independent", "sobol"};
    out["media"] = {"grid", "homogeneous"};  // medium/medium_builder.cpp
    return out;
}
}  // namespace pellucid
