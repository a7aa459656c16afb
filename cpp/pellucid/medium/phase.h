// Phase functions: how light scattered inside a medium distributes over directions.
// SPDX-License-Identifier: Apache-2.0
//
// CONVENTIONS (checked by tests/cpp/medium/test_phase.cpp):
//  * Directions are unit vectors in any frame (a phase function depends only on the angle between
//    them). Both point AWAY from the scattering point, as for BxDFs (bxdf/bxdf_types.h): wo toward
//    the previous path vertex (the viewer), wi toward the next vertex / the light.
//  * The scattering angle θ is the angle between the direction of propagation, −wo, and wi:
//    cos θ = −dot(wo, wi). θ = 0 (wi = −wo) is forward scattering, the light goes on unturned.
//  * eval(wo, wi) returns p(wo, wi) in 1/sr. There is no cosine factor, and ∫ p dwi = 1 over the
//    sphere for every wo, so p is its own pdf when sampled exactly (weight = p/pdf = 1).
//  * pdf(wo, wi) is per unit solid angle of wi.
//  * sample(wo, u) draws wi from p by the exact inverse CDF; weight = eval/pdf (1 here). A delta
//    phase function (hg with |g| = 1) has eval() = pdf() = 0, as delta BxDF lobes do: only sample()
//    reaches it, with pdf = 1 (the discrete probability) and delta = true.
//  * p(wo, wi) = p(wi, wo) (reciprocity); every value is finite, never NaN, for g ∈ [−1, 1].
//
// | type        | parameter | type  | default | meaning                                          |
// |-------------|-----------|-------|---------|--------------------------------------------------|
// | `isotropic` |           |       |         | p = 1/4π                                         |
// | `hg`        | g         | float | 0       | mean cosine of θ, in [−1, 1]; > 0 forward        |
// JSON (inside a medium): "phase": {"type": "hg", "g": 0.7}
#pragma once
#include <optional>
#include <string>
#include <variant>

#include "pellucid/math/constants.h"
#include "pellucid/math/frame.h"
#include "pellucid/math/lane_types.h"

namespace pellucid {

/// A sampled direction of kLaneWidth<F> lanes; `valid` marks lanes that hold one.
template <class F>
struct PhaseSampleT {
    MaskT<F> valid;
    V3<F> wi;
    F weight;        ///< p/pdf (1 for exact sampling and for the delta)
    F pdf;           ///< solid-angle density; 1 (discrete probability) for the delta
    MaskT<F> delta;  ///< |g| = 1: wi is the only possible direction
};

/// One sampled direction, as the scalar API returns it.
struct PhaseSample {
    Vec3f wi{0.f};
    float weight = 0.f;
    float pdf = 0.f;
    bool delta = false;
};
inline std::optional<PhaseSample> to_optional(const PhaseSampleT<float>& s) {
    if (!s.valid) return std::nullopt;
    return PhaseSample{s.wi, s.weight, s.pdf, s.delta};
}

/// 1 − cos θ and 1 + cos θ for cos θ = −dot(wo, wi), from the chords: for unit vectors
/// 1 − cos θ = |wi + wo|²/2 and 1 + cos θ = |wi − wo|²/2, which keep their relative precision
/// near θ = 0 and θ = π where 1 ± dot() cancels.
template <class F>
inline void one_minus_plus_cos(const V3<F>& wo, const V3<F>& wi, F* one_minus, F* one_plus) {
    const V3<F> s = wi + wo, d = wi - wo;
    *one_minus = F(0.5f) * dot(s, s);
    *one_plus = F(0.5f) * dot(d, d);
}

/// Henyey–Greenstein density p(θ) = (1 − g²) / (4π (1 + g² − 2g cos θ)^{3/2})  [1/sr]
/// (Henyey & Greenstein 1941, eq. 1), given 1 − cos θ and 1 + cos θ. The denominator's base is
/// written as a sum of non-negative terms, 1 + g² − 2g cos θ = (1 − g)² + 2g (1 − cos θ) for g ≥ 0
/// and (1 + g)² − 2g (1 + cos θ) for g < 0, and 1 − g² = (1 − g)(1 + g), so nothing cancels as
/// |g| → 1 or θ → 0. |g| ≥ 1 (the delta) gives 0.
template <class F>
inline F henyey_greenstein(const F& one_minus_cos, const F& one_plus_cos, const F& g) {
    const F a = F(1.f) - g, b = F(1.f) + g;
    const F base = lane::select(g >= F(0.f), a * a + F(2.f) * g * one_minus_cos, b * b - F(2.f) * g * one_plus_cos);
    const F num = a * b;
    const auto ok = lane::abs(g) < F(1.f) && base > F(0.f);
    const F safe = lane::select(ok, base, F(1.f));
    return lane::select(ok, F(kInv4Pi) * num / (safe * lane::sqrt(safe)), F(0.f));
}
/// p(θ) from cos θ directly (the known-answer form: 4π·p(cos θ = 0) = (1 − g²)/(1 + g²)^{3/2}).
template <class F>
inline F henyey_greenstein(const F& cos_theta, const F& g) {
    return henyey_greenstein<F>(F(1.f) - cos_theta, F(1.f) + cos_theta, g);
}

/// A Henyey–Greenstein sample for u ∈ [0, 1) by the exact inverse of its CDF, returned as
/// 1 − cos θ and 1 + cos θ. The usual form cos θ = (1 + g² − ((1 − g²)/(1 − g + 2gu))²)/(2g)
/// (e.g. pbrt-v3 §15.2.3) cancels for small |g| and divides 0 by 0 at g = 0. With t = 2u − 1,
/// expanding 1 + g² − (1 − g²)²/(1 + g t)² and factoring out 2g gives
///   1 − cos θ = (1 − g)² (1 − t) (2 + g (1 + t)) / (2 (1 + g t)²)
///   1 + cos θ = (1 + g)² (1 + t) (2 − g (1 − t)) / (2 (1 + g t)²)
/// products of non-negative factors, so both keep full relative precision for every g (they give
/// cos θ = t, uniform, at g = 0, and cos θ = ±1 at g = ±1). A lane whose 1 + g t is 0 (|g| = 1,
/// u = 0) gets the delta direction, cos θ = sign(g).
template <class F>
inline void hg_sample(const F& u, const F& g, F* one_minus_cos, F* one_plus_cos) {
    const F t = F(2.f) * u - F(1.f);
    const F den = F(1.f) + g * t;
    const auto ok = den > F(0.f);
    const F d = lane::select(ok, den, F(1.f));
    const F inv = F(1.f) / (F(2.f) * d * d);
    const F a = F(1.f) - g, b = F(1.f) + g;
    F om = lane::max(F(0.f), a * a * (F(1.f) - t) * (F(2.f) + g * (F(1.f) + t)) * inv);
    F op = lane::max(F(0.f), b * b * (F(1.f) + t) * (F(2.f) - g * (F(1.f) - t)) * inv);
    // 1 + g t carries the one cancellation (absolute error ~ε at |g t| → 1), as the same factor in
    // both terms: rescaling them to their exact sum 1 − cos θ + 1 + cos θ = 2 removes it.
    const F sum = om + op;
    const F k = lane::select(sum > F(0.f), F(2.f) / lane::select(sum > F(0.f), sum, F(1.f)), F(1.f));
    om = om * k;
    op = op * k;
    const auto fwd = g >= F(0.f);
    *one_minus_cos = lane::select(ok, lane::min(F(2.f), om), lane::select(fwd, F(0.f), F(2.f)));
    *one_plus_cos = lane::select(ok, lane::min(F(2.f), op), lane::select(fwd, F(2.f), F(0.f)));
}
/// cos θ of hg_sample.
template <class F>
inline F hg_sample_cos_theta(const F& u, const F& g) {
    F om, op;
    hg_sample<F>(u, g, &om, &op);
    return F(0.5f) * (op - om);
}

/// The direction at scattering angle θ (given as 1 − cos θ and 1 + cos θ) to the propagation
/// direction −wo, at azimuth 2π·u; sin θ = sqrt((1 − cos θ)(1 + cos θ)) keeps its precision near
/// θ = 0 and π.
template <class F>
inline V3<F> phase_direction(const V3<F>& wo, const F& one_minus_cos, const F& one_plus_cos, const F& u) {
    const F sin_theta = lane::sqrt(one_minus_cos * one_plus_cos);
    const F cos_theta = F(0.5f) * (one_plus_cos - one_minus_cos);
    const F phi = F(2.f * kPi) * u;
    const FrameT<F> fr = FrameT<F>::from_z(-wo);
    return fr.to_world(V3<F>(sin_theta * lane::cos(phi), sin_theta * lane::sin(phi), cos_theta));
}

/// p = 1/4π.
template <class F>
struct IsotropicPhaseT {
    F eval(const V3<F>&, const V3<F>&) const { return F(kInv4Pi); }
    F pdf(const V3<F>&, const V3<F>&) const { return F(kInv4Pi); }
    /// Uniform on the sphere: cos θ = 1 − 2u.x, φ = 2π u.y.
    PhaseSampleT<F> sample(const V3<F>& wo, const V2<F>& u) const {
        PhaseSampleT<F> s;
        s.wi = phase_direction<F>(wo, F(2.f) * u.x, F(2.f) - F(2.f) * u.x, u.y);
        s.weight = F(1.f);
        s.pdf = F(kInv4Pi);
        s.valid = MaskT<F>(true);
        s.delta = MaskT<F>(false);
        return s;
    }
};

/// Henyey–Greenstein with asymmetry g ∈ [−1, 1] (per lane).
template <class F>
struct HGPhaseT {
    F g;

    F eval(const V3<F>& wo, const V3<F>& wi) const {
        F om, op;
        one_minus_plus_cos<F>(wo, wi, &om, &op);
        return henyey_greenstein<F>(om, op, g);
    }
    F pdf(const V3<F>& wo, const V3<F>& wi) const { return eval(wo, wi); }
    /// cos θ by hg_sample_cos_theta(u.x), φ = 2π u.y; the delta (|g| = 1) returns wi = ∓wo.
    PhaseSampleT<F> sample(const V3<F>& wo, const V2<F>& u) const {
        PhaseSampleT<F> s;
        s.delta = lane::abs(g) >= F(1.f);
        F om, op;
        hg_sample<F>(u.x, g, &om, &op);
        const V3<F> dir = phase_direction<F>(wo, om, op, u.y);
        s.wi = lane::select(s.delta, lane::select(g > F(0.f), -wo, wo), dir);
        const F p = henyey_greenstein<F>(om, op, g);
        s.pdf = lane::select(s.delta, F(1.f), p);
        s.weight = F(1.f);
        s.valid = s.delta || p > F(0.f);
        return s;
    }
};

/// The scalar phase functions behind the PhaseFunction variant (float instantiations).
class IsotropicPhase {
public:
    float eval(const Vec3f& wo, const Vec3f& wi) const { return m_lanes.eval(wo, wi); }
    float pdf(const Vec3f& wo, const Vec3f& wi) const { return m_lanes.pdf(wo, wi); }
    std::optional<PhaseSample> sample(const Vec3f& wo, const Vec2f& u) const { return to_optional(m_lanes.sample(wo, u)); }
    /// Mean cosine of the scattering angle.
    float mean_cosine() const { return 0.f; }
    std::string to_string() const { return "IsotropicPhase[]"; }

private:
    IsotropicPhaseT<float> m_lanes;
};

class HGPhase {
public:
    /// g must lie in [−1, 1] (the scene builder reports other values; here it is clamped).
    explicit HGPhase(float g) : m_lanes{std::max(-1.f, std::min(1.f, g))} {}
    float eval(const Vec3f& wo, const Vec3f& wi) const { return m_lanes.eval(wo, wi); }
    float pdf(const Vec3f& wo, const Vec3f& wi) const { return m_lanes.pdf(wo, wi); }
    std::optional<PhaseSample> sample(const Vec3f& wo, const Vec2f& u) const { return to_optional(m_lanes.sample(wo, u)); }
    float mean_cosine() const { return m_lanes.g; }
    float g() const { return m_lanes.g; }
    std::string to_string() const { return "HGPhase[g=" + std::to_string(m_lanes.g) + "]"; }

private:
    HGPhaseT<float> m_lanes;
};

/// The closed list of phase functions (STYLE.md house rule 4).
using PhaseFunction = std::variant<IsotropicPhase, HGPhase>;

inline float eval(const PhaseFunction& p, const Vec3f& wo, const Vec3f& wi) {
    return std::visit([&](const auto& x) { return x.eval(wo, wi); }, p);
}
inline float pdf(const PhaseFunction& p, const Vec3f& wo, const Vec3f& wi) {
    return std::visit([&](const auto& x) { return x.pdf(wo, wi); }, p);
}
inline std::optional<PhaseSample> sample(const PhaseFunction& p, const Vec3f& wo, const Vec2f& u) {
    return std::visit([&](const auto& x) { return x.sample(wo, u); }, p);
}
inline std::string to_string(const PhaseFunction& p) {
    return std::visit([](const auto& x) { return x.to_string(); }, p);
}
}  // namespace pellucid
