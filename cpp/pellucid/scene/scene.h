// Scene: the built scene that rendering reads (const Scene&); only parameter updates
// (scene/scene_update.h) change it, in place.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "pellucid/bssrdf/separable.h"
#include "pellucid/bxdf/bsdf.h"
#include "pellucid/camera/perspective.h"
#include "pellucid/geometry/embree_scene.h"
#include "pellucid/geometry/interaction.h"
#include "pellucid/image/filter.h"
#include "pellucid/light/light.h"
#include "pellucid/material/material.h"
#include "pellucid/material/textured.h"
#include "pellucid/medium/medium.h"
#include "pellucid/texture/texture.h"
#include "pellucid/sampling/distribution_1d.h"
#include "pellucid/sampling/sampler.h"
#include "pellucid/scene/scene_desc.h"
#include "pellucid/scene/subsurface_choice.h"

namespace pellucid {

struct ShapeRecord {
    enum class Kind { Mesh, Sphere } kind = Kind::Mesh;
    uint32_t mesh_index = 0;  ///< into Scene::meshes (Kind::Mesh)
    Point3f center{0.f};      ///< Kind::Sphere: world center and radius
    float radius = 1.f;
    /// Kind::Sphere: to_world's linear part divided by its uniform scale (orthogonal; determinant
    /// −1 when to_world mirrors), object space → world. uv, ∂p/∂u, ∂p/∂v and the shading frame
    /// follow the sphere's own parameterisation about its object-space z axis, carried through it.
    Mat3f rotation{1.f};
    bool flip_normals = false;
    uint32_t material = 0;
    std::vector<uint32_t> face_materials;  ///< per triangle (OBJ usemtl); empty = `material` everywhere
    int32_t light = -1;
    std::string name;  ///< key path in the scene description, for messages
    /// Media on the two sides (indices into Scene::media, -1 = none, i.e. vacuum): `interior` on the
    /// side the geometric normal points away from, `exterior` on the side it points to.
    int32_t interior_medium = -1, exterior_medium = -1;
    /// The `null` material: an index-matched boundary with no surface; a path crosses it unchanged
    /// and only its current medium changes (`material` then holds the default material, unused).
    bool null_surface = false;
};

/// Integrator settings (plain data).
struct IntegratorSettings {
    std::string type = "path";
    int max_depth = -1;   ///< longest path in segments (Mitsuba 3 convention), -1 = unbounded
    int rr_depth = 5;     ///< Russian roulette starts at this depth
    std::string strategy = "mis";  ///< "mis", "nee", "bsdf", "direct"
    std::string light_selection = "balanced";  ///< "balanced", "power" or "uniform" (light/light.h)
    std::string aov;  ///< type "aov": "albedo", "normal" or "depth" (integrator/aov.h)
    bool medium_nee = true;  ///< next-event estimation at medium collisions (docs/media.md)
    std::string channel_sampling = "throughput";  ///< which colour channel tracks a medium: "throughput" or "uniform"
    /// Whether the strategy weighs light and BSDF samples by MIS ("mis" and "direct"); the path
    /// tracer and the scene's light selection (nee_under_mis) both ask here.
    bool uses_mis() const { return strategy == "mis" || strategy == "direct"; }
};

class Scene {
public:
    Scene() = default;
    Scene(const Scene&) = delete;
    Scene& operator=(const Scene&) = delete;

    /// Closest hit, filled into si. Thread-safe. with_uv false leaves si.uv (0, 0) on spheres, whose
    /// uv costs an atan2 and an acos (for callers that read no texture: shadow rays through media).
    bool intersect(const Ray& ray, SurfaceInteraction& si, bool with_uv = true) const;
    bool occluded(const Ray& ray) const { return accel.occluded(ray); }
    /// The BSDF at a hit: textures evaluated over the hit's footprint, bump/normal maps applied.
    /// A material with two_sided false seen from the back of the shading normal scatters nothing.
    BSDF bsdf(const SurfaceInteraction& si) const {
        if (has_one_sided && !material_textures[si.material_id].two_sided && !(dot(si.wo, si.shading.n) > 0.f))
            return BSDF::borrowing(&no_scatter_bxdf, si.shading, si.ng);
        if (!has_textures || !needs_textures(si))
            return BSDF::borrowing(&material_bxdfs[si.material_id], si.shading, si.ng);
        return textured_bsdf(si);
    }
    /// Does the hit's material read textures (so that its footprint is needed)?
    bool needs_textures(const SurfaceInteraction& si) const {
        const MaterialTextures& mt = material_textures[si.material_id];
        return mt.has_textured_params() || mt.perturbs_normal();
    }
    /// Set the hit's pixel footprint (dpdx, dpdy, du/dx …): from the ray's differentials when it
    /// carries them, else the camera's approximation (perspective.h approximate_dp_dxy).
    void compute_footprint(SurfaceInteraction& si, const RayDifferential& ray) const;
    /// The differentials of the ray leaving a delta (specular) bounce at si in direction wi, with
    /// relative IOR eta crossed (1 for reflection); pbrt-v3 §10.1.3 (reflection and refraction).
    RayDifferential specular_differentials(const SurfaceInteraction& si, const RayDifferential& in, const Ray& out,
                                           bool transmission, float eta) const;
    /// Emitted radiance at a surface hit toward si.wo (0 if the shape is not an emitter).
    Spectrum emitted(const SurfaceInteraction& si) const;
    /// Probability that next-event estimation picks light i.
    float light_pmf(size_t i) const { return lights.empty() ? 0.f : light_distribution.pmf(i); }
    /// Pick a light for next-event estimation; pmf receives its probability.
    size_t sample_light(float u, float* pmf) const { return light_distribution.sample_discrete(u, pmf); }
    std::string to_string() const;

    EmbreeScene accel;
    std::vector<TriangleMesh> meshes;
    std::vector<ShapeRecord> shapes;
    std::vector<Material> materials;
    std::vector<std::string> material_names;
    /// Each material's BxDF at an untextured hit (every parameter a constant: make_bxdf with
    /// TexEval{}), built once at scene build: parallel to materials. Materials are plain Params
    /// (material.h) and hold no BxDF.
    std::vector<BxDF> material_bxdfs;
    std::vector<MaterialTextures> material_textures;  ///< parallel to materials
    TextureList textures;
    bool has_textures = false;  ///< any material reads textures or perturbs normals
    /// Any material reads its hits' pixel footprints (material_reads_footprint): only then do
    /// camera rays carry differentials, delta bounces carry them on, and hits get footprints.
    bool needs_footprints = false;
    bool has_one_sided = false;  ///< any material has two_sided false
    /// The BxDF of a one-sided material seen from behind: flags None (the path ends), eval 0,
    /// pdf 0, and sample() gives nothing (its weight is 0).
    const BxDF no_scatter_bxdf = SmoothConductor<ConductorFresnel>(ConductorFresnel{}, Spectrum(0.f));
    std::vector<Light> lights;
    std::vector<uint32_t> infinite_lights;  ///< indices into lights
    Distribution1D light_distribution;      ///< light selection (light_selection_weights; nee_under_mis)
    bool nee_lights = true;                 ///< NEE samples some light (false: MIS of constant environments only)
    PerspectiveCamera camera;
    Filter filter = GaussianFilter{};
    bool film_splatting = false;  ///< film.reconstruction "splatting" (image/film.h), else filter sampling
    int width = 256, height = 256;
    int spp = 16;
    uint64_t seed = 0;
    SamplerType sampler = SamplerType::Independent;  ///< sampler.type (sampling/sampler.h)
    IntegratorSettings integrator;
    /// Participating media (medium/medium.h), in the order of the `media` object; shapes and the
    /// camera refer to them by index.
    std::vector<Medium> media;
    int32_t camera_medium = -1;       ///< the medium the camera sits in (-1 = none)
    bool has_null_surfaces = false;   ///< any shape has the `null` material
    /// Does the scene use media or null boundaries (which the path tracer must handle)?
    bool has_media() const { return !media.empty() || has_null_surfaces || camera_medium >= 0; }
    /// Subsurface scattering (docs/subsurface.md): the diffusion BSSRDFs, one per shape rendered
    /// with one, which shape_subsurface (per shape, -1: none) indexes; and each subsurface object's
    /// model choice with its reason (scene/subsurface_choice.h).
    std::vector<SeparableBSSRDF> subsurface;
    std::vector<int32_t> shape_subsurface;
    std::vector<SubsurfaceChoice> subsurface_choices;
    std::string source;
    uint64_t triangle_count = 0;
    /// The description it was built from, which parameter updates edit (scene/scene_update.h; a new
    /// field that depends on the description is carried over in scene_update.cpp's adopt()).
    std::shared_ptr<SceneDesc> desc;
    uint32_t updates = 0;     ///< parameter updates applied
    uint32_t bvh_builds = 0;  ///< times `accel` was built: 1 when loaded, +1 per update that moved geometry

    /// The hit record of a kernel hit (the one place intersect and the path kernel fill it; the
    /// kernel's packet vertices are geometry/hit_lanes.h's, as here). Without with_uv a sphere's uv (an atan2
    /// and an acos) is left 0.
    void fill_hit(const Ray& ray, const RayHit& h, SurfaceInteraction& si, bool with_uv) const;

private:
    BSDF textured_bsdf(const SurfaceInteraction& si) const;
};
}  // namespace pellucid
