// AOV integrator: renders one arbitrary output variable of the first hit as the RGB image.
// SPDX-License-Identifier: Apache-2.0
//
// | parameter | type   | default  | meaning                                                            |
// |-----------|--------|----------|--------------------------------------------------------------------|
// | aov       | string | required | "albedo": directional albedo at the first hit, one BSDF sample weight f·|cos θi|/pdf per camera sample (its mean converges to ∫ f |cos θi| dωi); 0 on a miss |
// |           |        |          | "normal": the shading normal, world space, components in [−1, 1] stored as-is (not remapped); 0 on a miss |
// |           |        |          | "depth": the distance t along the (unit) camera ray to the first hit, in scene units; 0 on a miss |
// JSON: "integrator": {"type": "aov", "aov": "normal"}
// The per-pixel filter still applies: a pixel is the filter-weighted mean over its samples, so
// normals and depth are averaged across edges (use a small box filter for exact per-pixel values).
// Unlike radiance, normal components may be negative; only NaN/Inf samples are discarded.
#pragma once
#include <string>

#include "pellucid/integrator/integrator.h"
#include "pellucid/sampling/sampler.h"

namespace pellucid {

class AovIntegrator final : public Integrator {
public:
    enum class Kind { Albedo, Normal, Depth };
    explicit AovIntegrator(Kind kind) : m_kind(kind) {}
    /// "albedo" | "normal" | "depth"; anything else throws pellucid::Error naming the known AOVs.
    static Kind parse(const std::string& name);
    static const char* name(Kind kind);

    RenderResult render(const Scene& scene, const RenderOptions& opts) const override;
    std::string to_string() const override;
    /// The AOV value of one camera ray.
    Spectrum Li(const Scene& scene, const RayDifferential& ray, Sampler& sampler) const;

private:
    Kind m_kind;
};
}  // namespace pellucid
