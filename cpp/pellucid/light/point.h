// Delta lights: point, spot (smooth falloff) and directional. They are reached only by light
// sampling (no MIS: a BSDF sample hits them with probability 0). Their sampling is written once
// over a lane type F (point_light_sample, spot_light_sample, directional_light_sample): sample_li
// is the float instantiation, and the packet path tracer runs the same templates on its lanes
// (light/light_table.h).
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
#include "pellucid/math/lane_atan.h"
#include "pellucid/math/lane_types.h"

namespace pellucid {

/// A delta light's sample in kLaneWidth<F> lanes (pdf 1, a delta in direction): where it is valid,
/// the unit direction toward the light and the radiance arriving along −wi.
template <class F>
struct DeltaLightSample {
    MaskT<F> valid;
    V3<F> wi;
    RGB<F> L;
};

/// A point emitter at p_light with radiant intensity I seen from p_ref: radiance I/d², valid where
/// d² > 0. Shared by point and spot lights; their sample_li is the float instantiation.
template <class F>
inline DeltaLightSample<F> point_light_sample(const V3<F>& p_light, const RGB<F>& I, const V3<F>& p_ref) {
    const V3<F> d = p_light - p_ref;
    const F d2 = length2(d);
    DeltaLightSample<F> s;
    s.valid = d2 > F(0.f);
    s.wi = d / lane::sqrt(d2);
    s.L = I / d2;
    return s;
}

/// Mitsuba 3's spot falloff at cos_theta = cos of the angle from the axis: 0 at or beyond the
/// cutoff (cos_theta ≤ cos_cutoff), 1 within the beam, linear in the angle between. The angle is
/// lane_math::acos_t (math/lane_atan.h), so every lane type gives the float instantiation's bits.
template <class F>
inline F spot_falloff(const F& cos_theta, const F& cos_cutoff, const F& cutoff, const F& beam) {
    const auto dark = cos_theta <= cos_cutoff;
    if (lane::all(dark)) return F(0.f);
    const F angle = lane_math::acos_t<F>(cos_theta);
    const F ramp = (cutoff - angle) / (cutoff - beam);
    return lane::select(dark, F(0.f), lane::select(angle <= beam, F(1.f), ramp));
}

/// A point light's sample s made a spot light's on the lanes `where`: the radiance times the
/// falloff toward −wi about the unit axis, valid where that is positive (not where it is ≤ 0).
template <class F>
inline void apply_spot_falloff(DeltaLightSample<F>& s, const MaskT<F>& where, const V3<F>& axis, const F& cos_cutoff,
                               const F& cutoff, const F& beam) {
    const F f = spot_falloff<F>(dot(-s.wi, axis), lane::select(where, cos_cutoff, F(2.f)), cutoff, beam);
    s.L = lane::select(where, s.L * f, s.L);
    s.valid = s.valid && (!where || !(f <= F(0.f)));
}
/// A spot light at p_light shining along the unit axis (apply_spot_falloff on a point light's sample).
template <class F>
inline DeltaLightSample<F> spot_light_sample(const V3<F>& p_light, const V3<F>& axis, const RGB<F>& I,
                                             const F& cos_cutoff, const F& cutoff, const F& beam,
                                             const V3<F>& p_ref) {
    DeltaLightSample<F> s = point_light_sample<F>(p_light, I, p_ref);
    apply_spot_falloff<F>(s, MaskT<F>(true), axis, cos_cutoff, cutoff, beam);
    return s;
}

/// The record sample_li returns for a delta light's valid sample at p_light (p_light unused for a
/// light at infinity); n_light and p_error stay zero, so the shadow ray ends at p_light exactly.
inline std::optional<LightLiSample> delta_light_record(const DeltaLightSample<float>& d, const Point3f& p_light,
                                                       bool infinite) {
    if (!d.valid) return std::nullopt;
    LightLiSample s;
    s.wi = d.wi;
    s.L = d.L;
    s.pdf = 1.f;
    s.p_light = p_light;
    s.infinite = infinite;
    s.delta = true;
    return s;
}

class PointLight {
public:
    PointLight(const Point3f& p, const Spectrum& intensity) : m_p(p), m_I(intensity) {}
    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx, Vec2f) const {
        return delta_light_record(point_light_sample<float>(m_p, m_I, ctx.p), m_p, false);
    }
    float power() const { return 4.f * kPi * m_I.average(); }
    const Point3f& position() const { return m_p; }
    const Spectrum& intensity() const { return m_I; }
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
    float falloff(const Vec3f& w_local) const { return spot_falloff<float>(w_local.z, m_cos_cutoff, m_cutoff, m_beam); }
    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx, Vec2f) const {
        return delta_light_record(
            spot_light_sample<float>(m_p, m_frame.n, m_I, m_cos_cutoff, m_cutoff, m_beam, ctx.p), m_p, false);
    }
    /// Φ = 2π I ∫ falloff(θ) sin θ dθ, exact for the linear ramp: with b = beam, c = cutoff,
    /// ∫_0^b sin θ dθ + ∫_b^c (c − θ)/(c − b) sin θ dθ = 1 − (sin c − sin b)/(c − b)
    /// (→ 1 − cos c as b → c).
    float power() const {
        double b = m_beam, c = m_cutoff;
        double frac = c - b > 1e-6 ? 1.0 - (std::sin(c) - std::sin(b)) / (c - b) : 1.0 - std::cos(c);
        return float(2.0 * M_PI * frac) * m_I.average();
    }
    const Point3f& position() const { return m_p; }
    /// The unit direction the spot shines along.
    const Vec3f& axis() const { return m_frame.n; }
    const Spectrum& intensity() const { return m_I; }
    /// Cutoff and beam angles in radians, and the cosine of the cutoff.
    float cutoff() const { return m_cutoff; }
    float beam() const { return m_beam; }
    float cos_cutoff() const { return m_cos_cutoff; }
    std::string to_string() const { return "SpotLight[position=" + pellucid::to_string(m_p) + ", intensity=" + m_I.to_string() + "]"; }

private:
    Point3f m_p;
    Frame m_frame;
    Spectrum m_I;
    float m_cutoff, m_beam, m_cos_cutoff;
};

/// A directional light travelling along the unit w: the direction toward it is −w everywhere.
template <class F>
inline DeltaLightSample<F> directional_light_sample(const V3<F>& w, const RGB<F>& E) {
    DeltaLightSample<F> s;
    s.valid = MaskT<F>(true);
    s.wi = -w;
    s.L = E;
    return s;
}

class DirectionalLight {
public:
    /// `dir` is the direction the light travels; scene_radius bounds shadow-ray placement.
    DirectionalLight(const Vec3f& dir, const Spectrum& irradiance, float scene_radius)
        : m_w(normalize(dir)), m_E(irradiance), m_radius(scene_radius) {}
    std::optional<LightLiSample> sample_li(const LightSampleContext&, Vec2f) const {
        return delta_light_record(directional_light_sample<float>(m_w, m_E), Point3f(0.f), true);
    }
    float power() const { return kPi * m_radius * m_radius * m_E.average(); }
    /// The unit direction the light travels.
    const Vec3f& direction() const { return m_w; }
    const Spectrum& irradiance() const { return m_E; }
    std::string to_string() const { return "DirectionalLight[direction=" + pellucid::to_string(m_w) + ", irradiance=" + m_E.to_string() + "]"; }

private:
    Vec3f m_w;
    Spectrum m_E;
    float m_radius;
};
}  // namespace pellucid
