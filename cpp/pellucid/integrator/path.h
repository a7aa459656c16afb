// Unidirectional path tracer with next-event estimation and multiple importance sampling.
// SPDX-License-Identifier: Apache-2.0
//
// | parameter | type   | default | meaning                                                              |
// |-----------|--------|---------|----------------------------------------------------------------------|
// | max_depth | int    | -1      | longest path in segments (1 = emitters seen directly, 2 = direct light); -1 = unbounded |
// | rr_depth  | int    | 5       | Russian roulette from this depth on                                  |
// | strategy  | string | "mis"   | "mis": light + BSDF sampling, power heuristic; "nee": light sampling (BSDF sampling only through delta lobes); "bsdf": BSDF sampling only; "direct": one bounce (mis, max_depth 2) |
// | light_selection | string | "balanced" | how NEE picks a light: "balanced" (each light at infinity as often as all finite lights together; finite lights ∝ power), "power" or "uniform" (light/light.h) |
// | medium_nee | bool | true | next-event estimation at collisions in media (docs/media.md) |
// | channel_sampling | string | "throughput" | which colour channel distance sampling in a medium follows: ∝ the path throughput, or "uniform" (1/3 each); either way with the one-sample MIS weight over channels |
// JSON: "integrator": {"type": "path", "max_depth": 8}
#pragma once
#include "pellucid/integrator/integrator.h"
#include "pellucid/scene/scene.h"

namespace pellucid {

class PathIntegrator final : public Integrator {
public:
    explicit PathIntegrator(const IntegratorSettings& s)
        : m_s(s), m_use_nee(s.strategy != "bsdf"), m_use_mis(s.uses_mis()),
          m_max_depth(s.strategy == "direct" ? 2 : s.max_depth) {}
    /// Renders with the estimator of integrator/path_kernel.h on the widest SIMD target the CPU
    /// has (integrator/simd_target.h).
    RenderResult render(const Scene& scene, const RenderOptions& opts) const override;
    std::string to_string() const override;

private:
    IntegratorSettings m_s;
    bool m_use_nee, m_use_mis;
    int m_max_depth;  ///< "direct" = MIS with paths of at most two segments
};
}  // namespace pellucid
