// Unidirectional path tracer with next-event estimation and multiple importance sampling.
// SPDX-License-Identifier: Apache-2.0
//
// | parameter | type   | default | meaning                                                              |
// |-----------|--------|---------|----------------------------------------------------------------------|
// | max_depth | int    | -1      | longest path in segments (1 = emitters seen directly, 2 = direct light); -1 = unbounded |
// | rr_depth  | int    | 5       | Russian roulette from this depth on                                  |
// | strategy  | string | "mis"   | "mis": light + BSDF sampling, power heuristic; "nee": light sampling (BSDF sampling only through delta lobes); "bsdf": BSDF sampling only; "direct": one bounce (mis, max_depth 2) |
// | light_selection | string | "power" | NEE picks a light with probability ∝ its power, or "uniform" |
// | packets   | bool   | true    | trace the rays of 16 paths at a time as one Embree packet; false = one path at a time. The image is the same |
// | lanes     | bool   | true    | render a scene the lane kernel models (flat Lambertian meshes, mesh area lights, any strategy: path_lanes.h) on it, 64 paths shaded per vectorised loop; false = always the general loop above |
// JSON: "integrator": {"type": "path", "max_depth": 8}
#pragma once
#include "pellucid/integrator/integrator.h"
#include "pellucid/scene/scene.h"

namespace pellucid {

class PathIntegrator final : public Integrator {
public:
    explicit PathIntegrator(const IntegratorSettings& s)
        : m_s(s), m_use_nee(s.strategy != "bsdf"), m_use_mis(s.strategy == "mis" || s.strategy == "direct"),
          m_max_depth(s.strategy == "direct" ? 2 : s.max_depth) {}
    RenderResult render(const Scene& scene, const RenderOptions& opts) const override;
    std::string to_string() const override;
    /// Radiance arriving along -ray.d at ray.o (one sample).
    Spectrum Li(const Scene& scene, RayDifferential ray, Sampler& sampler) const;

    /// One path between ray casts: what Li carries from one vertex to the next, so that paths can be
    /// advanced a vertex at a time, many side by side (render_tile_packets in path.cpp).
    struct PathState {
        RayDifferential ray;      ///< the next ray to trace
        Spectrum L{0.f}, beta{1.f};
        bool specular = true;     ///< the last bounce was a delta one (the camera ray counts as one)
        float prev_pdf = 0.f, eta_scale = 1.f;
        LightSampleContext prev_ctx;
        int depth = 1;            ///< segments so far, including `ray`
        bool has_shadow = false;  ///< NEE left `shadow`: add Ld to L unless it is occluded
        Ray shadow;
        Spectrum Ld{0.f};
    };
    /// Advance a path by one vertex, given what its ray hit (hit = false: it escaped): add emission,
    /// prepare NEE (st.shadow, st.Ld), sample the BSDF into st.ray. Returns false when the path ends
    /// (its pending shadow ray, if any, still counts).
    bool vertex(const Scene& scene, PathState& st, bool hit, SurfaceInteraction& si, Sampler& sampler) const;

private:
    IntegratorSettings m_s;
    bool m_use_nee, m_use_mis;
    int m_max_depth;  ///< "direct" = MIS with paths of at most two segments
};
}  // namespace pellucid
