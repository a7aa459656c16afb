// SPDX-License-Identifier: Apache-2.0
#include "pellucid/scene/subsurface_choice.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "pellucid/bssrdf/separable.h"
#include "pellucid/medium/medium_builder.h"
#include "pellucid/scene/properties.h"
#include "pellucid/scene/scene.h"
#include "pellucid/util/error.h"
#include "pellucid/util/log.h"

namespace pellucid {
namespace {

struct ObjectMetrics {
    float thickness = 0.f;  ///< mean chord length 4V/A
    float size = 0.f;       ///< bounding-box diagonal
    float distance = 0.f;   ///< camera to the nearest point of the bounding box
    size_t open_edges = 0;
};

ObjectMetrics object_metrics(const Scene& scene, const ShapeRecord& s) {
    ObjectMetrics m;
    Point3f lo(kInfinity), hi(-kInfinity);
    if (s.kind == ShapeRecord::Kind::Sphere) {
        m.thickness = 4.f * s.radius / 3.f;
        lo = s.center - Vec3f(s.radius);
        hi = s.center + Vec3f(s.radius);
    } else {
        const TriangleMesh& mesh = scene.meshes[s.mesh_index];
        double area = 0.0, volume = 0.0;
        for (size_t t = 0; t < mesh.triangle_count(); ++t) {
            const Point3f& a = mesh.positions[mesh.indices[3 * t]];
            const Point3f& b = mesh.positions[mesh.indices[3 * t + 1]];
            const Point3f& c = mesh.positions[mesh.indices[3 * t + 2]];
            const Vec3f n = cross(b - a, c - a);
            area += 0.5 * double(length(n));
            volume += double(dot(a, cross(b, c))) / 6.0;  // divergence theorem over the closed surface
        }
        for (const Point3f& p : mesh.positions) lo = min(lo, p), hi = max(hi, p);
        m.open_edges = open_edge_count(mesh);
        m.thickness = area > 0.0 ? float(4.0 * std::fabs(volume) / area) : 0.f;
    }
    m.size = length(hi - lo);
    const Point3f o = scene.camera.origin();
    const Point3f nearest = clamp(o, lo, hi);
    m.distance = length(nearest - o);
    return m;
}

std::string fmt(float v) { return format_float(v); }

Material coated_material(const SubsurfaceParams& p, const Spectrum& rd) {
    PlasticParams q;
    for (int c = 0; c < 3; ++c) q.diffuse_reflectance.value[c] = std::min(std::max(rd[c], 0.f), 1.f);
    q.specular_reflectance = Spectrum(1.f);
    q.int_ior = p.boundary.int_ior.value;  // the far field takes the constants
    q.ext_ior = p.boundary.ext_ior.value;
    q.variant = PlasticVariant::Linear;  // ρ(θo) = F(θo) + Kd (1 − F(θo)): the BSSRDF's far field
    Material m = q;
    if (p.rough) {
        RoughPlasticParams r;
        r.microfacet = p.microfacet;
        r.microfacet.alpha_u = p.microfacet.alpha_u.value;
        r.microfacet.alpha_v = p.microfacet.alpha_v.value;
        r.plastic = q;
        r.coat_transmittance = CoatTransmittance::Smooth;
        m = r;
    }
    prepare_material(m);
    return m;
}
}  // namespace

void resolve_subsurface(Scene& scene, const std::string& source) {
    scene.shape_subsurface.assign(scene.shapes.size(), -1);
    std::map<uint32_t, uint32_t> coated_of;  // material -> its coated stand-in
    std::map<uint32_t, int32_t> medium_of;   // material -> its interior medium (random walk)
    for (uint32_t id = 0; id < scene.shapes.size(); ++id) {
        ShapeRecord& s = scene.shapes[id];
        if (s.null_surface) continue;
        const auto* mat = std::get_if<SubsurfaceParams>(&scene.materials[s.material]);
        if (!mat) continue;
        const SubsurfaceParams& p = *mat;
        const float g = p.g.value, eta = relative_eta(p.boundary, TexEval{});
        const std::string where = s.name + " (material '" + scene.material_names[s.material] + "')";
        const ObjectMetrics m = object_metrics(scene, s);
        if (m.open_edges)
            log_warning(format_error(source, s.name, "a subsurface material on a mesh that is not closed (" +
                                                         std::to_string(m.open_edges) +
                                                         " open edges): probe rays and random walks leave through "
                                                         "the opening, and the object loses light there"));
        if (s.interior_medium >= 0)
            throw Error(format_error(source, path_join(s.name, "interior"),
                                     "a shape with a subsurface material has its interior from the material; "
                                     "remove 'interior'"));
        // Only the diffusion models read the interior's textures at each hit; the random walk's
        // medium and the coated stand-in are built once from constants.
        const char* textured = p.from_albedo ? (p.albedo.textured() ? "albedo" : p.mfp.textured() ? "mfp" : nullptr)
                                             : (p.sigma_a.textured() ? "sigma_a" : p.sigma_s.textured() ? "sigma_s" : nullptr);
        if (!textured && p.g.textured()) textured = "g";
        if (textured && (p.model == SubsurfaceModel::RandomWalk || p.model == SubsurfaceModel::Coated))
            throw Error(format_error(source, s.name, "material '" + scene.material_names[s.material] + "': '" +
                                                         textured + "' is a texture, which model '" +
                                                         to_string(p.model) + "' cannot vary over the surface (its " +
                                                         "interior is built once); use 'dipole', 'better_dipole' or "
                                                         "'auto', or give a constant"));
        Spectrum sa, ss;
        subsurface_coefficients(p, TexEval{}, bssrdf::Diffusion::BetterDipole, &sa, &ss);
        SubsurfaceChoice c;
        c.shape = id;
        c.thickness = m.thickness;
        c.footprint = m.distance * scene.camera.pixel_angle();
        float min_albedo = 1.f;
        for (int k = 0; k < 3; ++k) {
            const bssrdf::Profile pr = bssrdf::Profile::make(bssrdf::Diffusion::BetterDipole, sa[k], ss[k], g, eta);
            c.diffusion_length = std::max(c.diffusion_length, pr.diffusion_length());
            c.mean_free_path = std::max(c.mean_free_path, pr.mean_free_path());
            const float sps = ss[k] * (1.f - g), spt = sa[k] + sps;
            min_albedo = std::min(min_albedo, spt > 0.f ? sps / spt : 0.f);
        }
        c.min_albedo = min_albedo;
        // Lengths that make no sense for the object's size (a unit mistake, usually).
        if (m.size > 0.f && (c.mean_free_path > 10.f * m.size || c.mean_free_path < 1e-6f * m.size))
            log_warning(format_error(source, s.name, "the subsurface material's mean free path is " +
                                                         fmt(c.mean_free_path) + " scene units for an object " +
                                                         fmt(m.size) + " across: check the coefficients' units "
                                                         "(sigma_a/sigma_s are per scene unit; scale converts)"));
        const bool scatters = ss.max_component() > 0.f;
        if (textured) {
            c.model = p.model == SubsurfaceModel::Dipole ? SubsurfaceModel::Dipole : SubsurfaceModel::BetterDipole;
            c.reason = p.model == SubsurfaceModel::Auto ? std::string("textured interior ('") + textured +
                                                              "'): only the diffusion models read it at each hit"
                                                        : "as the material asks";
        } else if (!scatters) {
            c.model = SubsurfaceModel::RandomWalk;
            c.reason = "no scattering: an absorbing dielectric";
            log_warning(format_error(source, s.name, "the subsurface material does not scatter (sigma_s = 0): it "
                                                         "renders as an absorbing dielectric"));
        } else if (p.model != SubsurfaceModel::Auto) {
            c.model = p.model;
            c.reason = "as the material asks";
        } else if (m.open_edges == 0 && c.thickness < SubsurfaceThresholds::kThinRatio * c.diffusion_length) {
            c.model = SubsurfaceModel::RandomWalk;
            c.reason = "thin: thickness 4V/A = " + fmt(c.thickness) + " < " + fmt(SubsurfaceThresholds::kThinRatio) +
                       " diffusion lengths (" + fmt(c.diffusion_length) + ")";
        } else if (min_albedo < SubsurfaceThresholds::kLowAlbedo) {
            c.model = SubsurfaceModel::RandomWalk;
            c.reason = "low albedo: reduced albedo " + fmt(min_albedo) + " < " + fmt(SubsurfaceThresholds::kLowAlbedo);
        } else if (c.diffusion_length < SubsurfaceThresholds::kFootprintRatio * c.footprint) {
            c.model = SubsurfaceModel::Coated;
            c.reason = "far: diffusion length " + fmt(c.diffusion_length) + " < " +
                       fmt(SubsurfaceThresholds::kFootprintRatio) + " pixel footprint (" + fmt(c.footprint) + ")";
        } else {
            c.model = SubsurfaceModel::BetterDipole;
            c.reason = "thick: thickness " + fmt(c.thickness) + " >= " + fmt(SubsurfaceThresholds::kThinRatio) +
                       " diffusion lengths (" + fmt(c.diffusion_length) + "), reduced albedo " + fmt(min_albedo);
        }
        switch (c.model) {
            case SubsurfaceModel::Dipole:
            case SubsurfaceModel::BetterDipole: {
                const auto d = c.model == SubsurfaceModel::Dipole ? bssrdf::Diffusion::Dipole : bssrdf::Diffusion::BetterDipole;
                scene.shape_subsurface[id] = int32_t(scene.subsurface.size());
                scene.subsurface.push_back(make_separable_bssrdf(p, TexEval{}, d, id));
                break;
            }
            case SubsurfaceModel::RandomWalk: {
                auto it = medium_of.find(s.material);
                if (it == medium_of.end()) {
                    HomogeneousMedium hm;
                    Spectrum rw_a, rw_s;
                    subsurface_coefficients(p, TexEval{}, bssrdf::Diffusion::BetterDipole, &rw_a, &rw_s);
                    hm.sigma_a = rw_a;
                    hm.sigma_s = rw_s;
                    if (g != 0.f) hm.phase = HGPhase(g);
                    hm.name = "<interior of " + scene.material_names[s.material] + ">";
                    it = medium_of.emplace(s.material, int32_t(scene.media.size())).first;
                    scene.media.push_back(hm);
                }
                s.interior_medium = it->second;
                break;
            }
            case SubsurfaceModel::Coated: {
                auto it = coated_of.find(s.material);
                if (it == coated_of.end()) {
                    const SeparableBSSRDF b = make_separable_bssrdf(p, TexEval{}, bssrdf::Diffusion::BetterDipole, id);
                    it = coated_of.emplace(s.material, uint32_t(scene.materials.size())).first;
                    scene.materials.push_back(coated_material(p, b.total()));
                    scene.material_names.push_back(scene.material_names[s.material] + " <coated>");
                }
                s.material = it->second;
                break;
            }
            case SubsurfaceModel::Auto: break;
        }
        log_info(source + ": " + where + ": subsurface model " + to_string(c.model) + " (" + c.reason + ")");
        scene.subsurface_choices.push_back(std::move(c));
    }
}
}  // namespace pellucid
