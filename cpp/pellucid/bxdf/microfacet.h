// Microfacet normal distributions (GGX / Trowbridge–Reitz and Beckmann) with Smith
// masking–shadowing (height-correlated by default, or separable) and exact visible-normal
// sampling. Value types with identical members, used as the `Distribution` template parameter of
// the microfacet BxDFs.
// SPDX-License-Identifier: Apache-2.0
//
// Frame: local shading frame, z = macro normal; microfacet normals wm always have wm.z ≥ 0.
// Measures: D is a density per solid angle of wm with ∫ D(wm) cos θm dωm = 1;
// pdf_visible is a density per solid angle of wm.
// Roughness: alpha_x/alpha_y are the slope-space standard deviations (× √2 for Beckmann, Walter
// et al. 2007 §5.2); alpha_from_roughness(r) = r² maps a perceptual roughness r ∈ [0, 1] to α
// (Burley 2012, §5.4). Every alpha is clamped to ≥ kMinAlpha = 1e-4 on construction (NaN → 1e-4),
// so no expression divides by zero; the BxDFs switch to a delta lobe when effectively_smooth().
// Shadowing: the two-direction term G(wo, wi) is the height-correlated Smith form (default) or the
// separable product G1(wo)·G1(wi) (the form Mitsuba 3 uses); it is part of the distribution value,
// so every BxDF that calls G() follows the choice. G1, Λ and the visible-normal density do not
// depend on it. The separable form ignores the correlation between the heights that mask wo and
// wi, so it shadows more: G1(wo)G1(wi) ≤ 1/(1 + Λ(wo) + Λ(wi)) (Heitz 2014, §6).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "pellucid/math/constants.h"
#include "pellucid/math/lane_exp_log.h"
#include "pellucid/math/lane_types.h"
#include "pellucid/math/spherical.h"
#include "pellucid/math/vec.h"
#include "pellucid/sampling/warp.h"

namespace pellucid {

/// Which two-direction Smith masking–shadowing term G(wo, wi) a distribution evaluates.
enum class SmithShadowing : uint8_t {
    HeightCorrelated,  ///< G2 = 1/(1 + Λ(wo) + Λ(wi)) (Heitz 2014, eq. 99)
    Separable,         ///< G2 = G1(wo)·G1(wi) (Heitz 2014, eq. 98)
};
inline std::string to_string(SmithShadowing s) {
    return s == SmithShadowing::Separable ? "separable" : "height_correlated";
}

namespace microfacet_detail {
constexpr float kMinAlpha = 1e-4f;
/// Below this, BxDFs use the delta (smooth) lobe instead (pbrt-v4's EffectivelySmooth threshold).
constexpr float kSmoothAlpha = 1e-3f;
inline float clamp_alpha(float a) { return a >= kMinAlpha ? a : kMinAlpha; }
/// (αx² x² + αy² y²) / z²  =  α(φ)² tan² θ  (Heitz 2014, eq. 80, written without tan).
inline float alpha2_tan2(const Vec3f& w, float ax, float ay) {
    float num = ax * ax * w.x * w.x + ay * ay * w.y * w.y;
    return num / (w.z * w.z);
}
/// (x²/αx² + y²/αy²) / z²  =  tan² θm (cos² φ/αx² + sin² φ/αy²).
inline float slope2(const Vec3f& wm, float ax, float ay) {
    return (wm.x * wm.x / (ax * ax) + wm.y * wm.y / (ay * ay)) / (wm.z * wm.z);
}

/// G2 from Λ(wo) and Λ(wi): separable G1(wo)·G1(wi) (Heitz 2014, eq. 98) or height-correlated
/// 1/(1 + Λ(wo) + Λ(wi)) (eq. 99), per lane.
template <class F>
inline F smith_g2(const MaskT<F>& separable, const F& lo, const F& li) {
    return lane::select(separable, (F(1.f) / (F(1.f) + lo)) * (F(1.f) / (F(1.f) + li)), F(1.f) / (F(1.f) + lo + li));
}
/// D_wo(wm) = G1(wo)/|cos θo| · D(wm) · (wo·wm) (Heitz 2014, eq. 38) of a lane distribution d, wo
/// flipped into the upper hemisphere; 0 for back-facing microfacets and on the horizon.
template <class F, class Dist>
inline F visible_pdf(const Dist& d, const V3<F>& wo, const V3<F>& wm) {
    const V3<F> w = lane::select(wo.z < F(0.f), -wo, wo);
    const F c = dot(w, wm);
    const auto ok = wo.z != F(0.f) && c > F(0.f);
    return lane::select(ok, d.G1(w) / w.z * d.D(wm) * c, F(0.f));
}

// ---- The transcendental functions of the Beckmann model, over a lane type F ----
// e^x and ln x: math/lane_exp_log.h (the same bits on float and on every packet).
using lane_math::exp2_int;
using lane_math::exp_t;
using lane_math::log_t;

/// The scaled complementary error function e^{x²} erfc(x) for x ≥ 0: t·e^{P(t)}, t = 1/(1 + x/2),
/// the Chebyshev fit of Press et al. 1992, Numerical Recipes in C, 2nd ed., §6.2 (erfcc) without its
/// e^{−x²} factor: fractional error below 1.2e-7 for every x ≥ 0 in exact arithmetic.
template <class F>
inline F erfcx_t(const F& x) {
    const F t = F(1.f) / (F(1.f) + F(0.5f) * x);
    const F p = F(-1.26551223f) +
                t * (F(1.00002368f) +
                     t * (F(0.37409196f) +
                          t * (F(0.09678418f) +
                               t * (F(-0.18628806f) +
                                    t * (F(0.27886807f) +
                                         t * (F(-1.13520398f) + t * (F(1.48851587f) + t * (F(-0.82215223f) + t * F(0.17087277f)))))))));
    return t * exp_t(p);
}
/// erfc(x) = e^{−x²} · e^{x²} erfc(x) for x ≥ 0 (+∞ included).
template <class F>
inline F erfc_t(const F& x) {
    return exp_t(lane::neg(x * x)) * erfcx_t(x);
}
/// erf⁻¹(x) for x ∈ (−1, 1), given q = (1 − x)(1 + x) computed by the caller where it knows it more
/// precisely than from x (e.g. 4u(1 − u) for x = 2u − 1); q is clamped to ≥ 2⁻²⁴, so ±1 give about
/// ±3.9. Giles 2010, "Approximating the erfinv function", GPU Computing Gems, the single-precision
/// branch polynomials in w = −ln q.
template <class F>
inline F erfinv_t(const F& x, const F& q) {
    const F w = lane::neg(log_t(lane::max(q, F(5.96046448e-8f))));
    const F a = w - F(2.5f);
    F p = F(2.81022636e-08f);
    p = F(3.43273939e-07f) + p * a;
    p = F(-3.5233877e-06f) + p * a;
    p = F(-4.39150654e-06f) + p * a;
    p = F(0.00021858087f) + p * a;
    p = F(-0.00125372503f) + p * a;
    p = F(-0.00417768164f) + p * a;
    p = F(0.246640727f) + p * a;
    p = F(1.50140941f) + p * a;
    // The tail branch (|x| > 0.9966) only where some lane needs it: the same bits either way.
    const auto central = w < F(5.f);
    if (lane::all(central)) return p * x;
    const F b = lane::sqrt(w) - F(3.f);
    F r = F(-0.000200214257f);
    r = F(0.000100950558f) + r * b;
    r = F(0.00134934322f) + r * b;
    r = F(-0.00367342844f) + r * b;
    r = F(0.00573950773f) + r * b;
    r = F(-0.0076224613f) + r * b;
    r = F(0.00943887047f) + r * b;
    r = F(1.00167406f) + r * b;
    r = F(2.83297682f) + r * b;
    return lane::select(central, p, r) * x;
}
}  // namespace microfacet_detail

/// Shared members: Smith G from Λ (the same code for both distributions).
template <class Derived>
class MicrofacetBase {
public:
    float alpha_x() const { return m_ax; }
    float alpha_y() const { return m_ay; }
    bool effectively_smooth() const { return std::max(m_ax, m_ay) < microfacet_detail::kSmoothAlpha; }
    /// Perceptual roughness → α: α = r² (Burley 2012, §5.4). r is clamped to [0, 1].
    static float alpha_from_roughness(float r) { return sqr(clamp(r, 0.f, 1.f)); }

    /// Smith monodirectional masking G1(w) = 1/(1 + Λ(w)) (Heitz 2014, eq. 43); 0 on the horizon.
    float G1(const Vec3f& w) const { return 1.f / (1.f + self().lambda(w)); }
    /// Masking–shadowing G2(wo, wi) for reflection or transmission (directions on either side):
    /// height-correlated 1/(1 + Λ(wo) + Λ(wi)) (Heitz 2014, eq. 99) or separable G1(wo)·G1(wi)
    /// (eq. 98), as shadowing() says. Back-facing microfacets (χ⁺) are the caller's test.
    float G(const Vec3f& wo, const Vec3f& wi) const {
        if (m_shadowing == SmithShadowing::Separable) return G1(wo) * G1(wi);
        return 1.f / (1.f + self().lambda(wo) + self().lambda(wi));
    }
    SmithShadowing shadowing() const { return m_shadowing; }
    /// Distribution of visible normals D_wo(wm) = G1(wo)/|cos θo| · D(wm) · |wo·wm|
    /// (Heitz 2014, eq. 38) on the visible set wo·wm > 0 (wo flipped into the upper hemisphere
    /// first), 0 for back-facing microfacets, which sample_visible never returns.
    float pdf_visible(const Vec3f& wo, const Vec3f& wm) const {
        if (wo.z == 0.f) return 0.f;
        Vec3f w = wo.z < 0.f ? -wo : wo;
        float c = dot(w, wm);
        if (!(c > 0.f)) return 0.f;
        return G1(w) / w.z * self().D(wm) * c;
    }

protected:
    MicrofacetBase(float ax, float ay, SmithShadowing s)
        : m_ax(microfacet_detail::clamp_alpha(ax)), m_ay(microfacet_detail::clamp_alpha(ay)), m_shadowing(s) {}
    std::string params() const {
        std::string p = "alpha_x=" + std::to_string(m_ax) + ", alpha_y=" + std::to_string(m_ay);
        return m_shadowing == SmithShadowing::Separable ? p + ", shadowing=separable" : p;
    }
    float m_ax, m_ay;
    SmithShadowing m_shadowing;

private:
    const Derived& self() const { return static_cast<const Derived&>(*this); }
};

/// GGX over a lane type F (simd/lane.h): one αx, αy and shadowing choice per lane. GGX below (the
/// distribution every GGX BxDF holds) is its float instantiation, so the two are one source.
template <class F>
struct GGXT {
    F ax, ay;             ///< clamped to ≥ kMinAlpha by GGX's constructor
    MaskT<F> separable;   ///< SmithShadowing::Separable

    /// D(wm) = 1 / (π αx αy (x²/αx² + y²/αy² + z²)²) for unit wm, z > 0 (Heitz 2014, eq. 85
    /// multiplied out so no tan θ or cos⁴ θ appears).
    F D(const V3<F>& wm) const {
        const F s = wm.x * wm.x / (ax * ax) + wm.y * wm.y / (ay * ay) + wm.z * wm.z;
        return lane::select(wm.z <= F(0.f), F(0.f), F(1.f) / (F(kPi) * ax * ay * s * s));
    }
    /// Λ(w) = (−1 + sqrt(1 + α² tan² θ))/2 (Heitz 2014, eq. 86), with α² tan² θ =
    /// (αx² x² + αy² y²)/z² (eq. 80); +∞ on the horizon.
    F lambda(const V3<F>& w) const {
        const auto horizon = w.z == F(0.f);
        const F num = ax * ax * w.x * w.x + ay * ay * w.y * w.y;
        const F a2t2 = num / lane::select(horizon, F(1.f), w.z * w.z);
        return lane::select(horizon, F(kInfinity), F(0.5f) * (lane::sqrt(F(1.f) + a2t2) - F(1.f)));
    }
    /// Smith G1(w) = 1/(1 + Λ(w)) (Heitz 2014, eq. 43); 0 on the horizon.
    F G1(const V3<F>& w) const { return F(1.f) / (F(1.f) + lambda(w)); }
    /// G2: height-correlated 1/(1 + Λ(wo) + Λ(wi)) (eq. 99) or separable G1(wo)·G1(wi) (eq. 98).
    F G(const V3<F>& wo, const V3<F>& wi) const { return microfacet_detail::smith_g2<F>(separable, lambda(wo), lambda(wi)); }
    /// D_wo(wm) (Heitz 2014, eq. 38; microfacet_detail::visible_pdf).
    F pdf_visible(const V3<F>& wo, const V3<F>& wm) const { return microfacet_detail::visible_pdf<F>(*this, wo, wm); }
    /// Visible normal for wo (flipped into the upper hemisphere), by the spherical-cap method of
    /// Dupuy & Benyoub 2023, "Sampling Visible GGX Normals with Spherical Caps", HPG, Listing 3,
    /// inside the stretch/unstretch of Heitz 2018, JCGT 7(4), §3. cos/sin of φ = 2π u.x come from
    /// detail::sincos_two_pi (warp.h), the same on every lane type.
    V3<F> sample_visible(const V3<F>& wo, const V2<F>& u) const {
        const V3<F> w = lane::select(wo.z < F(0.f), -wo, wo);
        const V3<F> wh = normalize(V3<F>(ax * w.x, ay * w.y, w.z));
        F cphi, sphi;
        detail::sincos_two_pi<F>(u.x, &cphi, &sphi);
        const F z = (F(1.f) - u.y) * (F(1.f) + wh.z) - wh.z;
        const F st = lane::sqrt(lane::max(F(0.f), F(1.f) - z * z));
        const V3<F> h = V3<F>(st * cphi, st * sphi, z) + wh;
        return normalize(V3<F>(ax * h.x, ay * h.y, lane::max(F(0.f), h.z)));
    }
};

/// Trowbridge–Reitz / GGX distribution (Walter et al. 2007, eq. 33; anisotropic form Heitz 2014,
/// eq. 85): GGXT<float> behind the MicrofacetBase interface.
class GGX : public MicrofacetBase<GGX> {
public:
    explicit GGX(float alpha = 0.1f) : MicrofacetBase(alpha, alpha, SmithShadowing::HeightCorrelated) {}
    GGX(float alpha_x, float alpha_y, SmithShadowing s = SmithShadowing::HeightCorrelated)
        : MicrofacetBase(alpha_x, alpha_y, s) {}

    float D(const Vec3f& wm) const { return lanes().D(wm); }
    float lambda(const Vec3f& w) const { return lanes().lambda(w); }
    Vec3f sample_visible(const Vec3f& wo, const Vec2f& u) const { return lanes().sample_visible(wo, u); }
    /// The parameters as the lane form takes them.
    GGXT<float> lanes() const { return {m_ax, m_ay, m_shadowing == SmithShadowing::Separable}; }
    std::string to_string() const { return "GGX[" + params() + "]"; }
};

/// Beckmann over a lane type F (simd/lane.h): one αx, αy and shadowing choice per lane. Beckmann
/// below (the distribution every Beckmann BxDF holds) is its float instantiation, so the two are one
/// source. Its exp, log, erfc and erf⁻¹ are microfacet_detail's, the same bits on every lane type.
template <class F>
struct BeckmannT {
    F ax, ay;             ///< clamped to ≥ kMinAlpha by Beckmann's constructor
    MaskT<F> separable;   ///< SmithShadowing::Separable

    /// D(wm) = exp(−(x²/αx² + y²/αy²)/z²) / (π αx αy z⁴) for unit wm, z > 0: Heitz 2014, eq. 82,
    /// with tan² θm (cos² φm/αx² + sin² φm/αy²) written in wm's coordinates; 0 where the exponential
    /// is (so that z⁴ underflowing to 0 at extreme grazing gives 0, not 0/0).
    F D(const V3<F>& wm) const {
        const auto up = wm.z > F(0.f);
        const F c2 = lane::select(up, wm.z * wm.z, F(1.f));
        const F e = (wm.x * wm.x / (ax * ax) + wm.y * wm.y / (ay * ay)) / c2;
        const F ex = microfacet_detail::exp_t(lane::neg(e));
        const auto on = up && ex > F(0.f);
        return lane::select(on, ex / lane::select(on, F(kPi) * ax * ay * c2 * c2, F(1.f)), F(0.f));
    }
    /// Λ(w) = (erf(a) − 1)/2 + e^{−a²}/(2a√π) with a = 1/(α tan θ) = |z|/√(αx² x² + αy² y²)
    /// (Heitz 2014, eqs. 80 and 83), evaluated as e^{−a²} (1/(a√π) − e^{a²} erfc(a))/2 so that both
    /// terms share the exponential (microfacet_detail::erfcx_t); 0 at normal incidence, +∞ on the
    /// horizon.
    F lambda(const V3<F>& w) const {
        const auto horizon = w.z == F(0.f);
        const F den2 = ax * ax * w.x * w.x + ay * ay * w.y * w.y;
        const auto normal = den2 == F(0.f);
        const F a = lane::abs(w.z) / lane::sqrt(lane::select(normal, F(1.f), den2));
        const F l = F(0.5f) * microfacet_detail::exp_t(lane::neg(a * a)) *
                    (F(0.564189584f) / a - microfacet_detail::erfcx_t(a));  // 1/√π
        return lane::select(horizon, F(kInfinity), lane::select(normal || !(l > F(0.f)), F(0.f), l));
    }
    /// Smith G1(w) = 1/(1 + Λ(w)) (Heitz 2014, eq. 43); 0 on the horizon.
    F G1(const V3<F>& w) const { return F(1.f) / (F(1.f) + lambda(w)); }
    /// G2: height-correlated 1/(1 + Λ(wo) + Λ(wi)) (eq. 99) or separable G1(wo)·G1(wi) (eq. 98).
    F G(const V3<F>& wo, const V3<F>& wi) const { return microfacet_detail::smith_g2<F>(separable, lambda(wo), lambda(wi)); }
    /// D_wo(wm) (Heitz 2014, eq. 38; microfacet_detail::visible_pdf).
    F pdf_visible(const V3<F>& wo, const V3<F>& wm) const { return microfacet_detail::visible_pdf<F>(*this, wo, wm); }

    /// Visible normal for wo (flipped into the upper hemisphere), exactly distributed as
    /// pdf_visible up to float rounding, with a fixed amount of work per lane. Heitz & d'Eon 2014,
    /// "Importance Sampling Microfacet-Based BSDFs using the Distribution of Visible Normals", EGSR,
    /// §4: stretch wo to unit roughness, sample the two slopes of the visible normals there, rotate
    /// them to wo's azimuth and unstretch. For wo at angle θ in the xz-plane the slope x̃ has the
    /// density ∝ (cos θ − x̃ sin θ) e^{−x̃²} on x̃ < cot θ, and ỹ is a unit Gaussian (slope variance ½).
    /// x̃ is found in the erf domain b = erf(x̃) ∈ [−1, c], c = erf(cot θ), as Jakob 2014 ("An Improved
    /// Visible Normal Sampling Routine for the Beckmann Distribution") proposes: there its CDF times
    /// 2/cos θ is G(b) = 1 + b + tan θ e^{−x̃²}/√π, with the smooth derivative G'(b) = 1 − x̃ tan θ.
    /// We solve G(b) = u G(c) from a start of our own: the exact solutions at θ = 0
    /// (b = (1 + c)u − 1) and at θ → 90° (b = c − (1 + c) erf √(−ln u)), blended by sin² θ. One
    /// Halley step in b (cubic convergence; G''(b) = −tan θ (√π/2) e^{x̃²}), kept inside a bisection
    /// bracket, is followed by one Halley step on x̃ itself, where G'(x̃) = (2/√π) e^{−x̃²}(1 − x̃ tan θ)
    /// and G''(x̃) = (2/√π) e^{−x̃²}(−2x̃(1 − x̃ tan θ) − tan θ): the result is the slope, with no
    /// further erf⁻¹. Where that step leaves the bracket's slopes (beyond cot θ, where G' vanishes),
    /// the lanes take a second bracketed step in b instead. In exact arithmetic the two steps leave
    /// 1.7e-8 of the CDF (a blend by 1 − cos θ would need three steps in b); in float the sampled
    /// slopes invert their CDF to within BeckmannMath.SampleVisibleInvertsTheSlopeCdf's bound.
    V3<F> sample_visible(const V3<F>& wo, const V2<F>& u) const {
        using namespace microfacet_detail;
        const V3<F> w = lane::select(wo.z < F(0.f), -wo, wo);
        const V3<F> ws = normalize(V3<F>(ax * w.x, ay * w.y, w.z));
        const F sin_t = lane::sqrt(ws.x * ws.x + ws.y * ws.y);
        const auto tilted = sin_t > F(0.f);
        const F cos_p = lane::select(tilted, ws.x / lane::select(tilted, sin_t, F(1.f)), F(1.f));
        const F sin_p = lane::select(tilted, ws.y / lane::select(tilted, sin_t, F(1.f)), F(0.f));
        const F cos_t = lane::select(ws.z > F(1e-7f), ws.z, F(1e-7f));
        const F tan_t = sin_t / cos_t;
        const F cot_t = cos_t / sin_t;  // +∞ at normal incidence, where c = 1 and the tan θ terms vanish
        const F e_cot = exp_t(lane::neg(cot_t * cot_t));
        const F c = F(1.f) - e_cot * erfcx_t(cot_t);
        const F k = tan_t * F(0.564189584f);  // tan θ/√π
        const F u1 = lane::max(u.x, F(5.96046448e-8f));
        const F target = u1 * (F(1.f) + c + k * e_cot);
        // The start: erf √(−ln u) = 1 − e^{ln u} e^{−ln u} erfc √(−ln u) = 1 − u erfcx(√(−ln u)).
        const F g0 = (F(1.f) + c) * u1 - F(1.f);
        const F g1 = c - (F(1.f) + c) * (F(1.f) - u1 * erfcx_t(lane::sqrt(lane::neg(log_t(u1)))));
        F b = g0 + (sin_t * sin_t) * (g1 - g0);
        F lo(-1.f), hi = c;
        const F half_sqrt_pi_tan = tan_t * F(0.886226925f);  // tan θ √π/2
        F x, ex, v, d;
        // G at b (x = erf⁻¹ b, its e^{−x²}, v = G(b) − target, d = 1 − x tan θ), the bracket narrowed
        // by its sign.
        auto eval = [&]() {
            x = erfinv_t(b, (F(1.f) - b) * (F(1.f) + b));
            ex = exp_t(lane::neg(x * x));
            v = (F(1.f) + b + k * ex) - target;
            d = F(1.f) - x * tan_t;
            const auto above = v > F(0.f);
            lo = lane::select(above, lo, b);
            hi = lane::select(above, b, hi);
        };
        // Halley's step in b, b − 2vG'/(2G'² − vG''), with G'' = −tan θ (√π/2) e^{x²}; times e^{−x²}
        // above and below, so one division; bisection where it leaves the bracket.
        auto step_b = [&]() {
            const F den = F(2.f) * d * d * ex + v * half_sqrt_pi_tan;
            const auto ok = d > F(0.f) && den > F(0.f);
            const F bn = b - F(2.f) * v * d * ex / lane::select(ok, den, F(1.f));
            b = lane::select(ok && bn >= lo && bn <= hi, bn, F(0.5f) * (lo + hi));
        };
        eval();
        step_b();
        eval();
        // Halley's step in x̃, x̃ − 2vG'/(2G'² − vG'') with G' and G'' over their common (2/√π) e^{−x̃²}:
        // x̃ − 2vd/(2 (2/√π) e^{−x̃²} d² + v (2x̃d + tan θ)).
        const F den_x = F(2.f) * F(1.12837917f) * ex * d * d + v * (F(2.f) * x * d + tan_t);
        const auto ok_x = d > F(0.f) && den_x > F(0.f);
        const F xn = x - F(2.f) * v * d / lane::select(ok_x, den_x, F(1.f));
        // G is increasing below cot θ, where its one root lies: a step that ends there, and moves x̃
        // by at most 1 (false for a NaN), is kept.
        const auto in = ok_x && xn < cot_t && lane::abs(xn - x) <= F(1.f);
        F sx = xn;
        if (!lane::all(in)) {  // (rare: the same bits whether or not other lanes take it)
            step_b();
            sx = lane::select(in, xn, erfinv_t(b, (F(1.f) - b) * (F(1.f) + b)));
        }
        const F sy = erfinv_t(F(2.f) * u.y - F(1.f), F(4.f) * u.y * (F(1.f) - u.y));
        const F tx = (cos_p * sx - sin_p * sy) * ax, ty = (sin_p * sx + cos_p * sy) * ay;
        return normalize(V3<F>(lane::neg(tx), lane::neg(ty), F(1.f)));
    }
};

/// Beckmann distribution (Walter et al. 2007, eq. 25; anisotropic form Heitz 2014, eq. 82):
/// BeckmannT<float> behind the MicrofacetBase interface.
class Beckmann : public MicrofacetBase<Beckmann> {
public:
    explicit Beckmann(float alpha = 0.1f) : MicrofacetBase(alpha, alpha, SmithShadowing::HeightCorrelated) {}
    Beckmann(float alpha_x, float alpha_y, SmithShadowing s = SmithShadowing::HeightCorrelated)
        : MicrofacetBase(alpha_x, alpha_y, s) {}

    float D(const Vec3f& wm) const { return lanes().D(wm); }
    float lambda(const Vec3f& w) const { return lanes().lambda(w); }
    Vec3f sample_visible(const Vec3f& wo, const Vec2f& u) const { return lanes().sample_visible(wo, u); }
    /// The parameters as the lane form takes them.
    BeckmannT<float> lanes() const { return {m_ax, m_ay, m_shadowing == SmithShadowing::Separable}; }
    std::string to_string() const { return "Beckmann[" + params() + "]"; }
};

/// Inverse error function in double precision (Giles 2010 initial guess + two Newton steps on libm's
/// erf): the reference the tests hold erfinv_t to.
double erfinv(double x);
}  // namespace pellucid
