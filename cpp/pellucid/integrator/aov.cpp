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

Spectrum AovIntegrator::Li(const Scene& scene, const Ray& ray, PCG32& rng) const {
    SurfaceInteraction si;
    if (!scene.intersect(ray, si)) return Spectrum(0.f);
    switch (m_kind) {
        case Kind::Depth: return Spectrum(si.t);
        case Kind::Normal: return Spectrum(si.shading.n.x, si.shading.n.y, si.shading.n.z);
        case Kind::Albedo: {
            // One-sample estimate of ρ(wo) = ∫ f(wo, wi) |cos θi| dωi: E[weight] = ρ (the BSDF's
            // sample weight is f·|cos θi|/pdf, bxdf/bxdf_types.h).
            BSDF bsdf = scene.bsdf(si);
            float u_lobe = rng.next_float();
            Vec2f u = rng.next_2d();
            auto bs = bsdf.sample(si.wo, u_lobe, u);
            return bs ? bs->weight : Spectrum(0.f);
        }
    }
    return Spectrum(0.f);
}

RenderResult AovIntegrator::render(const Scene& scene, const RenderOptions& opts) const {
    // render_tile() keeps negative values out of the film (they are invalid radiance); normals are
    // signed, so this loop discards only NaN/Inf. Seeding and filtering are render_tile()'s.
    return render_loop(scene, opts, [&](const TileJob& job, Film& film) {
        uint64_t bad = 0;
        const uint64_t width = uint64_t(scene.width);
        for (int y = job.y0; y < job.y1; ++y)
            for (int x = job.x0; x < job.x1; ++x) {
                const uint64_t pixel = uint64_t(y) * width + uint64_t(x);
                for (int s = job.s0; s < job.s1; ++s) {
                    PCG32 rng = PCG32::for_sample(pixel, uint64_t(s), job.seed);
                    Vec2f off = sample_filter(scene.filter, rng.next_2d());
                    Spectrum v = Li(scene, scene.camera.generate_ray(float(x) + 0.5f + off.x, float(y) + 0.5f + off.y), rng);
                    if (!v.is_finite()) {
                        ++bad;
                        continue;
                    }
                    film.add_sample(x, y, v);
                }
            }
        return bad;
    });
}
}  // namespace pellucid
