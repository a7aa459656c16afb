// Path tracing with NEE and MIS (Veach 1997, ch. 9; the power heuristic, eq. 9.13).
// SPDX-License-Identifier: Apache-2.0
//
// Sample dimensions (sampling/sampler.h). Every path vertex uses the same layout, whichever branches
// run, so that with the sobol sampler a dimension always feeds the same decision and the points of
// that decision stay stratified over a pixel's samples:
//   0, 1                   pixel filter offset (render_tile)
//   vertex v = depth - 1 (0 at the first hit), base b = 2 + 7 v:
//   b                      light selection (NEE)                    1D
//   b + 1, b + 2           point on the light (NEE)                 2D
//   b + 3                  BSDF lobe selection                      1D
//   b + 4, b + 5           BSDF direction                           2D
//   b + 6                  Russian roulette                         1D
// A skipped branch (no NEE on a specular surface, no roulette before rr_depth) leaves its
// dimensions unused. The sampler's Sobol part covers 64 dimensions (8 vertices and most of the
// 9th); later ones draw from the sample's PCG32 stream. The independent sampler ignores set_dimension and consumes
// its stream in call order (the pre-Sampler order, so its images are unchanged).
#include "pellucid/integrator/path.h"

#include <algorithm>

#include "pellucid/integrator/aov.h"
#include "pellucid/sampling/mis.h"
#include "pellucid/util/error.h"

namespace pellucid {

std::unique_ptr<Integrator> make_integrator(const Scene& scene) {
    if (scene.integrator.type == "path") return std::make_unique<PathIntegrator>(scene.integrator);
    if (scene.integrator.type == "aov")
        return std::make_unique<AovIntegrator>(AovIntegrator::parse(scene.integrator.aov));
    throw Error("integrator.type: unknown integrator '" + scene.integrator.type + "'");
}

RenderResult PathIntegrator::render(const Scene& scene, const RenderOptions& opts) const {
    const SamplerType type = sampler_type(scene, opts);
    return render_loop(scene, opts, [&](const TileJob& job, Film& film) {
        return render_tile(scene, job, film, type, [&](const RayDifferential& r, Sampler& u) { return Li(scene, r, u); });
    });
}

std::string PathIntegrator::to_string() const {
    return "PathIntegrator[max_depth=" + std::to_string(m_s.max_depth) + ", rr_depth=" +
           std::to_string(m_s.rr_depth) + ", strategy=" + m_s.strategy + "]";
}

namespace {
constexpr int kVertexDims = 7;  ///< dimensions per path vertex (the layout at the top of this file)
constexpr int kLightSelectDim = 0, kLobeDim = 3, kRouletteDim = 6;

// Light contribution of one area/environment hit found by BSDF sampling, MIS-weighted against the
// light-sampling strategy that could have produced the same direction.
float bsdf_hit_weight(bool use_mis, bool use_nee, bool specular, float bsdf_pdf, float light_pdf) {
    if (specular || !use_nee) return 1.f;
    if (!use_mis) return 0.f;  // "nee": light sampling alone accounts for non-delta directions
    return power_heuristic(bsdf_pdf, light_pdf);
}
}  // namespace

Spectrum PathIntegrator::Li(const Scene& scene, RayDifferential ray, Sampler& sampler) const {
    const bool use_nee = m_use_nee && !scene.lights.empty();
    const bool use_mis = m_use_mis;
    Spectrum L(0.f), beta(1.f);
    bool specular = true;  // the camera ray counts as a delta "bounce"
    float prev_pdf = 0.f, eta_scale = 1.f;
    LightSampleContext prev_ctx;
    SurfaceInteraction si;

    for (int depth = 1;; ++depth) {  // depth = number of path segments, including this ray
        if (!scene.intersect(ray, si)) {
            for (uint32_t li : scene.infinite_lights) {
                InfiniteHit env = infinite_hit(scene.lights[li], prev_ctx, ray.d);
                float lpdf = scene.light_pmf(li) * env.pdf;
                L += beta * env.Le * bsdf_hit_weight(use_mis, use_nee, specular, prev_pdf, lpdf);
            }
            break;
        }
        if (si.light_id >= 0) {
            Spectrum Le = scene.emitted(si);
            if (!Le.is_black()) {
                float lpdf = 0.f;
                if (!specular) {
                    const auto& al = std::get<AreaLight>(scene.lights[size_t(si.light_id)]);
                    lpdf = scene.light_pmf(size_t(si.light_id)) * al.pdf_li(prev_ctx, ray.d, si.p, si.ng);
                }
                L += beta * Le * bsdf_hit_weight(use_mis, use_nee, specular, prev_pdf, lpdf);
            }
        }
        if (m_max_depth >= 0 && depth >= m_max_depth) break;

        // The pixel footprint, for texture filtering and bump steps (and to carry differentials on).
        if (scene.has_textures) scene.compute_footprint(si, ray);
        BSDF bsdf = scene.bsdf(si);
        BxDFFlags flags = bsdf.flags();
        if (flags == BxDFFlags::None) break;
        const Vec3f wo = si.wo;
        LightSampleContext ctx{si.p, si.ng};
        const int dim0 = Sampler::kPixelDims + kVertexDims * (depth - 1);

        // Next-event estimation: one light (uniformly or by power), one point on it.
        if (use_nee && is_non_specular(flags)) {
            sampler.set_dimension(dim0 + kLightSelectDim);
            float u_light = sampler.get_1d();
            Vec2f u = sampler.get_2d();
            float pmf;
            size_t li = scene.sample_light(u_light, &pmf);
            auto ls = std::visit([&](const auto& l) { return l.sample_li(ctx, u); }, scene.lights[li]);
            if (ls && ls->pdf > 0.f) {
                Spectrum f = bsdf.eval(wo, ls->wi);
                if (!f.is_black()) {
                    Ray shadow = ls->infinite ? si.spawn_ray(ls->wi) : si.spawn_ray_to(ls->p_light, ls->n_light, ls->p_error);
                    if (!scene.occluded(shadow)) {
                        float light_pdf = pmf * ls->pdf;
                        float w = (ls->delta || !use_mis) ? 1.f : power_heuristic(light_pdf, bsdf.pdf(wo, ls->wi));
                        L += beta * f * ls->L * (w / light_pdf);
                    }
                }
            }
        }

        // Continue the path by sampling the BSDF.
        sampler.set_dimension(dim0 + kLobeDim);
        float u_lobe = sampler.get_1d();
        Vec2f u = sampler.get_2d();
        auto bs = bsdf.sample(wo, u_lobe, u);
        if (!bs) break;
        beta *= bs->weight;
        prev_pdf = bs->pdf;
        specular = bs->is_specular();
        if (has_flag(bs->lobe, BxDFFlags::Transmission)) eta_scale *= sqr(bs->eta);
        prev_ctx = ctx;
        if (scene.has_textures && specular && ray.has_differentials)
            ray = scene.specular_differentials(si, ray, si.spawn_ray(bs->wi), has_flag(bs->lobe, BxDFFlags::Transmission),
                                               bs->eta);
        else
            ray = RayDifferential(si.spawn_ray(bs->wi));

        // Russian roulette on the throughput with the η² factor removed (pbrt-v4 §13.4.1 / Mitsuba 3
        // path.cpp): survive with q = min(max β·η², 0.95) from rr_depth on.
        if (depth >= m_s.rr_depth) {
            float q = std::min(beta.max_component() * eta_scale, 0.95f);
            sampler.set_dimension(dim0 + kRouletteDim);
            if (!(sampler.get_1d() < q)) break;
            beta /= q;
        }
        if (beta.is_black()) break;
    }
    return L;
}
}  // namespace pellucid
