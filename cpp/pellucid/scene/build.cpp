// Scene building.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/scene/build.h"

#include <cmath>
#include <map>
#include <set>
#include <type_traits>

#include "pellucid/geometry/mesh_io.h"
#include "pellucid/image/image_io.h"
#include "pellucid/material/builders.h"
#include "pellucid/medium/medium_builder.h"
#include "pellucid/scene/registry.h"
#include "pellucid/scene/texture_builder.h"
#include "pellucid/util/error.h"
#include "pellucid/util/limits.h"
#include "pellucid/util/log.h"

namespace pellucid {
namespace {

constexpr int kMaxResolution = 16384;

class Builder {
public:
    Builder(const SceneDesc& d, Scene& s, const GeometryReuse& reuse)
        : m_desc(d), m_scene(s), m_ctx{d.source, d.base_dir}, m_textures(s.textures, m_ctx), m_reuse(reuse) {
        m_ctx.textures = &m_textures;
        if (reuse.prior)
            for (const ShapeRecord& r : reuse.prior->shapes) m_prior_shapes[r.name] = &r;
    }

    void build() {
        Properties root(m_desc.root, m_desc.source, "");
        build_film(root.get_node("film"));
        build_sampler(root.get_node("sampler"));
        build_integrator(root.get_node("integrator"));
        if (const Node* media = root.get_node("media")) build_media(*media, m_ctx, m_scene.media);  // docs/media.md
        build_camera(root.get_node("camera"));
        if (const Node* t = root.get_node("textures")) m_textures.build_named(*t, "textures");
        build_materials(root.get_node("materials"));
        build_shapes(root.get_node("shapes"));
        build_lights(root.get_node("lights"));  // after shapes: needs the scene bounds and area lights
        root.check_unqueried();
        resolve_subsurface(m_scene, m_desc.source);  // may add media and materials (docs/subsurface.md)
        m_scene.material_textures.resize(m_scene.materials.size());
        for (const Material& m : m_scene.materials) m_scene.material_bxdfs.push_back(make_bxdf(m));
        for (const auto& mt : m_scene.material_textures) {
            m_scene.has_textures = m_scene.has_textures || mt.has_textured_params() || mt.perturbs_normal();
            m_scene.needs_footprints = m_scene.needs_footprints || material_reads_footprint(mt, m_scene.textures);
        }
        for (const auto& mt : m_scene.material_textures) m_scene.has_one_sided = m_scene.has_one_sided || !mt.two_sided;
        if (m_scene.shapes.empty() && m_scene.lights.empty())
            log_warning(m_desc.source + ": the scene has no shapes and no lights; it renders black");
        if (keeps_prior_accel()) return;
        m_scene.accel.commit();
        ++m_scene.bvh_builds;
    }

private:
    [[noreturn]] void fail(const std::string& path, const std::string& msg) const {
        throw Error(format_error(m_desc.source, path, msg));
    }

    void build_film(const Node* n) {
        if (!n) return;
        Properties p(*n, m_desc.source, "film");
        m_scene.width = p.get_int("width", 256);
        m_scene.height = p.get_int("height", 256);
        for (auto [key, v] : {std::pair<const char*, int>{"width", m_scene.width}, {"height", m_scene.height}})
            if (v < 1 || v > kMaxResolution)
                p.fail(key, "resolution " + std::to_string(v) + " is out of range [1, " +
                                std::to_string(kMaxResolution) + "]");
        if (std::string e = film_size_error(m_scene.width, m_scene.height); !e.empty()) p.fail("", e);
        if (const Node* f = p.get_node("filter")) {
            Properties fp(*f, m_desc.source, "film.filter");
            std::string type = fp.type();
            auto it = filter_registry().find(type);
            if (it == filter_registry().end())
                fp.fail("type", "unknown filter '" + type + "' (known: box, gaussian, tent)");
            m_scene.filter = it->second(fp);
            fp.check_unqueried();
        }
        m_scene.film_splatting =
            p.get_choice("reconstruction", "filter_sampling", "reconstruction", {"filter_sampling", "splatting"}) == "splatting";
        p.check_unqueried();
    }

    void build_sampler(const Node* n) {
        if (!n) return;
        Properties p(*n, m_desc.source, "sampler");
        m_scene.sampler = parse_sampler_type(
            p.get_choice("type", "independent", "sampler", {"independent", "sobol"}), "sampler.type");
        m_scene.spp = p.get_int("sample_count", 16);
        if (m_scene.spp < 1 || m_scene.spp > (1 << 24))
            p.fail("sample_count", "value " + std::to_string(m_scene.spp) + " is out of range [1, 16777216]");
        int seed = p.get_int("seed", 0);
        if (seed < 0) p.fail("seed", "value " + std::to_string(seed) + " must be >= 0");
        m_scene.seed = uint64_t(seed);
        p.check_unqueried();
    }

    void build_integrator(const Node* n) {
        if (!n) return;
        Properties p(*n, m_desc.source, "integrator");
        IntegratorSettings& s = m_scene.integrator;
        s.type = p.type();
        if (s.type == "aov") {  // integrator/aov.h
            s.aov = p.get_string("aov");
            if (s.aov != "albedo" && s.aov != "normal" && s.aov != "depth")
                p.fail("aov", "unknown aov '" + s.aov + "' (known: albedo, depth, normal)");
            p.check_unqueried();
            return;
        }
        if (s.type != "path") p.fail("type", "unknown integrator '" + s.type + "' (known: aov, path)");
        s.max_depth = p.get_int("max_depth", -1);
        if (s.max_depth < -1) p.fail("max_depth", "value " + std::to_string(s.max_depth) + " must be >= -1");
        s.rr_depth = p.get_int("rr_depth", 5);
        if (s.rr_depth < 1) p.fail("rr_depth", "value " + std::to_string(s.rr_depth) + " must be >= 1");
        s.strategy = p.get_string("strategy", "mis");
        if (s.strategy != "mis" && s.strategy != "nee" && s.strategy != "bsdf" && s.strategy != "direct")
            p.fail("strategy", "unknown strategy '" + s.strategy + "' (known: bsdf, direct, mis, nee)");
        s.light_selection = p.get_string("light_selection", "balanced");
        if (s.light_selection != "balanced" && s.light_selection != "power" && s.light_selection != "uniform")
            p.fail("light_selection",
                   "unknown light selection '" + s.light_selection + "' (known: balanced, power, uniform)");
        s.medium_nee = p.get_bool("medium_nee", true);
        s.channel_sampling = p.get_string("channel_sampling", "throughput");
        if (s.channel_sampling != "throughput" && s.channel_sampling != "uniform")
            p.fail("channel_sampling",
                   "unknown channel sampling '" + s.channel_sampling + "' (known: throughput, uniform)");
        p.check_unqueried();
    }

    void build_camera(const Node* n) {
        Transform to_world;
        float fov = 45.f;
        std::string axis = "x";
        if (n) {
            Properties p(*n, m_desc.source, "camera");
            std::string type = p.type();
            if (type != "perspective") p.fail("type", "unknown camera '" + type + "' (known: perspective)");
            fov = p.get_float("fov", 45.f);
            if (!(fov > 0.f && fov < 180.f)) p.fail("fov", "value " + std::to_string(fov) + " must be in (0, 180)");
            axis = p.get_string("fov_axis", "x");
            to_world = p.get_transform("to_world");
            const Point3f o = to_world.point(Point3f(0.f));
            if (!within_coordinate_limit(o.x, o.y, o.z))
                p.fail("to_world", "the camera position " + point_text(o.x, o.y, o.z) +
                                       " is beyond the coordinate limit of 1e18 scene units");
            if (axis != "x" && axis != "y" && axis != "smaller" && axis != "larger")
                p.fail("fov_axis", "unknown axis '" + axis + "' (known: x, y, smaller, larger)");
            m_scene.camera_medium = resolve_medium(p, "medium", m_scene.media);
            p.check_unqueried();
        }
        float w = float(m_scene.width), h = float(m_scene.height);
        bool along_y = axis == "y" || (axis == "smaller" && h < w) || (axis == "larger" && h > w);
        float fov_x = fov;
        if (along_y) fov_x = degrees(2.f * std::atan(std::tan(radians(fov) * 0.5f) * w / h));
        m_scene.camera = PerspectiveCamera(to_world, fov_x, m_scene.width, m_scene.height);
    }

    uint32_t add_material(const Node& n, const std::string& path, const std::string& name) {
        MaterialTextures mt;
        m_ctx.material_textures = &mt;
        Material m = build_material(n, m_ctx, path);
        m_ctx.material_textures = nullptr;
        m_scene.material_textures.resize(m_scene.materials.size());
        m_scene.material_textures.push_back(mt);
        m_scene.materials.push_back(std::move(m));
        m_scene.material_names.push_back(name);
        return uint32_t(m_scene.materials.size() - 1);
    }

    void build_materials(const Node* n) {
        if (!n) return;
        if (!n->is_object()) fail("materials", std::string("expected an object of named materials, got a ") + n->kind_name());
        for (const auto& [name, m] : n->members()) {
            if (is_null_material(m)) {  // no surface: bounds media only (docs/media.md)
                check_null_material(m, path_join("materials", name));
                m_null_materials.insert(name);
                continue;
            }
            m_materials[name] = add_material(m, path_join("materials", name), name);
        }
    }

    void check_null_material(const Node& n, const std::string& path) const {
        Properties q(n, m_desc.source, path);
        q.type();
        q.check_unqueried();  // the null material takes no parameters
    }

    uint32_t resolve_material(Properties& p, const std::string& path, bool* null_surface) {
        const Node* m = p.get_node("material");
        *null_surface = m && ((m->is_string() && m_null_materials.count(m->as_string())) || is_null_material(*m));
        if (*null_surface && m->is_object()) check_null_material(*m, path_join(path, "material"));
        if (!m || *null_surface) {
            if (m_default_material < 0) {
                m_scene.materials.push_back(LambertianParams{});
                m_scene.material_names.push_back("<default>");
                m_default_material = int(m_scene.materials.size() - 1);
            }
            return uint32_t(m_default_material);
        }
        if (m->is_string()) {
            auto it = m_materials.find(m->as_string());
            if (it == m_materials.end()) p.fail("material", "no material '" + m->as_string() + "'");
            return it->second;
        }
        return add_material(*m, path_join(path, "material"), path_join(path, "material"));
    }

    void build_shapes(const Node* n) {
        if (!n) return;
        if (!n->is_array()) fail("shapes", std::string("expected an array, got a ") + n->kind_name());
        for (size_t i = 0; i < n->size(); ++i) build_shape(n->items()[i], path_index("shapes", i));
    }

    void build_shape(const Node& n, const std::string& path) {
        Properties p(n, m_desc.source, path);
        std::string type = p.type();
        auto it = shape_registry().find(type);
        if (it == shape_registry().end()) {
            std::vector<std::string> names;
            for (const auto& [k, v] : shape_registry()) names.push_back(k);
            p.fail("type", unknown_type_message("shape", type, names));
        }
        if (const ShapeRecord* old = reusable_shape(path)) return reuse_shape(p, path, type, *old);
        ShapeGeometry g = it->second(p, m_ctx);
        Transform to_world = p.get_transform("to_world");
        ShapeRecord rec;
        rec.name = path;
        const bool has_material = p.has("material");
        rec.material = resolve_material(p, path, &rec.null_surface);
        rec.interior_medium = resolve_medium(p, "interior", m_scene.media);
        rec.exterior_medium = resolve_medium(p, "exterior", m_scene.media);
        const Node* emitter = p.get_node("emitter");
        p.check_unqueried();
        if (g.is_sphere) {
            to_sphere(g, to_world, p, rec);
            rec.kind = ShapeRecord::Kind::Sphere;
            rec.center = g.center;
            rec.radius = g.radius;
            rec.flip_normals = g.flip_normals;
        } else {
            g.mesh.transform(to_world);
            g.mesh.validate(format_error(m_desc.source, path, ""));
            size_t removed = g.mesh.remove_degenerate(&g.face_material);
            if (removed)
                log_warning(format_error(m_desc.source, path, "skipped " + std::to_string(removed) +
                                                                 " zero-area triangle(s)"));
            if (g.mesh.triangle_count() == 0) {
                log_warning(format_error(m_desc.source, path, "mesh has no triangles left; shape skipped"));
                return;
            }
            rec.kind = ShapeRecord::Kind::Mesh;
            rec.mesh_index = uint32_t(m_scene.meshes.size());
            if (!g.face_material_names.empty()) resolve_face_materials(g, p, has_material, rec);
            // An interior medium needs a closed boundary; a surface with only an exterior medium
            // merely sits in that medium (a wall in fog).
            if (size_t open = rec.interior_medium >= 0 ? open_edge_count(g.mesh) : 0)
                log_warning(format_error(m_desc.source, path, "the mesh has an interior medium but is not closed (" +
                                                                  std::to_string(open) + " edges are not shared by exactly "
                                                                  "two triangles): unless other shapes close the volume, "
                                                                  "paths leave the medium through its open edges"));
        }
        if (emitter) rec.light = build_area_light(*emitter, path_join(path, "emitter"), g);
        uint32_t id = g.is_sphere ? m_scene.accel.add_sphere(g.center, g.radius) : m_scene.accel.add_mesh(g.mesh);
        PELLUCID_CHECK(id == m_scene.shapes.size(), "geometry ids must be dense");
        if (!g.is_sphere) {
            g.mesh.precompute_flat();
            m_scene.triangle_count += g.mesh.triangle_count();
            m_scene.meshes.push_back(std::move(g.mesh));
        }
        m_scene.has_null_surfaces = m_scene.has_null_surfaces || rec.null_surface;
        m_scene.shapes.push_back(std::move(rec));
    }

    // Parameter updates (scene_update.cpp): the prior scene's record of an unchanged shape, or null.
    bool keeps_prior_accel() const { return m_reuse.prior && m_reuse.changed.empty(); }
    const ShapeRecord* reusable_shape(const std::string& path) const {
        if (!m_reuse.prior || m_reuse.changed.count(path)) return nullptr;
        auto it = m_prior_shapes.find(path);
        return it == m_prior_shapes.end() ? nullptr : it->second;
    }

    // An unchanged shape in a parameter update: geometry from the prior scene; material, media and
    // emitter built anew. Material ids equal the prior build's (scene_update.cpp builds from scratch
    // when they could move, and builds an OBJ anew when its material changes), so per-face ids stay valid.
    void reuse_shape(Properties& p, const std::string& path, const std::string& type, const ShapeRecord& old) {
        ShapeRecord rec = old;
        rec.light = -1;
        const uint32_t material = resolve_material(p, path, &rec.null_surface);
        if (type != "obj") rec.material = material;
        rec.interior_medium = resolve_medium(p, "interior", m_scene.media);
        rec.exterior_medium = resolve_medium(p, "exterior", m_scene.media);
        const TriangleMesh* mesh =
            old.kind == ShapeRecord::Kind::Mesh ? &m_reuse.prior->meshes[old.mesh_index] : nullptr;
        if (mesh && rec.interior_medium >= 0 && old.interior_medium < 0)
            if (size_t open = open_edge_count(*mesh))
                log_warning(format_error(m_desc.source, path, "the mesh has an interior medium but is not closed (" +
                                                                  std::to_string(open) + " open edges)"));
        if (const Node* emitter = p.get_node("emitter")) {
            ShapeGeometry g;
            g.is_sphere = !mesh;
            if (mesh) g.mesh = *mesh;
            g.center = old.center;
            g.radius = old.radius;
            g.flip_normals = old.flip_normals;
            rec.light = build_area_light(*emitter, path_join(path, "emitter"), g);
        }
        if (!keeps_prior_accel()) {  // the BVH is built anew: the prior geometry goes into it
            uint32_t id = mesh ? m_scene.accel.add_mesh(*mesh) : m_scene.accel.add_sphere(old.center, old.radius);
            PELLUCID_CHECK(id == m_scene.shapes.size(), "geometry ids must be dense");
            if (mesh) {
                rec.mesh_index = uint32_t(m_scene.meshes.size());
                m_scene.triangle_count += mesh->triangle_count();
                m_scene.meshes.push_back(*mesh);
            }
        }
        m_scene.has_null_surfaces = m_scene.has_null_surfaces || rec.null_surface;
        m_scene.shapes.push_back(std::move(rec));
    }

    // Per-face materials of an OBJ (issue #6): each usemtl name maps to the scene material its
    // `materials` rename names, else to the scene material of that id, else to the shape's
    // `material`; with no `material` on the shape an unresolved name that faces use is an error.
    // Faces before any usemtl take the shape's material. The result is one id per triangle, read at
    // hit time (Scene::intersect), or none at all when every face resolves to the same material.
    void resolve_face_materials(const ShapeGeometry& g, Properties& p, bool has_material, ShapeRecord& rec) {
        const std::vector<std::string>& names = g.face_material_names;
        std::vector<bool> used(names.size(), false);
        for (uint32_t f : g.face_material)
            if (f != ObjMesh::kNoMaterial) used[f] = true;
        std::vector<uint32_t> ids(names.size(), rec.material);
        for (size_t i = 0; i < names.size(); ++i) {
            std::string target = names[i];
            bool renamed = false;
            for (const auto& [from, to] : g.material_renames)
                if (from == names[i]) {
                    target = to;
                    renamed = true;
                }
            auto it = m_materials.find(target);
            if (it != m_materials.end()) ids[i] = it->second;
            else if (renamed) p.fail(path_join("materials", names[i]), "no material '" + target + "'");
            else if (!has_material && used[i])
                p.fail("", "mesh '" + p.get_string("filename") + "' face material '" + names[i] +
                               "' is not a scene material (define it under 'materials', rename it with the "
                               "shape's 'materials', or give the shape a 'material')");
        }
        std::vector<uint32_t> per_face(g.face_material.size());
        bool uniform = true;
        for (size_t t = 0; t < per_face.size(); ++t) {
            uint32_t f = g.face_material[t];
            per_face[t] = f == ObjMesh::kNoMaterial ? rec.material : ids[f];
            uniform = uniform && per_face[t] == per_face[0];
        }
        if (uniform) rec.material = per_face.empty() ? rec.material : per_face[0];
        else rec.face_materials = std::move(per_face);
    }

    // A sphere's to_world must be a similarity (rotation or mirror, uniform scale, translation): it
    // maps the center and scales the radius, and its rotation orients the sphere's uv and tangents.
    void to_sphere(ShapeGeometry& g, const Transform& t, Properties& p, ShapeRecord& rec) {
        std::string why;
        const float scale = t.similarity_scale(&why);
        if (!(scale > 0.f))
            p.fail("to_world", "a sphere's transform must be a similarity (rotation, uniform scale and "
                               "translation), but " + why);
        g.center = t.point(g.center);
        g.radius *= scale;
        const Vec3f far = glm::abs(g.center) + Vec3f(g.radius);
        if (!within_coordinate_limit(far.x, far.y, far.z))
            p.fail("to_world", "the sphere (centre " + point_text(g.center.x, g.center.y, g.center.z) + ", radius " + std::to_string(g.radius) +
                                   ") reaches beyond the coordinate limit of 1e18 scene units");
        rec.rotation = Mat3f(t.matrix()) / scale;
    }

    int32_t build_area_light(const Node& n, const std::string& path, const ShapeGeometry& g) {
        Properties p(n, m_desc.source, path);
        std::string type = p.type();
        if (type != "area") p.fail("type", "unknown emitter type '" + type + "' (known: area)");
        Spectrum radiance = p.get_spectrum("radiance", Spectrum(1.f));
        if (radiance.has_negative()) p.fail("radiance", "value " + radiance.to_string() + " must be >= 0");
        bool two_sided = p.get_bool("two_sided", false);
        p.check_unqueried();
        if (radiance.is_black()) {
            log_warning(format_error(m_desc.source, path, "emitter has zero radiance; skipped"));
            return -1;
        }
        if (g.is_sphere) m_scene.lights.emplace_back(AreaLight(g.center, g.radius, g.flip_normals, radiance, two_sided));
        else m_scene.lights.emplace_back(AreaLight(g.mesh, radiance, two_sided));
        return int32_t(m_scene.lights.size() - 1);
    }

    /// A positional light's position must be a valid ray origin for Embree (util/limits.h).
    static void check_position(Properties& p, const Point3f& pos) {
        if (!within_coordinate_limit(pos.x, pos.y, pos.z))
            p.fail(p.has("position") ? "position" : "to_world",
                   "the light position " + point_text(pos.x, pos.y, pos.z) + " is beyond the coordinate limit of 1e18 scene units");
    }

    // Bounding sphere of all geometry, for the power of lights at infinity.
    float scene_radius() const {
        Vec3f lo(kInfinity), hi(-kInfinity);
        for (const auto& m : keeps_prior_accel() ? m_reuse.prior->meshes : m_scene.meshes)
            for (const auto& p : m.positions) {
                lo = glm::min(lo, p);
                hi = glm::max(hi, p);
            }
        for (const auto& sh : m_scene.shapes)
            if (sh.kind == ShapeRecord::Kind::Sphere) {
                lo = glm::min(lo, sh.center - Vec3f(sh.radius));
                hi = glm::max(hi, sh.center + Vec3f(sh.radius));
            }
        return lo.x <= hi.x ? std::max(1e-3f, 0.5f * length(hi - lo)) : 1.f;
    }

    Spectrum non_negative(Properties& p, const char* key) {
        Spectrum v = p.get_spectrum(key, Spectrum(1.f));
        if (v.has_negative()) p.fail(key, "value " + v.to_string() + " must be >= 0");
        return v;
    }

    void build_lights(const Node* n) {
        const float radius = scene_radius();
        if (n) {
            if (!n->is_array()) fail("lights", std::string("expected an array, got a ") + n->kind_name());
            for (size_t i = 0; i < n->size(); ++i) build_light(n->items()[i], path_index("lights", i), radius);
        }
        std::vector<float> w = light_selection_weights(m_scene.lights, m_scene.integrator.light_selection, radius);
        // Under MIS, NEE leaves the lights nee_under_mis excludes to BSDF sampling; without any
        // other light, the paths take no NEE sample at all (Scene::nee_lights).
        if (m_scene.integrator.uses_mis()) {
            m_scene.nee_lights = false;
            for (size_t i = 0; i < w.size(); ++i) {
                if (nee_under_mis(m_scene.lights[i])) m_scene.nee_lights = true;
                else w[i] = 0.f;
            }
        }
        m_scene.light_distribution = Distribution1D(w);
    }

    void build_light(const Node& node, const std::string& path, float radius) {
        Properties p(node, m_desc.source, path);
        std::string type = p.type();
        Light light = ConstantLight(Spectrum(0.f));
        Spectrum value;
        if (type == "constant") {
            value = non_negative(p, "radiance");
            light = ConstantLight(value);
        } else if (type == "point") {
            value = non_negative(p, "intensity");
            Transform t = p.get_transform("to_world");
            Point3f pos = p.has("position") ? p.get_vec3("position") : t.point(Point3f(0.f));
            check_position(p, pos);
            light = PointLight(pos, value);
        } else if (type == "spot") {
            value = non_negative(p, "intensity");
            float cutoff = p.get_float("cutoff_angle", 20.f);
            p.check_range("cutoff_angle", cutoff, 1e-3f, 90.f);
            float beam = p.get_float("beam_width", 0.75f * cutoff);
            p.check_range("beam_width", beam, 0.f, cutoff);
            Transform t = p.get_transform("to_world");
            check_position(p, t.point(Point3f(0.f)));
            light = SpotLight(t.point(Point3f(0.f)), t.vector(Vec3f(0, 0, 1)), value, cutoff, beam);
        } else if (type == "directional") {
            value = non_negative(p, "irradiance");
            Transform t = p.get_transform("to_world");
            Vec3f dir = p.has("direction") ? p.get_vec3("direction") : t.vector(Vec3f(0, 0, 1));
            if (!(length(dir) > 0.f)) p.fail("direction", "must be non-zero");
            light = DirectionalLight(dir, value, radius);
        } else if (type == "envmap") {
            EnvmapLight env = build_envmap(p);
            value = Spectrum(float(env.integral()));
            light = std::move(env);
        } else {
            p.fail("type", unknown_type_message("light", type, registry_types().at("lights")));
        }
        p.check_unqueried();
        if (value.is_black()) {
            log_warning(format_error(m_desc.source, path, "light has zero power; skipped"));
            return;
        }
        bool infinite = std::visit([](const auto& x) {
            return is_infinite_area_light_v<std::decay_t<decltype(x)>>;
        }, light);
        if (infinite) m_scene.infinite_lights.push_back(uint32_t(m_scene.lights.size()));
        m_scene.lights.push_back(std::move(light));
    }

    // A lat-long environment map (light/envmap.h). Every failure names the file and the key path.
    EnvmapLight build_envmap(Properties& p) {
        const std::string name = p.get_string("filename");
        const std::string file = m_ctx.resolve(name);
        float scale = p.get_float("scale", 1.f);
        if (!(scale >= 0.f) || !std::isfinite(scale))
            p.fail("scale", "value " + std::to_string(scale) + " must be finite and >= 0");
        // The map's frame must be rotated (and at most uniformly scaled), so solid angle is preserved.
        const Transform to_world = p.get_transform("to_world");
        std::string why;
        const float s0 = to_world.similarity_scale(&why);
        if (!(s0 > 0.f))
            p.fail("to_world", "an envmap's transform must be a rotation (optionally uniformly scaled), but " + why);
        const Mat3f m(to_world.matrix());
        Image img;
        try {
            img = read_image_file(file);
        } catch (const Error& e) {
            p.fail("filename", e.what());
        }
        if (img.width < 2 || img.height < 3)
            p.fail("filename", file + ": the environment map is " + std::to_string(img.width) + "x" +
                                   std::to_string(img.height) + " pixels; it must be at least 2x3");
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x)
                for (int c = 0; c < 3; ++c) {
                    float v = img.pixel(x, y)[c];
                    if (!std::isfinite(v) || v < 0.f)
                        p.fail("filename", file + ": pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                                               ") has radiance " + std::to_string(v) + "; it must be finite and >= 0");
                }
        return EnvmapLight(img, scale, m / s0, name);
    }

    const SceneDesc& m_desc;
    Scene& m_scene;
    BuildContext m_ctx;
    TextureBuilder m_textures;
    std::map<std::string, uint32_t> m_materials;
    std::set<std::string> m_null_materials;  ///< named `null` materials
    int m_default_material = -1;
    const GeometryReuse& m_reuse;
    std::map<std::string, const ShapeRecord*> m_prior_shapes;
};
}  // namespace

std::unique_ptr<Scene> build_scene(const SceneDesc& desc) {
    auto scene = build_scene(desc, GeometryReuse{});
    scene->desc = std::make_shared<SceneDesc>(desc);
    return scene;
}

std::unique_ptr<Scene> build_scene(SceneDesc&& desc) {
    auto scene = build_scene(desc, GeometryReuse{});
    scene->desc = std::make_shared<SceneDesc>(std::move(desc));
    return scene;
}

std::unique_ptr<Scene> build_scene(const SceneDesc& desc, const GeometryReuse& reuse) {
    auto scene = std::make_unique<Scene>();
    scene->source = desc.source;
    Builder(desc, *scene, reuse).build();
    return scene;
}
}  // namespace pellucid
