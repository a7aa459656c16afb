// Constant environment: uniform radiance from every direction at infinity.
// SPDX-License-Identifier: Apache-2.0
//
// | parameter | type     | default | meaning                       |
// |-----------|----------|---------|-------------------------------|
// | radiance  | spectrum | 1       | radiance (W·m⁻²·sr⁻¹), ≥ 0    |
// JSON: "lights": [{"type": "constant", "radiance": 1.0}]
#pragma once
#include <optional>
#include <string>

#include "pellucid/light/light_types.h"
#include "pellucid/math/constants.h"
#include "pellucid/sampling/warp.h"

namespace pellucid {

class ConstantLight {
public:
    explicit ConstantLight(const Spectrum& radiance) : m_radiance(radiance) {}
    Spectrum Le(const Vec3f& /*dir*/) const { return m_radiance; }
    const Spectrum& radiance() const { return m_radiance; }
    /// Uniform over the sphere of directions (pdf 1/4π), as the packet path tracer samples it
    /// (light_table.h).
    std::optional<LightLiSample> sample_li(const LightSampleContext&, Vec2f u) const {
        LightLiSample s;
        s.wi = square_to_uniform_sphere_lanes<float>(u);
        s.pdf = kInv4Pi;
        s.L = m_radiance;
        s.infinite = true;
        return s;
    }
    float pdf_li(const LightSampleContext&, const Vec3f&) const { return kInv4Pi; }
    /// Power through a disk of the scene's bounding radius (pbrt-v4 convention).
    float power(float scene_radius) const { return kPi * scene_radius * scene_radius * 4.f * kPi * m_radiance.average(); }
    std::string to_string() const { return "ConstantLight[radiance=" + m_radiance.to_string() + "]"; }

private:
    Spectrum m_radiance;
};
}  // namespace pellucid
