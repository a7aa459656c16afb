// The path tracer: settings, and the render through the estimator of path_kernel.h on the SIMD
// target the CPU runs best (simd_target.h).
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

#include "pellucid/integrator/aov.h"
#include "pellucid/integrator/simd_target.h"
#include "pellucid/util/error.h"

namespace pellucid {

std::unique_ptr<Integrator> make_integrator(const Scene& scene) {
    if (scene.integrator.type == "path") return std::make_unique<PathIntegrator>(scene.integrator);
    if (scene.integrator.type == "aov")
        return std::make_unique<AovIntegrator>(AovIntegrator::parse(scene.integrator.aov));
    throw Error("integrator.type: unknown integrator '" + scene.integrator.type + "'");
}

RenderResult PathIntegrator::render(const Scene& scene, const RenderOptions& opts) const {
    const PathSetup setup = make_path_setup(scene, m_max_depth, m_s.rr_depth, m_use_nee, m_use_mis, sampler_type(scene, opts));
    const PathTileFn tile = path_tile_function(simd_target());
    return render_loop(scene, opts, [&](const TileJob& job, Film& film) { return tile(setup, job, film); });
}

std::string PathIntegrator::to_string() const {
    return "PathIntegrator[max_depth=" + std::to_string(m_s.max_depth) + ", rr_depth=" +
           std::to_string(m_s.rr_depth) + ", strategy=" + m_s.strategy + "]";
}
}  // namespace pellucid
