// AOV integrator (albedo, shading normal, depth).
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/integrator/aov.h"

#include "pellucid/scene/scene.h"
#include "pellucid/util/error.h"

namespace pellucid {

AovIntegrator::Kind AovIntegrator::parse(const std::string& name) {
    if (name == "albedo") return Kind::Albedo;
    if (name == "normal") return Kind::Normal;
    if (name == "depth") return Kind::Depth;
    throw Error("aov: unknown aov '" + name + "' (known: albedo, depth, normal)");
}

const char* AovIntegrator::name(Kind kind) {
    switch (kind) {
        case Kind::Albedo: return "albedo";
        case Kind::Normal: return "normal";
        case Kind::Depth: return "depth";
    }
    return "?";
}

std::string AovIntegrator::to_string() const { return std::string("AovIntegrator[aov=") + name(m_kind) + "]"; }

Spectrum AovIntegrator::Li(const Scene& scene, const RayDifferential& ray, Sampler& sampler) const {
    SurfaceInteraction si;
    if (!scene.intersect(ray, si)) return Spectrum(0.f);
    if (scene.has_textures) scene.compute_footprint(si, ray);  // textured albedo, filtered like renders
    switch (m_kind) {
        case Kind::Depth: return Spectrum(si.t);
        case Kind::Normal: return Spectrum(si.shading.n.x, si.shading.n.y, si.shading.n.z);
        case Kind::Albedo: {
            // One-sample estimate of ρ(wo) = ∫ f(wo, wi) |cos θi| dωi: E[weight] = ρ (the BSDF's
            // sample weight is f·|cos θi|/pdf, bxdf/bxdf_types.h).
            // Dimensions: the pixel offset (0, 1), then the lobe (2) and the direction (3, 4).
            BSDF bsdf = scene.bsdf(si);
            sampler.set_dimension(Sampler::kPixelDims);
            float u_lobe = sampler.get_1d();
            Vec2f u = sampler.get_2d();
            auto bs = bsdf.sample(si.wo, u_lobe, u);
            return bs ? bs->weight : Spectrum(0.f);
        }
    }
    return Spectrum(0.f);
}

RenderResult AovIntegrator::render(const Scene& scene, const RenderOptions& opts) const {
    // Normals are signed: the film takes every finite sample.
    const SamplerType type = sampler_type(scene, opts);
    return render_loop(scene, opts, [&](const TileJob& job, Film& film) {
        return render_tile<SampleValues::Signed>(
            scene, job, film, type, [&](const RayDifferential& r, Sampler& u) { return Li(scene, r, u); });
    });
}
}  // namespace pellucid
