// Delta lights: point, spot (smooth falloff) and directional. They are reached only by light
// sampling (no MIS: a BSDF sample hits them with probability 0).
// SPDX-License-Identifier: Apache-2.0
//
// point       | position [0,0,0] (or to_world) | intensity (W/sr) 1
// spot        | to_world (looks down +z; look_at) | intensity 1 | cutoff_angle 20° | beam_width 0.75·cutoff
// directional | direction [0,0,-1] (or to_world: +z) | irradiance (W/m²) 1
// JSON: "lights": [{"type": "point", "position": [0, 2, 0], "intensity": 10}]
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
    /// Power of the cone with the linear ramp approximated by its mean half-angle.
    float power() const {
        return 2.f * kPi * (1.f - std::cos(0.5f * (m_cutoff + m_beam))) * m_I.average();
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
