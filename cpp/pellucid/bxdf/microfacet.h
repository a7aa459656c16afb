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
    F G(const V3<F>& wo, const V3<F>& wi) const {
        const F lo = lambda(wo), li = lambda(wi);
        return lane::select(separable, (F(1.f) / (F(1.f) + lo)) * (F(1.f) / (F(1.f) + li)), F(1.f) / (F(1.f) + lo + li));
    }
    /// D_wo(wm) = G1(wo)/|cos θo| · D(wm) · (wo·wm) (Heitz 2014, eq. 38), wo flipped into the upper
    /// hemisphere; 0 for back-facing microfacets and on the horizon.
    F pdf_visible(const V3<F>& wo, const V3<F>& wm) const {
        const V3<F> w = lane::select(wo.z < F(0.f), -wo, wo);
        const F c = dot(w, wm);
        const auto ok = wo.z != F(0.f) && c > F(0.f);
        return lane::select(ok, G1(w) / w.z * D(wm) * c, F(0.f));
    }
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

/// Beckmann distribution (Walter et al. 2007, eq. 25; anisotropic form Heitz 2014, eq. 82).
class Beckmann : public MicrofacetBase<Beckmann> {
public:
    explicit Beckmann(float alpha = 0.1f) : MicrofacetBase(alpha, alpha, SmithShadowing::HeightCorrelated) {}
    Beckmann(float alpha_x, float alpha_y, SmithShadowing s = SmithShadowing::HeightCorrelated)
        : MicrofacetBase(alpha_x, alpha_y, s) {}

    /// D(wm) = exp(−tan² θm (cos² φ/αx² + sin² φ/αy²)) / (π αx αy cos⁴ θm).
    float D(const Vec3f& wm) const {
        if (wm.z <= 0.f) return 0.f;
        float e = microfacet_detail::slope2(wm, m_ax, m_ay);
        float c2 = wm.z * wm.z;
        return std::exp(-e) / (kPi * m_ax * m_ay * c2 * c2);
    }
    /// Λ(w) = (erf(a) − 1)/2 + exp(−a²)/(2a√π), a = 1/(α tan θ) (Heitz 2014, eq. 83), evaluated
    /// exactly in double precision (no rational approximation); +∞ on the horizon.
    float lambda(const Vec3f& w) const;
    /// Exact visible-normal sampling: the marginal slope CDF in the incident plane is inverted by
    /// safeguarded Newton iteration (the approach of Jakob 2014, "An Improved Visible Normal Sampling
    /// Routine for the Beckmann Distribution"; CDF from Heitz & d'Eon 2014, EGSR, §4), the other
    /// slope is Gaussian.
    Vec3f sample_visible(const Vec3f& wo, const Vec2f& u) const;
    std::string to_string() const { return "Beckmann[" + params() + "]"; }
};

/// Inverse error function in double precision (Giles 2010 initial guess + Newton polishing).
double erfinv(double x);
}  // namespace pellucid
