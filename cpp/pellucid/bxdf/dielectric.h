// Dielectric interfaces: smooth (delta reflect/refract), rough (Walter et al. 2007), and thin
// (two parallel interfaces, no bending).
// SPDX-License-Identifier: Apache-2.0
//
// `eta` is int_ior / ext_ior; the +z side of the local frame is the exterior. Directions may come
// from either side (wo.z < 0 = inside). Refraction in TransportMode::Radiance scales the throughput
// by 1/η'² with η' = η(wi side)/η(wo side); Importance does not (Veach 1997, §5.2), so in
// Importance mode the smooth interfaces conserve energy exactly (white furnace = 1).
//
// SmoothDielectric ("dielectric"), ThinDielectric ("thin_dielectric"):
// | parameter              | type          | default | meaning                                   |
// |------------------------|---------------|---------|-------------------------------------------|
// | int_ior                | float/string  | "bk7"   | interior IOR (number or ior.h name)       |
// | ext_ior                | float/string  | "air"   | exterior IOR                              |
// | specular_reflectance   | spectrum      | 1       | multiplier on the reflected lobe          |
// | specular_transmittance | spectrum      | 1       | multiplier on the transmitted lobe        |
// JSON: {"type": "dielectric", "int_ior": "water", "ext_ior": "air"}
//
// RoughDielectric<Distribution> ("rough_dielectric"): the above plus
// | distribution           | string        | "ggx"   | "ggx" or "beckmann"                       |
// | alpha, alpha_u, alpha_v| float         | 0.1     | as for rough_conductor                    |
// | shadowing              | string        | "height_correlated" | or "separable" (microfacet.h) |
// | multiple_scattering    | bool          | false   | Kulla–Conty compensation (GGX, height-correlated only) |
// JSON: {"type": "rough_dielectric", "int_ior": 1.5, "distribution": "ggx", "alpha": 0.3}
//
// Kulla–Conty for the dielectric (Kulla & Conty 2017, "Revisiting Physically Based Shading at
// Imageworks", SIGGRAPH course, multiple-scattering section, dielectric slides: one compensation
// lobe per side of the interface, split between reflection and transmission so that the pair
// stays reciprocal). With E_e, E_i the single-scattering R+T albedos seen from the exterior and
// interior (kulla_conty.h tables, Importance mode), Ē_e, Ē_i their averages, and x_e, x_i the
// transmitted fractions of each side's lobe, the lobes' f (eval adds the |cos θi|) are
//   exterior → exterior: (1 − x_e) (1 − E_e(μo)) (1 − E_e(μi)) / (π (1 − Ē_e))
//   exterior → interior:      x_e  (1 − E_e(μo)) (1 − E_i(μi)) / (π (1 − Ē_i))
//   interior → interior: (1 − x_i) (1 − E_i(μo)) (1 − E_i(μi)) / (π (1 − Ē_i))
//   interior → exterior:      x_i  (1 − E_i(μo)) (1 − E_e(μi)) / (π (1 − Ē_e))
// in Importance form (Radiance divides transmission by η'², as the single-scattering lobe).
// Each side's lobe integrates to exactly its missing energy 1 − E(μo), so the white R+T albedo is
// 1 up to the table's error. Reflection lobes are symmetric. Transmission obeys the η² rule
// (f_rad(e→i) = f_imp(i→e), Veach 1997 eq. 5.14) iff
//   x_e (1 − Ē_e) = η² x_i (1 − Ē_i)      (η = int_ior/ext_ior),
// i.e. the two sides exchange energy in the proportion that radiance compression by η² dictates
// (this constraint is our derivation from Veach's adjoint rule; the slides give the per-side
// structure and the need for a reciprocal split, not this particular choice). One degree of freedom remains; we let the
// less dense side L transmit like an average smooth interface, x_L = 1 − F_avg(η_ld) with
// η_ld = max(η, 1/η) (the fraction a diffuse-like lobe refracts, cf. plastic.h), and solve
// x_L (1 − Ē_L) = η_ld² x_D (1 − Ē_D) for the denser side's x_D; should x_D exceed 1 (never for
// η ∈ [1/3, 3], α ≤ 1 with our tables; tested) it is set to 1 and x_L lowered to keep the
// balance. The lobes are sampled by cosine-weighted directions with probability
// 1 − E(μo) (then reflection vs transmission by x), the single-scattering lobe otherwise.
// Model no more than needed: skipped when max(1 − Ē_e, 1 − Ē_i) < 1e-3 (GGX, η = 1.5: α < 0.015;
// test_kulla_conty_dielectric.cpp), as for the conductor. Anisotropic α reads the table at √(αx αy),
// which is approximate: white furnace 0.96–1.00 for αx:αy = 0.8:0.4 (bxdf_cases.h);
// η outside [1/3, 3] reads it at the nearest η (approximate, documented in docs/materials.md).
// Scene-facing rules: material/dielectric.h.
//
// Model no more than needed: an effectively smooth distribution (max α < 1e-3) or an
// index-matched interface (η == 1, where the refraction half vector is undefined and the lobe is a
// pure pass-through) evaluates as SmoothDielectric.
#pragma once
#include <optional>
#include <string>

#include "pellucid/bxdf/bxdf_types.h"
#include "pellucid/bxdf/fresnel.h"
#include "pellucid/bxdf/microfacet.h"
#include "pellucid/math/spherical.h"

namespace pellucid {

/// The smooth dielectric over a lane type F (simd/lane.h): per-lane η, specular reflectance and
/// transmittance. SmoothDielectric (the variant's alternative) is its float instantiation behind the
/// scalar BxDF API; the path tracer's packets use it directly.
template <class F>
struct SmoothDielectricT {
    F eta;
    RGB<F> r, t;

    /// Fresnel-weighted choice between mirror reflection and Snell refraction (TIR → reflection).
    BxDFSampleT<F> sample(const BxDFContext& ctx, const V3<F>& wo, const F& u_lobe, const V2<F>& /*u*/) const {
        const F R = fresnel_dielectric<F>(wo.z, eta), T = F(1.f) - R;
        const F pr = has_flag(ctx.allowed, BxDFFlags::Reflection) ? R : F(0.f);
        const F pt = has_flag(ctx.allowed, BxDFFlags::Transmission) ? T : F(0.f);
        const F sum = pr + pt;
        const auto ok = wo.z != F(0.f) && sum > F(0.f);
        const F sum1 = lane::select(ok, sum, F(1.f));
        const auto reflect = u_lobe < pr / sum1;
        BxDFSampleT<F> s;
        // Mirror reflection.
        const V3<F> wr(lane::neg(wo.x), lane::neg(wo.y), wo.z);
        const F pdf_r = pr / sum1;
        const RGB<F> w_r = r * (R / lane::select(ok, pdf_r, F(1.f)));
        // Refraction.
        F etap;
        V3<F> wt;
        const auto refracts = refract<F>(wo, V3<F>(F(0.f), F(0.f), F(1.f)), eta, &etap, &wt) && wt.z * wo.z < F(0.f);
        const F pdf_t = pt / sum1;
        RGB<F> w_t = t * (T / lane::select(pdf_t > F(0.f), pdf_t, F(1.f)));
        if (ctx.mode == TransportMode::Radiance) w_t = w_t / (etap * etap);
        s.valid = ok && (reflect || refracts);
        s.wi = lane::select(reflect, wr, wt);
        s.pdf = lane::select(reflect, pdf_r, pdf_t);
        s.weight = lane::select(reflect, w_r, w_t);
        s.eta = lane::select(reflect, F(1.f), etap);
        s.lobe = lane::select(lane::int_mask(reflect), IntT<F>(int32_t(BxDFFlags::SpecularReflection)),
                              IntT<F>(int32_t(BxDFFlags::SpecularTransmission)));
        return s;
    }
};

class SmoothDielectric {
public:
    explicit SmoothDielectric(float eta = 1.5046f, const Spectrum& specular_reflectance = Spectrum(1.f),
                              const Spectrum& specular_transmittance = Spectrum(1.f));
    Spectrum eval(const BxDFContext&, const Vec3f&, const Vec3f&) const { return Spectrum(0.f); }
    float pdf(const BxDFContext&, const Vec3f&, const Vec3f&) const { return 0.f; }
    /// Fresnel-weighted choice between mirror reflection and Snell refraction (TIR → reflection).
    std::optional<BxDFSample> sample(const BxDFContext& ctx, const Vec3f& wo, float u_lobe, const Vec2f& u) const;
    BxDFFlags flags() const;
    float eta() const { return m_eta; }
    std::string to_string() const;
    /// The packet form's parameters (SmoothDielectricT<float>).
    SmoothDielectricT<float> lanes() const { return {m_eta, m_r, m_t}; }

private:
    float m_eta;
    Spectrum m_r, m_t;
};

/// The thin slab over a lane type F (simd/lane.h): per-lane η, specular reflectance and
/// transmittance. ThinDielectric (the variant's alternative) is its float instantiation behind the
/// scalar BxDF API; the path tracer's packets use it directly (a delta form: sample only).
template <class F>
struct ThinDielectricT {
    F eta;
    RGB<F> r, t;

    /// Reflection with the slab's summed R', else straight through (wi = −wo) with T' = 1 − R'.
    BxDFSampleT<F> sample(const BxDFContext& ctx, const V3<F>& wo, const F& u_lobe, const V2<F>& /*u*/) const {
        F R = fresnel_dielectric<F>(lane::abs(wo.z), eta), T = F(1.f) - R;
        // Sum over internal bounces (geometric series); R < 1 always since no TIR from outside.
        const auto series = R < F(1.f);
        R = lane::select(series, R + T * T * R / (F(1.f) - R * R), R);
        T = lane::select(series, F(1.f) - R, T);
        const F pr = has_flag(ctx.allowed, BxDFFlags::Reflection) ? R : F(0.f);
        const F pt = has_flag(ctx.allowed, BxDFFlags::Transmission) ? T : F(0.f);
        const F sum = pr + pt;
        const auto reflect = u_lobe < pr / sum;
        BxDFSampleT<F> s;
        s.valid = wo.z != F(0.f) && sum > F(0.f);
        s.wi = lane::select(reflect, V3<F>(lane::neg(wo.x), lane::neg(wo.y), wo.z),
                            V3<F>(lane::neg(wo.x), lane::neg(wo.y), lane::neg(wo.z)));
        s.pdf = lane::select(reflect, pr / sum, pt / sum);
        s.weight = lane::select(reflect, r * (R / s.pdf), t * (T / s.pdf));
        s.eta = F(1.f);
        s.lobe = lane::select(lane::int_mask(reflect), IntT<F>(int32_t(BxDFFlags::SpecularReflection)),
                              IntT<F>(int32_t(BxDFFlags::SpecularTransmission)));
        return s;
    }
};

/// Thin slab (soap bubble, window pane): infinitely many internal bounces summed in closed form,
/// R' = R + T² R / (1 − R²), T' = 1 − R' (pbrt-v4 §9.5.2 derivation; Mitsuba's thindielectric),
/// transmission does not bend (wi = −wo) and crosses back into the same medium (no η² scaling).
class ThinDielectric {
public:
    explicit ThinDielectric(float eta = 1.5046f, const Spectrum& specular_reflectance = Spectrum(1.f),
                            const Spectrum& specular_transmittance = Spectrum(1.f));
    Spectrum eval(const BxDFContext&, const Vec3f&, const Vec3f&) const { return Spectrum(0.f); }
    float pdf(const BxDFContext&, const Vec3f&, const Vec3f&) const { return 0.f; }
    std::optional<BxDFSample> sample(const BxDFContext& ctx, const Vec3f& wo, float u_lobe, const Vec2f& u) const;
    BxDFFlags flags() const;
    std::string to_string() const;
    /// The packet form's parameters (ThinDielectricT<float>).
    ThinDielectricT<float> lanes() const { return {m_eta, m_r, m_t}; }

private:
    float m_eta;
    Spectrum m_r, m_t;
};

/// The smallest |cos θo| a rough dielectric divides by.
inline constexpr float kMinCosD = 1e-7f;

/// What a rough dielectric needs of the generalised half vector of (wo, wi) (Walter et al. 2007,
/// eq. 16), oriented to +z, computed in double: wo·wm and wi·wm of nearly orthogonal vectors lose
/// most of their digits to cancellation in float, and reciprocity at grazing angles with them.
struct DielectricHalf {
    Vec3f wm{0.f, 0.f, 1.f};
    float dot_o = 0.f, dot_i = 0.f;
    /// Fresnel reflectance on wm and 1 − it, each rounded from double. Near the critical angle
    /// of the denser side Fresnel is ill-conditioned (√ singularity), so a transmission pair takes
    /// it from the less dense side.
    float R = 0.f, T = 0.f;
    float denom = 0.f;  ///< (wi·wm + wo·wm/η')², η' = 1 for reflection (eq. 17's denominator)
    float etap2 = 1.f;  ///< η'²
    bool ok = false;    ///< both directions off the horizon, |h| > 0, no back-facing microfacet
};
/// The half-vector step over a double lane type D (double, or a double packet: simd/lane.h, "The
/// double side"): each field is the double whose rounding to float is that DielectricHalf field
/// (ok is 1 or 0). The float function (dielectric_half) is its double instantiation and a float
/// packet runs it on its double parts (dielectric_half_lanes), so every lane gets the float
/// function's bits: the same IEEE double operations in the same order, the float function's early
/// outs as selects, and its float products as double ones rounded to float (a product of two
/// floats is exact in double, so rounding it once gives the float product).
template <class D>
struct DielectricHalfD {
    Vec3P<D> wm;
    D dot_o, dot_i, R, T, denom, etap2, ok;
};
template <class D>
inline DielectricHalfD<D> dielectric_half_d(const Vec3P<D>& wo, const Vec3P<D>& wi, const D& eta) {
    const D zero(0.0), one(1.0);
    const D co = wo.z, ci = wi.z;
    const auto off_horizon = co != zero && ci != zero;
    const auto reflect = lane::round_to_float(co * ci) > zero;  // co · ci > 0 in float
    // Walter et al. 2007, eq. 16: h = −(η_i wi + η_o wo), here scaled by 1/η_o and oriented to +z;
    // η' = η(wi side)/η(wo side) is 1 for reflection.
    const D inv_eta = one / eta;
    const D etap = lane::select(reflect, one, lane::select(co > zero, eta, inv_eta));
    const D inv_etap = lane::select(reflect, one, lane::select(co > zero, inv_eta, eta));
    const Vec3P<D> h = wi * etap + wo;
    const D hl = length(h);  // sqrt((x² + y²) + z²), as glm::length
    const auto has_h = off_horizon && hl > zero;
    const Vec3P<D> wm = h * (one / lane::select(h.z < zero, lane::neg(hl), hl));
    const D dot_o = dot(wo, wm), dot_i = dot(wi, wm);  // (x + y) + z, as glm::dot
    const D fo = lane::round_to_float(dot_o), fi = lane::round_to_float(dot_i);
    // Back-facing microfacets contribute nothing (Walter et al. 2007, §5.1, χ⁺ terms); the test
    // is on the float dot products, in float.
    const auto front = !(lane::round_to_float(fi * ci) <= zero) && !(lane::round_to_float(fo * co) <= zero);
    const auto ok = has_h && front;
    // Fresnel from the less dense side of a transmission pair (DielectricHalf::R).
    // (Mask inequality spelt with && and ||: simd/packet.h.)
    const auto above = co > zero, denser = eta >= one;
    const auto from_inside = !reflect && ((above && !denser) || (!above && denser));
    const D Fd = fresnel_dielectric_d(lane::select(from_inside, dot_i, dot_o), eta, inv_eta);
    // Eq. 17's denominator from the float dot products: a double sum, squared in float.
    const D s = lane::round_to_float(fi + fo * inv_etap);
    DielectricHalfD<D> out;
    out.wm = lane::select(has_h, wm, Vec3P<D>(zero, zero, one));
    out.dot_o = lane::select(has_h, dot_o, zero), out.dot_i = lane::select(has_h, dot_i, zero);
    out.R = lane::select(ok, Fd, zero), out.T = lane::select(ok, one - Fd, zero);
    out.denom = lane::select(ok && !reflect, s * s, zero);
    out.etap2 = lane::select(ok, etap * etap, one);
    out.ok = lane::select(ok, one, zero);
    return out;
}
DielectricHalf dielectric_half(const Vec3f& wo, const Vec3f& wi, float eta);
/// Fresnel reflectance (double precision) at cos_i and 1 − it, both rounded to float.
void dielectric_fresnel_pair(float cos_i, float eta, float* R, float* T);

/// DielectricHalf over a lane type F (a lane outside `where` gets ok = false and DielectricHalf's
/// defaults), each lane exactly the float function: a float is the float function itself, a
/// packet runs dielectric_half_d on its double parts.
template <class F>
struct DielectricHalfT {
    V3<F> wm;
    F dot_o, dot_i, R, T, denom, etap2;
    MaskT<F> ok;
};
template <class F>
inline DielectricHalfT<F> dielectric_half_lanes(const V3<F>& wo, const V3<F>& wi, const F& eta, const MaskT<F>& where) {
    if constexpr (std::is_same_v<F, float>) {
        const DielectricHalf h = where ? dielectric_half(wo, wi, eta) : DielectricHalf{};
        return {h.wm, h.dot_o, h.dot_i, h.R, h.T, h.denom, h.etap2, h.ok};
    } else {
        using D = DoubleT<F>;
        DielectricHalfD<D> h[kDoubleParts<F>];
        on_double_parts<F>(wo, wi, eta, [](const auto& o, const auto& i, const D& e) { return dielectric_half_d<D>(o, i, e); }, h);
        // Each field rounded to float, on the lanes `where` (the float function's defaults elsewhere).
        auto out = [&](auto field, float other) { return from_double_parts<F>(where, h, field, other); };
        DielectricHalfT<F> r;
        r.wm = V3<F>(out([](const auto& x) { return x.wm.x; }, 0.f), out([](const auto& x) { return x.wm.y; }, 0.f),
                     out([](const auto& x) { return x.wm.z; }, 1.f));
        r.dot_o = out([](const auto& x) { return x.dot_o; }, 0.f);
        r.dot_i = out([](const auto& x) { return x.dot_i; }, 0.f);
        r.R = out([](const auto& x) { return x.R; }, 0.f);
        r.T = out([](const auto& x) { return x.T; }, 0.f);
        r.denom = out([](const auto& x) { return x.denom; }, 0.f);
        r.etap2 = out([](const auto& x) { return x.etap2; }, 1.f);
        r.ok = out([](const auto& x) { return x.ok; }, 0.f) != F(0.f);
        return r;
    }
}
/// dielectric_fresnel_pair over a lane type F (lanes outside `where`: 0, 0): a float is the float
/// function, a packet computes fresnel_dielectric_d on its double parts.
template <class F>
inline void dielectric_fresnel_pair_lanes(const F& cos_i, const F& eta, const MaskT<F>& where, F* R, F* T) {
    if constexpr (std::is_same_v<F, float>) {
        *R = *T = 0.f;
        if (where) dielectric_fresnel_pair(cos_i, eta, R, T);
    } else {
        using D = DoubleT<F>;
        constexpr int P = kDoubleParts<F>;
        D c[P], e[P], r[P], t[P];
        lane::to_doubles(cos_i, c), lane::to_doubles(eta, e);
        for (int p = 0; p < P; ++p) r[p] = fresnel_dielectric_d(c[p], e[p]), t[p] = D(1.0) - r[p];
        *R = lane::select(where, lane::from_doubles(r), F(0.f));
        *T = lane::select(where, lane::from_doubles(t), F(0.f));
    }
}

/// The rough dielectric without multiple-scattering compensation over a lane type F, on the lane
/// distribution DistT<F> (GGXT or BeckmannT): RoughDielectric's single-scattering lobes are its
/// float instantiation, and the path tracer's packets use it directly. The half vector and Fresnel
/// are computed in double on the packet's double parts (dielectric_half_lanes), each lane exactly
/// the float function; D, G and the visible-normal density and sampling run on the float packet.
template <template <class> class DistT, class F>
struct RoughDielectricT {
    DistT<F> d;
    F eta;  ///< η_int / η_ext, not 1
    RGB<F> r, t;

    struct EvalPdf {
        RGB<F> f;
        F pdf;
    };
    /// f·|cos θi| (eq. 20 reflection, eq. 21 transmission; Radiance divides by η'², Veach 1997,
    /// eq. 5.12) and the density of sample() (VNDF, Jacobians eqs. 14 and 17), on the lanes `where`.
    EvalPdf eval_pdf(const BxDFContext& ctx, const V3<F>& wo, const V3<F>& wi, const MaskT<F>& where) const {
        using M = MaskT<F>;
        const DielectricHalfT<F> h = dielectric_half_lanes<F>(wo, wi, eta, where);
        const M reflect = wo.z * wi.z > F(0.f);
        const F pr = has_flag(ctx.allowed, BxDFFlags::Reflection) ? h.R : F(0.f);
        const F pt = has_flag(ctx.allowed, BxDFFlags::Transmission) ? h.T : F(0.f);
        const M lobes = pr + pt > F(0.f);
        const F sum = lane::select(lobes, pr + pt, F(1.f));
        const F aco = lane::max(lane::abs(wo.z), F(kMinCosD));
        const F Dm = d.D(h.wm), G = d.G(wo, wi), vis = d.pdf_visible(wo, h.wm);
        // Reflection.
        const RGB<F> f_r = r * (Dm * G * h.R / (F(4.f) * aco));
        const F pdf_r = vis / (F(4.f) * lane::select(h.ok, lane::abs(h.dot_o), F(1.f))) * pr / sum;
        // Transmission.
        const M tr = h.denom > F(0.f);
        const F denom = lane::select(tr, h.denom, F(1.f));
        F ft = Dm * h.T * G * lane::abs(h.dot_i * h.dot_o) / (aco * denom);
        if (ctx.mode == TransportMode::Radiance) ft = ft / h.etap2;
        const F dwm_dwi = lane::abs(h.dot_i) / denom;
        const F pdf_t = vis * dwm_dwi * pt / sum;
        const M on = h.ok && (reflect || tr);
        EvalPdf out;
        out.f = lane::select(on, lane::select(reflect, f_r, t * ft), RGB<F>(F(0.f)));
        out.pdf = lane::select(on && lobes, lane::select(reflect, pdf_r, pdf_t), F(0.f));
        return out;
    }
    /// A visible normal (VNDF), then reflection or refraction chosen by Fresnel.
    BxDFSampleT<F> sample(const BxDFContext& ctx, const V3<F>& wo, const F& u_lobe, const V2<F>& u,
                          const MaskT<F>& where) const {
        using M = MaskT<F>;
        const V3<F> wm = d.sample_visible(wo, u);
        F R, T;
        dielectric_fresnel_pair_lanes<F>(dot(wo, wm), eta, where, &R, &T);
        const F pr = has_flag(ctx.allowed, BxDFFlags::Reflection) ? R : F(0.f);
        const F pt = has_flag(ctx.allowed, BxDFFlags::Transmission) ? T : F(0.f);
        const M lobes = pr + pt > F(0.f);
        const M reflects = u_lobe < pr / lane::select(lobes, pr + pt, F(1.f));
        const V3<F> wr = -wo + F(2.f) * dot(wo, wm) * wm;  // reflect (math/spherical.h)
        F etap;
        V3<F> wt;
        const M refracts = refract<F>(wo, wm, eta, &etap, &wt) && wt.z * wo.z < F(0.f);
        BxDFSampleT<F> s;
        s.wi = lane::select(reflects, wr, wt);
        const EvalPdf ep = eval_pdf(ctx, wo, s.wi, where && lobes);
        s.valid = where && wo.z != F(0.f) && lobes && lane::select(reflects, wr.z * wo.z > F(0.f), refracts) &&
                  ep.pdf > F(0.f);
        s.pdf = ep.pdf;
        s.weight = ep.f / lane::select(s.valid, ep.pdf, F(1.f));
        s.eta = lane::select(reflects, F(1.f), etap);
        s.lobe = lane::select(lane::int_mask(reflects), IntT<F>(int32_t(BxDFFlags::GlossyReflection)),
                              IntT<F>(int32_t(BxDFFlags::GlossyTransmission)));
        return s;
    }
};

/// The path tracer's packet parameters of a rough dielectric (kRoughDielectricParams floats): 0 η,
/// 1–3 specular reflectance, 4–6 specular transmittance, 9 αx, 10 αy, 11 separable shadowing (1 or 0).
inline constexpr int kRoughDielectricParams = 12;
template <template <class> class DistT>
inline void rough_dielectric_packet_params(const RoughDielectricT<DistT, float>& l, float* q) {
    q[0] = l.eta;
    for (int c = 0; c < 3; ++c) q[1 + c] = l.r[c], q[4 + c] = l.t[c];
    q[7] = q[8] = 0.f;
    q[9] = l.d.ax, q[10] = l.d.ay, q[11] = l.d.separable ? 1.f : 0.f;
}
/// The packet form from packet parameters q(k) on the lanes `where`; the other lanes (other models,
/// whose parameters are not a dielectric's) get η 1.5, α 1 and black reflectance and transmittance.
template <template <class> class DistT, class F, class Q>
inline RoughDielectricT<DistT, F> rough_dielectric_lanes(const MaskT<F>& where, Q q) {
    auto at = [&](int k, float other) { return lane::select(where, q(k), F(other)); };
    return {DistT<F>{at(9, 1.f), at(10, 1.f), at(11, 0.f) != F(0.f)}, at(0, 1.5f),
            RGB<F>(at(1, 0.f), at(2, 0.f), at(3, 0.f)), RGB<F>(at(4, 0.f), at(5, 0.f), at(6, 0.f))};
}

/// Rough dielectric interface: Walter, Marschner, Li, Torrance 2007, "Microfacet Models for
/// Refraction through Rough Surfaces", EGSR. Reflection eq. 20, transmission eq. 21, generalised
/// half vector eq. 16, Jacobians eqs. 14 and 17; VNDF sampling replaces their eq. 24–28 sampling.
template <class Distribution>
class RoughDielectric {
public:
    /// `fresnel_avg`: the average the Kulla–Conty set-up reads, precomputed by
    /// multiscatter_fresnel_average(eta) (null: computed here when needed).
    RoughDielectric(const Distribution& distrib, float eta, const Spectrum& specular_reflectance = Spectrum(1.f),
                    const Spectrum& specular_transmittance = Spectrum(1.f), bool multiscatter = false,
                    const DielectricFresnelAverage* fresnel_avg = nullptr);
    /// The Fresnel average the multiple-scattering set-up of a BxDF of relative IOR `eta` reads
    /// (that of the less dense side), for a material to compute once at load.
    static DielectricFresnelAverage multiscatter_fresnel_average(float eta);
    Spectrum eval(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const;
    float pdf(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const;
    std::optional<BxDFSample> sample(const BxDFContext& ctx, const Vec3f& wo, float u_lobe, const Vec2f& u) const;
    BxDFFlags flags() const;
    std::string to_string() const;
    bool is_smooth() const { return m_d.effectively_smooth() || m_eta == 1.f; }
    bool multiscatter() const { return m_ms; }
    /// The single-scattering lobes' packet form (RoughDielectricT<float>).
    using Lanes = std::conditional_t<std::is_same_v<Distribution, GGX>, RoughDielectricT<GGXT, float>,
                                     RoughDielectricT<BeckmannT, float>>;
    Lanes lanes() const { return Lanes{m_d.lanes(), m_eta, m_r, m_t}; }
    /// Whether the model is exactly its packet form: rough, and without multiple scattering.
    bool has_lanes() const { return !is_smooth() && !m_ms; }

private:
    struct EvalPdf {
        Spectrum f{0.f};
        float pdf = 0.f;
    };
    EvalPdf eval_pdf(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const;
    // Kulla–Conty (header comment): lobe value (with |cos θi|, Importance form) and sampling terms.
    void setup_multiscatter(const DielectricFresnelAverage* fresnel_avg);
    static float valid_eta(float eta) { return eta > 0.f && std::isfinite(eta) ? eta : 1.f; }
    static float less_dense_eta(float eta) { return eta >= 1.f ? eta : 1.f / eta; }  // η_ld, ≥ 1
    float ms_E(const Vec3f& w) const;  // E of the side w is on
    Spectrum ms_eval(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const;
    float ms_probability(const BxDFContext& ctx, const Vec3f& wo, float* p_trans) const;

    Distribution m_d;
    float m_eta;
    Spectrum m_r, m_t;
    bool m_ms = false;
    float m_alpha_ms = 0.f;
    float m_x[2] = {0.f, 0.f};         // transmitted fraction x_e, x_i
    float m_inv_loss[2] = {0.f, 0.f};  // 1/(π(1 − Ē)) of the exterior / interior
};
extern template class RoughDielectric<GGX>;
extern template class RoughDielectric<Beckmann>;
}  // namespace pellucid
