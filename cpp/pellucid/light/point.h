// Delta lights: point, spot (smooth falloff) and directional. They are reached only by light
// sampling (no MIS: a BSDF sample hits them with probability 0).
// SPDX-License-Identifier: Apache-2.0
//
//
// `point`: radiant intensity I in every direction; power 4π·I.
// | parameter | type      | default   | meaning                                              |
// |-----------|-----------|-----------|------------------------------------------------------|
// | position  | vec3      | [0, 0, 0] | position (or the origin of to_world)                 |
// | to_world  | transform | identity  | used when position is absent                         |
// | intensity | colour    | 1         | radiant intensity (W·sr⁻¹), ≥ 0; zero skips the light with a warning |
// JSON: "lights": [{"type": "point", "position": [0, 2, 0], "intensity": 10}]
//
// `spot`: a point light shining down +z of to_world, full intensity inside beam_width, a ramp
// linear in angle to zero at cutoff_angle (Mitsuba 3's falloff).
// | parameter    | type      | default        | meaning                                      |
// |--------------|-----------|----------------|----------------------------------------------|
// | to_world     | transform | identity       | position and orientation (e.g. look_at)      |
// | intensity    | colour    | 1              | intensity on the axis (W·sr⁻¹), ≥ 0          |
// | cutoff_angle | float     | 20             | degrees, in [0.001, 90]: no light beyond     |
// | beam_width   | float     | 0.75·cutoff    | degrees, in [0, cutoff_angle]: full intensity within |
// JSON: {"type": "spot", "intensity": 50, "cutoff_angle": 30,
//        "to_world": [{"look_at": {"origin": [0, 4, 0], "target": [0, 0, 0], "up": [0, 0, 1]}}]}
//
// `directional`: parallel light from infinitely far away.
// | parameter  | type      | default    | meaning                                             |
// |------------|-----------|------------|-----------------------------------------------------|
// | direction  | vec3      | [0, 0, 1]  | direction the light travels (or +z of to_world)     |
// | to_world   | transform | identity   | used when direction is absent                       |
// | irradiance | colour    | 1          | irradiance on a surface facing the light (W·m⁻²), ≥ 0 |
// JSON: {"type": "directional", "direction": [0, -1, 0], "irradiance": 3}
// Its power (for light selection) is π r² E over a disk of the scene's bounding radius r.
#pragma once
#include <cmath>
#include <optional>
#include <string>

#include "pellucid/light/light_types.h"
#include "pellucid/math/constants.h"
#include "pellucid/math/frame.h"

namespace pellucid {

/// The light sample of a point emitter at p_light with radiant intensity I seen from ctx
/// (radiance arriving = I/d², a delta in direction): shared by point and spot lights.
inline std::optional<LightLiSample> delta_point_sample(const LightSampleContext& ctx, const Point3f& p_light,
                                                       const Spectrum& I) {
    Vec3f d = p_light - ctx.p;
    float d2 = length2(d);
    if (!(d2 > 0.f)) return std::nullopt;
    LightLiSample s;
    s.wi = d / std::sqrt(d2);
    s.L = I / d2;
    s.pdf = 1.f;
    s.p_light = p_light;
    s.delta = true;
    return s;
}

class PointLight {
public:
    PointLight(const Point3f& p, const Spectrum& intensity) : m_p(p), m_I(intensity) {}
    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx, Vec2f) const {
        return delta_point_sample(ctx, m_p, m_I);
    }
    float power() const { return 4.f * kPi * m_I.average(); }
    std::string to_string() const { return "PointLight[position=" + pellucid::to_string(m_p) + ", intensity=" + m_I.to_string() + "]"; }

private:
    Point3f m_p;
    Spectrum m_I;
};

/// Spot light with Mitsuba 3's falloff: full intensity inside beam_width, then a ramp linear in
/// angle down to zero at cutoff_angle (continuous, so no hard edge).
class SpotLight {
public:
    SpotLight(const Point3f& p, const Vec3f& dir, const Spectrum& intensity, float cutoff_deg, float beam_deg)
        : m_p(p), m_frame(Frame::from_z(normalize(dir))), m_I(intensity),
          m_cutoff(radians(cutoff_deg)), m_beam(radians(beam_deg)), m_cos_cutoff(std::cos(radians(cutoff_deg))) {}
    float falloff(const Vec3f& w_local) const {
        if (w_local.z <= m_cos_cutoff) return 0.f;
        float angle = safe_acos(w_local.z);
        if (angle <= m_beam) return 1.f;
        return (m_cutoff - angle) / (m_cutoff - m_beam);
    }
    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx, Vec2f) const {
        auto s = delta_point_sample(ctx, m_p, m_I);
        if (!s) return s;
        float f = falloff(m_frame.to_local(-s->wi));
        if (f <= 0.f) return std::nullopt;
        s->L *= f;
        return s;
    }
    /// Φ = 2π I ∫ falloff(θ) sin θ dθ, exact for the linear ramp: with b = beam, c = cutoff,
    /// ∫_0^b sin θ dθ + ∫_b^c (c − θ)/(c − b) sin θ dθ = 1 − (sin c − sin b)/(c − b)
    /// (→ 1 − cos c as b → c).
    float power() const {
        double b = m_beam, c = m_cutoff;
        double frac = c - b > 1e-6 ? 1.0 - (std::sin(c) - std::sin(b)) / (c - b) : 1.0 - std::cos(c);
        return float(2.0 * M_PI * frac) * m_I.average();
    }
    std::string to_string() const { return "SpotLight[position=" + pellucid::to_string(m_p) + ", intensity=" + m_I.to_string() + "]"; }

private:
    Point3f m_p;
    Frame m_frame;
    Spectrum m_I;
    float m_cutoff, m_beam, m_cos_cutoff;
};

class DirectionalLight {
public:
    /// `dir` is the direction the light travels; scene_radius bounds shadow-ray placement.
    DirectionalLight(const Vec3f& dir, const Spectrum& irradiance, float scene_radius)
        : m_w(normalize(dir)), m_E(irradiance), m_radius(scene_radius) {}
    std::optional<LightLiSample> sample_li(const LightSampleContext&, Vec2f) const {
        LightLiSample s;
        s.wi = -m_w;
        s.L = m_E;
        s.pdf = 1.f;
        s.infinite = true;
        s.delta = true;
        return s;
    }
    float power() const { return kPi * m_radius * m_radius * m_E.average(); }
    std::string to_string() const { return "DirectionalLight[direction=" + pellucid::to_string(m_w) + ", irradiance=" + m_E.to_string() + "]"; }

private:
    Vec3f m_w;
    Spectrum m_E;
    float m_radius;
};
}  // namespace pellucid
