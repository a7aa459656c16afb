// Disney principled BSDF, 2015 model: Burley 2015, "Extending the Disney BRDF to a BSDF with
// Integrated Subsurface Scattering", SIGGRAPH course notes (Physically Based Shading course), built
// on the 2012 BRDF (Burley 2012, "Physically-Based Shading at Disney", §5 and App. B). One BxDF
// with two modes: a solid (an interface between the exterior, +z, and an interior of relative IOR
// η) and a thin sheet (`thin`: the same medium on both sides, no bending). Defined as Mitsuba 3.9
// defines its `principled` and `principledthin` plugins, so imported scenes render as Mitsuba
// renders them; where that definition departs from Burley's notes it is said below.
// SPDX-License-Identifier: Apache-2.0
//
// Notation: wo is the viewer side, wi the light side (bxdf_types.h); co = cos θo, ci = cos θi,
// cos θd = wi·h for the reflection half vector h; F_S(x) = (1 − x)^5 (the Schlick weight);
// c_tint = base/luminance(base); m = metallic, t_s = specular_tint.
// Specular α from roughness r and anisotropic a: αx = max(1e-3, r²/s), αy = max(1e-3, r²·s),
// s = √(1 − 0.9a) (Burley 2012, §5.4 and App. B); GGX D. G is Smith's SEPARABLE form
// G1(wo)·G1(wi) (Heitz 2014, eq. 98), each G1 zero where its direction sees the back of the
// microfacet.
// η: `eta` if given, else from `specular` by ((η − 1)/(η + 1))² = 0.08·specular, i.e.
//   η = 2/(1 − √(0.08·specular)) − 1 (specular 0.5 → η = 1.5; the 2012 model's F0 = 0.08·specular
//   read as the normal-incidence reflectance of an interface). With specular transmission, η = 1
//   becomes 1.001 and specular = 0 becomes 1e-3 (a refracting lobe needs η ≠ 1).
// Lobe weights: w_brdf = (1 − m)(1 − spec_trans), w_bsdf = (1 − m)·spec_trans (Burley 2015:
// spec_trans blends the dielectric BRDF toward a rough glass, metallic blends both toward metal).
// S(R0, cos) = R0 + (1 − R0) F_S(cos), with the transmitted cosine when cos is on the denser side
// (1 on total internal reflection). R0(η) = ((η − 1)/(η + 1))². F_η is the exact dielectric Fresnel.
//
// SOLID, seen from the exterior (co > 0), f =
//     F_p · D(h) G / (4 co ci)                                       specular reflection
//       F_p = (1 − m)(1 − t_s) F_η(wo·h) + m·S(base) + (1 − m) t_s·S(c_tint·R0(η))
//       (Burley 2015 keeps the exact F_η for the dielectric; the Schlick blend is Mitsuba's)
//   + w_bsdf √base (1 − F_η) D G |wo·h||wi·h| η'² / (co |ci| (wo·h + η' wi·h)²)
//       specular transmission: Walter et al. 2007, eq. 21, h the generalised half vector (eq. 16),
//       η' = η of wi's side / η of wo's side; Radiance mode divides by η'² (bxdf_types.h);
//       the √base tint is Burley 2015's
//   + ¼ clearcoat · S(0.04) · D_GTR1(h; α_c) · G_c                    clearcoat
//       α_c = lerp(0.1, 0.001, clearcoat_gloss), GTR1 of Burley 2012 App. B eq. 4, G_c separable
//       GGX with α = 0.25. As Mitsuba defines it: WITHOUT Burley's microfacet factor 1/(4 co ci)
//   + w_brdf · base/π · lerp(f_d + f_r, f_ss, flatness)               diffuse
//       f_d = (1 − F_S(ci)/2)(1 − F_S(co)/2), f_r = R_R (F_S(ci) + F_S(co) + F_S(ci) F_S(co)(R_R − 1)),
//       R_R = 2 r cos² θd (Burley 2015's Lambert + retro-reflection split of the 2012 diffuse);
//       f_ss = 1.25 (F_ss (1/(co + ci) − 0.5) + 0.5), F_ss = (1 + (F_ss90 − 1) F_S(ci))(1 + (F_ss90 − 1) F_S(co)),
//       F_ss90 = r cos² θd (Hanrahan–Krueger approximation, Burley 2012 §5.3)
//   + (1 − m) · sheen · lerp(1, c_tint, sheen_tint) · F_S(cos θd)     sheen (Burley 2012 §5.5),
//       only where w_brdf > 0.
// From the interior (co < 0) only the interface remains: reflection w_bsdf F_η D G/(4 |co| |ci|)
// and the transmission lobe above. Without a transmission lobe (w_bsdf = 0) the solid is opaque and,
// like every pellucid material, two-sided: seen from behind it is the front mirrored (Mitsuba's
// principled is black from behind unless wrapped in `twosided`, which then gives exactly this).
//
// THIN (`thin`): wo and wi are first mirrored together so that wo is on +z (the sheet is the same
// from both sides); η is the sheet's IOR, d_t = diffuse_transmission/2 ∈ [0, 1]. f =
//     spec_trans · lerp(F_η, S(c_tint·R0(η)), t_s) · D G / (4 co ci)         reflection
//   + spec_trans · base · (1 − F_η) · D' G' / (4 co |ci|)                    transmission
//       at the half vector of wo and wi mirrored to +z, with the roughness scaled by
//       (0.65 η − 0.35) (Burley 2015, Fig. 15), only where wi·h < 0 (Mitsuba's visibility test;
//       this support is not symmetric in wo and wi, so this lobe is reciprocal only where both
//       directions lie in it)
//   + (1 − spec_trans)(1 − d_t) · (diffuse + sheen as above, without w_brdf and (1 − m))
//   + (1 − spec_trans) · d_t · base/π                                          diffuse transmission.
// No metallic and no clearcoat in the thin mode.
//
// Sampling (Mitsuba's lobe probabilities). Solid, exterior: the specular group with weight 1, split
// at the sampled visible normal m into reflection 1 − w_bsdf(1 − F_η(wo·m)) and transmission
// w_bsdf(1 − F_η(wo·m)); clearcoat ¼·clearcoat (GTR1 half vectors, Burley 2012 App. B eq. 5);
// diffuse w_brdf (cosine-weighted). Interior: F_η : 1 − F_η. Thin: spec_trans/2 for each specular
// lobe, (1 − spec_trans)(1 − d_t) cosine reflection, (1 − spec_trans) d_t cosine transmission.
// Visible normals: GGX::sample_visible. Lobes outside ctx.allowed get probability 0.
//
// Energy: not conserving. The diffuse lobe is not reduced by what the specular lobes reflect (for a
// white base their sum exceeds 1), the retro-reflection exceeds 1 at grazing angles for high
// roughness, and the thin diffuse lobes add to the specular ones. With base colours ≤ 0.6 the
// albedo stays below 1 (tests/cpp/bxdf/bxdf_cases.h; the excess: test_principled_bsdf.cpp).
// Scene-facing parameters: material/principled.h.
//
// Packet form: PrincipledBSDFT<F> writes the opaque solid (no thin sheet, no transmission lobe:
// w_bsdf = 0, which leaves w_brdf = 1 − m) once over a lane type F (simd/lane.h): specular reflection
// with the blended Fresnel, clear coat, diffuse with retro-reflection and flatness, and sheen. The
// path tracer shades such materials with it (kPacketPrincipled, integrator/path_services.h), and
// PrincipledBSDF's eval, pdf and sample are its float instantiation wherever has_lanes(). The half
// vector and the dielectric Fresnel are computed in double by principled_half_d, on a packet's two
// halves as double packets (principled_half_lanes; the float function principled_half is its double
// instantiation), and the clear coat's GTR1 normal (pow, sin, cos) one lane at a time by a function
// compiled once (principled_gtr1_normal), so every lane type gives the same bits; the rest runs on
// the packet. ln α_c² is a parameter,
// computed once at construction. The thin sheet has a packet form of its own, PrincipledThinT<F>
// (kPacketPrincipledThin; PrincipledBSDF's eval, pdf and sample are its float instantiation where
// thin()): its half vector is that of wo and wi mirrored to +z, in float, so the whole form is lane
// operations. So has the solid with a transmission lobe, PrincipledSolidT<F> (kPacketPrincipledSolid;
// the float instantiation where neither): its generalised half vector, Fresnel and the Jacobian's
// denominator come in double from principled_half_d as well. Every principled material
// is shaded as a packet, and the three forms share the diffuse, sheen, Schlick and GTR1 terms.
#pragma once
#include <optional>
#include <string>
#include <type_traits>

#include "pellucid/bxdf/bxdf_types.h"
#include "pellucid/bxdf/fresnel.h"
#include "pellucid/bxdf/microfacet.h"
#include "pellucid/bxdf/principled.h"

namespace pellucid {

namespace principled_detail {
/// Both lobe bits allowed (not just one of them).
constexpr bool allows(const BxDFContext& ctx, BxDFFlags lobe) {
    return (uint32_t(ctx.allowed) & uint32_t(lobe)) == uint32_t(lobe);
}
/// (1 − cos)^5, cos clamped to [0, 1] (Schlick 1994, eq. 15; disney::schlick_weight).
template <class F>
inline F schlick_weight(const F& c) {
    const F m = lane::min(lane::max(F(1.f) - c, F(0.f)), F(1.f)), m2 = m * m;
    return m2 * m2 * m;
}
/// Schlick's weight at an interface of relative IOR eta, for the cosine cos_i between the incident
/// direction and the microfacet normal: the transmitted cosine from the denser side (1 on total
/// internal reflection); PrincipledBSDF::schlick is r0 + (1 − r0)·this.
template <class F>
inline F schlick_weight_eta(const F& cos_i, const F& eta) {
    const F eta_it = lane::select(cos_i >= F(0.f), eta, F(1.f) / eta);
    const F cos_t2 = F(1.f) - (F(1.f) - cos_i * cos_i) / (eta_it * eta_it);
    return lane::select(eta_it > F(1.f), schlick_weight<F>(lane::abs(cos_i)),
                        schlick_weight<F>(lane::sqrt(lane::max(F(0.f), cos_t2))));
}
template <class F>
inline F schlick(const F& r0, const F& cos_i, const F& eta) {
    return r0 + (F(1.f) - r0) * schlick_weight_eta<F>(cos_i, eta);
}
template <class F>
inline RGB<F> schlick(const RGB<F>& r0, const F& cos_i, const F& eta) {
    const F w = F(0.f) + (F(1.f) - F(0.f)) * schlick_weight_eta<F>(cos_i, eta);
    return RGB<F>(r0.r + (F(1.f) - r0.r) * w, r0.g + (F(1.f) - r0.g) * w, r0.b + (F(1.f) - r0.b) * w);
}
/// GTR1 (γ = 1) of the clear coat (Burley 2012, App. B eq. 4), zero below the horizon; log_a2 = ln α².
template <class F>
inline F gtr1(const F& cos_h, const F& alpha, const F& log_a2) {
    const F a2 = alpha * alpha;
    const F d = (a2 - F(1.f)) / (F(kPi) * log_a2 * (F(1.f) + (a2 - F(1.f)) * cos_h * cos_h));
    return lane::select(d * cos_h > F(1e-20f), d, F(0.f));
}
/// Smith G1 of d for v and microfacet normal h, zero where v sees the back of the microfacet.
template <class F>
inline F g1(const GGXT<F>& d, const V3<F>& v, const V3<F>& h) {
    return lane::select(dot(v, h) * v.z > F(0.f), d.G1(v), F(0.f));
}
/// w_diffuse·(diffuse, retro-reflection, flatness) + w_sheen·sheen, as f·ci (header comment), on
/// the lanes `where` (a term that no lane of `where` has is not computed).
template <class F>
inline RGB<F> diffuse_sheen(const RGB<F>& base, const RGB<F>& tint, const F& roughness, const F& flatness,
                            const F& sheen, const F& sheen_tint, const F& co, const F& ci, const F& cos_d,
                            const F& w_diffuse, const F& w_sheen, const MaskT<F>& where) {
    const F fo = schlick_weight<F>(co), fi = schlick_weight<F>(ci);
    const F f_d = (F(1.f) - F(0.5f) * fo) * (F(1.f) - F(0.5f) * fi);
    const F rr = F(2.f) * roughness * cos_d * cos_d;
    const F f_r = rr * (fo + fi + fo * fi * (rr - F(1.f)));
    F f = f_d + f_r;
    const auto flat = flatness > F(0.f);
    if (lane::any(where && flat)) {
        const F fss90 = F(0.5f) * rr;
        const F fss = (F(1.f) + (fss90 - F(1.f)) * fo) * (F(1.f) + (fss90 - F(1.f)) * fi);
        const F f_ss = F(1.25f) * (fss * (F(1.f) / (co + ci) - F(0.5f)) + F(0.5f));
        f = lane::select(flat, f + (f_ss - f) * flatness, f);
    }
    RGB<F> out = base * (w_diffuse * F(kInvPi) * f * ci);
    const auto sheen_on = sheen > F(0.f) && w_sheen > F(0.f);
    if (lane::any(where && sheen_on)) {
        const F s = w_sheen * sheen * schlick_weight<F>(lane::abs(cos_d)) * ci;
        const RGB<F> sh(F(1.f) + (tint.r - F(1.f)) * sheen_tint, F(1.f) + (tint.g - F(1.f)) * sheen_tint,
                        F(1.f) + (tint.b - F(1.f)) * sheen_tint);
        out = lane::select(sheen_on, out + sh * s, out);
    }
    return out;
}

/// The clear coat's GTR1 normal: cos² θh = (1 − α^{2(1−u.y)})/(1 − α²), φ = 2π u.x (Burley 2012,
/// App. B eq. 5), with libm's pow, cos and sin.
Vec3f principled_gtr1_normal(float alpha, const Vec2f& u);

/// principled_gtr1_normal over a lane type F (principled2012_detail::normal_lanes).
template <class F>
inline V3<F> principled_gtr1_normal_lanes(const F& alpha, const V2<F>& u, const MaskT<F>& where) {
    return principled2012_detail::normal_lanes<F, principled_gtr1_normal>(alpha, u, where);
}
/// What the solids need of the half vector of (wo, wi) with wo.z, wi.z ≠ 0, computed in double: h
/// (generalised for transmission, Walter et al. 2007 eq. 16, oriented to +z), wo·h and wi·h, the
/// dielectric Fresnel (from wi's side for transmission from the denser side), the Jacobian's
/// denominator (wo·h + η' wi·h)² and η' (η(wi side)/η(wo side)); ok false where h is undefined.
struct PrincipledHalf {
    Vec3f h{0.f, 0.f, 1.f};
    float dot_o = 0.f, dot_i = 0.f, F = 0.f, denom = 0.f, etap = 1.f;
    bool ok = false;
};
/// principled_half over a double lane type D (double, or a double packet: simd/lane.h, "The double
/// side"): each field is the double whose rounding to float is that PrincipledHalf field (ok is 1
/// or 0). The float function is its double instantiation and a float packet runs it on its double
/// parts (principled_half_lanes), so every lane gets the float function's bits: the same IEEE
/// double operations in the same order, the early out (no half vector) as selects, and the float
/// product wo.z·wi.z as the double product rounded to float (exact in double, as for
/// dielectric_half_d).
template <class D>
struct PrincipledHalfD {
    Vec3P<D> h;
    D dot_o, dot_i, F, denom, etap, ok;
};
template <class D>
inline PrincipledHalfD<D> principled_half_d(const Vec3P<D>& wo, const Vec3P<D>& wi, const D& eta) {
    const D zero(0.0), one(1.0);
    const auto front = wo.z > zero, reflect = lane::round_to_float(wo.z * wi.z) > zero;
    // η' = η(wi side)/η(wo side) for transmission; Walter et al. 2007, eq. 16's h (wi·1 = wi
    // exactly for reflection), oriented to +z.
    const D inv_eta = one / eta;
    const D etap = lane::select(front, eta, inv_eta);
    const Vec3P<D> hh = wo + wi * lane::select(reflect, one, etap);
    const D hl = length(hh);  // sqrt((x² + y²) + z²), as glm::length
    const auto has_h = hl > zero;
    const Vec3P<D> hd = hh * (one / lane::select(hh.z < zero, lane::neg(hl), hl));
    const D dot_o = dot(wo, hd), dot_i = dot(wi, hd);  // (x + y) + z, as glm::dot
    // F from wi's side for transmission from the denser side. (Mask inequality spelt with && and
    // ||: simd/packet.h.)
    const auto denser = eta >= one;
    const auto from_wi = !reflect && ((front && !denser) || (!front && denser));
    const D Fd = fresnel_dielectric_d(lane::select(from_wi, dot_i, dot_o), eta, inv_eta);
    // The Jacobian's denominator: a double sum, rounded to float and squared in float.
    const D s = lane::round_to_float(dot_o + etap * dot_i);
    PrincipledHalfD<D> out;
    out.h = Vec3P<D>(lane::select(has_h, hd.x, zero), lane::select(has_h, hd.y, zero), lane::select(has_h, hd.z, one));
    out.dot_o = lane::select(has_h, dot_o, zero), out.dot_i = lane::select(has_h, dot_i, zero);
    out.F = lane::select(has_h, Fd, zero);
    out.denom = lane::select(has_h, lane::round_to_float(s * s), zero);
    out.etap = etap;
    out.ok = lane::select(has_h, one, zero);
    return out;
}
PrincipledHalf principled_half(const Vec3f& wo, const Vec3f& wi, float eta);
/// principled_half over a lane type F (lanes outside `where`: PrincipledHalf's defaults): a float is
/// the float function, a packet runs principled_half_d on its double parts.
template <class F>
inline void principled_half_lanes(const V3<F>& wo, const V3<F>& wi, const F& eta, const MaskT<F>& where,
                                        V3<F>* h, F* dot_o, F* dot_i, F* fr, F* denom, F* etap, MaskT<F>* ok) {
    if constexpr (std::is_same_v<F, float>) {
        const PrincipledHalf p = where ? principled_half(wo, wi, eta) : PrincipledHalf{};
        *h = p.h, *dot_o = p.dot_o, *dot_i = p.dot_i, *fr = p.F, *denom = p.denom, *etap = p.etap, *ok = p.ok;
    } else {
        using D = DoubleT<F>;
        PrincipledHalfD<D> r[kDoubleParts<F>];
        on_double_parts<F>(wo, wi, eta, [](const auto& o, const auto& i, const D& e) { return principled_half_d<D>(o, i, e); }, r);
        // Each field rounded to float, on the lanes `where` (the float function's defaults elsewhere).
        auto out = [&](auto field, float other) { return from_double_parts<F>(where, r, field, other); };
        *h = V3<F>(out([](const auto& x) { return x.h.x; }, 0.f), out([](const auto& x) { return x.h.y; }, 0.f),
                   out([](const auto& x) { return x.h.z; }, 1.f));
        *dot_o = out([](const auto& x) { return x.dot_o; }, 0.f);
        *dot_i = out([](const auto& x) { return x.dot_i; }, 0.f);
        *fr = out([](const auto& x) { return x.F; }, 0.f);
        *denom = out([](const auto& x) { return x.denom; }, 0.f);
        *etap = out([](const auto& x) { return x.etap; }, 1.f);
        *ok = out([](const auto& x) { return x.ok; }, 0.f) != F(0.f);
    }
}
/// What the packet forms' eval_pdf returns: f·|cos θi| and the density.
template <class F>
struct EvalPdf {
    RGB<F> f;
    F pdf;
};
/// The solids' diffuse and clear-coat directions for wo on the lanes that chose them (`diffuse`,
/// `coat`; computed only where some lane did, +z elsewhere): a cosine-weighted direction, and wo
/// reflected about a GTR1 normal, valid (*ok_c) where wo sees the normal and the reflection leaves
/// above the surface.
template <class F>
inline void diffuse_coat_directions(const V3<F>& wo, const V2<F>& u, const F& cc_alpha, const MaskT<F>& diffuse,
                                    const MaskT<F>& coat, V3<F>* wd, V3<F>* wc, MaskT<F>* ok_c) {
    const V3<F> up(F(0.f), F(0.f), F(1.f));
    *wd = lane::any(diffuse) ? square_to_cosine_hemisphere<F>(u) : up;
    *wc = up;
    *ok_c = MaskT<F>(false);
    if (lane::any(coat)) {
        const V3<F> mc = principled_gtr1_normal_lanes<F>(cc_alpha, u, coat);
        *wc = -wo + F(2.f) * dot(wo, mc) * mc;
        *ok_c = dot(wo, mc) > F(0.f) && wc->z > F(0.f);
    }
}
}  // namespace principled_detail

/// The opaque solid principled BSDF over a lane type F (header comment, "Packet form"): per-lane
/// parameters. PrincipledBSDF::lanes() fills the float instantiation; the path tracer loads a packet
/// of them per vertex (principled_lanes).
template <class F>
struct PrincipledBSDFT {
    RGB<F> base, tint;  ///< base colour and c_tint
    F metallic, roughness, spec_tint, sheen, sheen_tint, flatness, clearcoat;
    F cc_alpha, cc_log_a2;  ///< α_c and ln α_c²
    F eta, w_brdf;
    GGXT<F> spec;

    using EvalPdf = principled_detail::EvalPdf<F>;
    /// f·|cos θi| and the density of sample(), on the lanes `where` (others: unspecified). Seen from
    /// behind, the front mirrored; transmission pairs give 0.
    EvalPdf eval_pdf(const BxDFContext& ctx, const V3<F>& wo, const V3<F>& wi, const MaskT<F>& where) const {
        using namespace principled_detail;
        using M = MaskT<F>;
        const M flip = wo.z < F(0.f);
        const V3<F> o = lane::select(flip, -wo, wo), i = lane::select(flip, -wi, wi);
        const F co = o.z, ci = i.z;
        const M pair = wo.z != F(0.f) && wi.z != F(0.f) && co * ci > F(0.f);
        V3<F> h;
        F dot_o, dot_i, fr, denom, etap;
        M defined;
        principled_half_lanes<F>(o, i, eta, where && pair, &h, &dot_o, &dot_i, &fr, &denom, &etap, &defined);
        const M compatible = dot_o > F(0.f) && dot_i > F(0.f);
        // Lobe probabilities: the specular group 1 (its reflection share is 1 without transmission),
        // the clear coat ¼·clearcoat, the diffuse w_brdf.
        const bool gr = principled_detail::allows(ctx, BxDFFlags::GlossyReflection),
                   dr = principled_detail::allows(ctx, BxDFFlags::DiffuseReflection);
        const F g_spec = gr ? F(1.f) : F(0.f);
        F p_cc = lane::select(M(gr) && clearcoat > F(0.f), F(0.25f) * clearcoat, F(0.f));
        F p_d = lane::select(M(dr) && w_brdf > F(0.f), w_brdf, F(0.f));
        const F total = g_spec + p_cc + p_d;
        const F inv_total = lane::select(total > F(0.f), F(1.f) / lane::select(total > F(0.f), total, F(1.f)), F(0.f));
        const F p_r = gr ? inv_total : F(0.f);
        p_cc = p_cc * inv_total;
        p_d = p_d * inv_total;

        // D, G1 and the visible-normal density share their terms (GGXT::pdf_visible, g1).
        const F D = spec.D(h), G1o = spec.G1(o), G1i = spec.G1(i);
        const F c_o = dot(o, h), c_i = dot(i, h);
        const F G = lane::select(compatible, lane::select(c_o * o.z > F(0.f), G1o, F(0.f)) *
                                                 lane::select(c_i * i.z > F(0.f), G1i, F(0.f)),
                                 F(0.f));
        const F vis = lane::select(compatible && c_o > F(0.f), G1o / o.z * D * c_o, F(0.f));
        const F jac = F(1.f) / (F(4.f) * lane::abs(dot_i));
        // Specular reflection with the blended Fresnel (one Schlick weight at wo·h for all three).
        const F one_m = F(1.f) - metallic;
        const F w = schlick_weight_eta<F>(dot_o, eta);
        auto schlick_w = [&](const RGB<F>& r0) {
            return RGB<F>(r0.r + (F(1.f) - r0.r) * w, r0.g + (F(1.f) - r0.g) * w, r0.b + (F(1.f) - r0.b) * w);
        };
        RGB<F> Fp(one_m * (F(1.f) - spec_tint) * fr);
        const auto metal = metallic > F(0.f), tinted = spec_tint > F(0.f);
        if (lane::any(where && metal)) Fp = lane::select(metal, Fp + schlick_w(base) * metallic, Fp);
        if (lane::any(where && tinted)) {
            const F r0 = (eta - F(1.f)) / (eta + F(1.f));
            Fp = lane::select(tinted, Fp + schlick_w(tint * (r0 * r0)) * (one_m * spec_tint), Fp);
        }
        RGB<F> f = lane::select(compatible && fr > F(0.f), Fp * (D * G / (F(4.f) * co)), RGB<F>(F(0.f)));
        F pdf = p_r * vis * jac;
        // The clear coat.
        const M cc = clearcoat > F(0.f);
        if (lane::any(where && cc)) {
            const F Dc = gtr1<F>(h.z, cc_alpha, cc_log_a2);
            const F Fc = F(0.04f) + (F(1.f) - F(0.04f)) * w;
            const GGXT<F> coat{F(0.25f), F(0.25f), M(false)};
            const F fc = F(0.25f) * clearcoat * Fc * Dc * (g1<F>(coat, o, h) * g1<F>(coat, i, h)) * ci;
            f = lane::select(cc && compatible, f + RGB<F>(fc), f);
            pdf = lane::select(cc, pdf + p_cc * Dc * h.z * jac, pdf);
        }
        // Diffuse weighted by w_brdf, sheen by 1 − m, both only where w_brdf > 0.
        const M diffuse = w_brdf > F(0.f);
        if (lane::any(where && diffuse)) {
            const RGB<F> ds = diffuse_sheen<F>(base, tint, roughness, flatness, sheen, sheen_tint, co, ci, dot_i, w_brdf,
                                               one_m, where && diffuse);
            f = lane::select(diffuse, f + ds, f);
        }
        pdf = pdf + p_d * ci * F(kInvPi);
        EvalPdf out;
        out.f = lane::select(pair, f, RGB<F>(F(0.f)));
        out.pdf = lane::select(pair, pdf, F(0.f));
        return out;
    }
    RGB<F> eval(const BxDFContext& ctx, const V3<F>& wo, const V3<F>& wi, const MaskT<F>& where) const {
        return eval_pdf(ctx, wo, wi, where).f;
    }
    /// Mitsuba's lobe choice (header comment) on the lanes `where` (others: not valid).
    BxDFSampleT<F> sample(const BxDFContext& ctx, const V3<F>& wo, const F& u_lobe, const V2<F>& u,
                          const MaskT<F>& where) const {
        using namespace principled_detail;
        using M = MaskT<F>;
        const M flip = wo.z < F(0.f);
        const V3<F> o = lane::select(flip, -wo, wo);
        const bool gr = principled_detail::allows(ctx, BxDFFlags::GlossyReflection),
                   dr = principled_detail::allows(ctx, BxDFFlags::DiffuseReflection);
        const F g_spec = gr ? F(1.f) : F(0.f);
        const F p_cc = lane::select(M(gr) && clearcoat > F(0.f), F(0.25f) * clearcoat, F(0.f));
        const F p_d = lane::select(M(dr) && w_brdf > F(0.f), w_brdf, F(0.f));
        const F total = g_spec + p_cc + p_d;
        const F x = u_lobe * total;
        const M is_d = x < p_d, is_cc = !is_d && x < p_d + p_cc, is_spec = !is_d && !is_cc;
        // Each lobe's direction where some lane of `where` chose it.
        const V3<F> up(F(0.f), F(0.f), F(1.f));
        V3<F> wd, wc;
        M ok_c;
        diffuse_coat_directions<F>(o, u, cc_alpha, where && is_d, where && is_cc, &wd, &wc, &ok_c);
        // Specular: a visible normal, reflected about (without transmission the reflection share is 1).
        V3<F> ws = up;
        M ok_s(false);
        if (lane::any(where && is_spec)) {
            const V3<F> ms = spec.sample_visible(o, u);
            ws = -o + F(2.f) * dot(o, ms) * ms;
            ok_s = M(gr) && ws.z * o.z > F(0.f);
        }
        const V3<F> wi = lane::select(is_d, wd, lane::select(is_cc, wc, ws));
        const M ok = where && o.z != F(0.f) && total > F(0.f) && (is_d || (is_cc && ok_c) || (is_spec && ok_s));
        const EvalPdf ep = eval_pdf(ctx, o, wi, ok);
        return reflection_sample_from_eval<F>(lane::select(flip, -wi, wi), ep.f, ep.pdf, ok, is_d);
    }
};

/// The path tracer's packet parameters of an opaque solid principled BSDF (kPrincipledParams floats):
/// 0–2 base, 3–5 c_tint, 6 metallic, 7 roughness, 8 specular_tint, 9 sheen, 10 sheen_tint,
/// 11 flatness, 12 clearcoat, 13 α_c, 14 ln α_c², 15 η, 16 αx, 17 αy, 18 w_brdf.
inline constexpr int kPrincipledParams = 19;
inline void principled_packet_params(const PrincipledBSDFT<float>& l, float* q) {
    for (int c = 0; c < 3; ++c) q[c] = l.base[c], q[3 + c] = l.tint[c];
    q[6] = l.metallic, q[7] = l.roughness, q[8] = l.spec_tint, q[9] = l.sheen, q[10] = l.sheen_tint;
    q[11] = l.flatness, q[12] = l.clearcoat, q[13] = l.cc_alpha, q[14] = l.cc_log_a2, q[15] = l.eta;
    q[16] = l.spec.ax, q[17] = l.spec.ay, q[18] = l.w_brdf;
}
/// The packet form from packet parameters q(k) on the lanes `where`; the other lanes (other models)
/// get a black diffuse material of α 1.
template <class F, class Q>
inline PrincipledBSDFT<F> principled_lanes(const MaskT<F>& where, Q q) {
    auto at = [&](int k, float other) { return lane::select(where, q(k), F(other)); };
    return {RGB<F>(at(0, 0.f), at(1, 0.f), at(2, 0.f)),
            RGB<F>(at(3, 1.f), at(4, 1.f), at(5, 1.f)),
            at(6, 0.f), at(7, 1.f), at(8, 0.f), at(9, 0.f), at(10, 0.f), at(11, 0.f), at(12, 0.f),
            at(13, 0.1f), at(14, -4.6051702f), at(15, 1.5f),
            at(18, 1.f),
            GGXT<F>{at(16, 1.f), at(17, 1.f), MaskT<F>(false)}};
}

/// The solid with a transmission lobe (header comment, SOLID; w_bsdf > 0) over a lane type F: the
/// opaque form's parameters and w_bsdf. PrincipledBSDF's eval, pdf and sample are its float
/// instantiation where neither has_lanes() nor thin(), and the path tracer shades such solids with it
/// (kPacketPrincipledSolid). The half vector, its Fresnel and the Jacobian's denominator are the
/// double-precision function's (principled_half), called a lane at a time; the rest is lane
/// operations.
template <class F>
struct PrincipledSolidT {
    PrincipledBSDFT<F> o;  ///< base … w_brdf, as the opaque form
    F w_bsdf;

    using EvalPdf = principled_detail::EvalPdf<F>;
    EvalPdf eval_pdf(const BxDFContext& ctx, const V3<F>& wo, const V3<F>& wi, const MaskT<F>& where) const {
        using namespace principled_detail;
        using M = MaskT<F>;
        const F co = wo.z, ci = wi.z;
        const M pair = co != F(0.f) && ci != F(0.f);
        const M front = co > F(0.f), reflect = co * ci > F(0.f);
        V3<F> h;
        F dot_o, dot_i, fr, denom, etap;
        M ok;
        principled_half_lanes<F>(wo, wi, o.eta, where && pair, &h, &dot_o, &dot_i, &fr, &denom, &etap, &ok);
        const F s = lane::select(front, F(1.f), F(-1.f));
        const M compatible = dot_o * s > F(0.f) && lane::select(reflect, dot_i * s > F(0.f), dot_i * s < F(0.f));
        // Lobe probabilities: the specular group split at h by F.
        const bool gr = allows(ctx, BxDFFlags::GlossyReflection), gt = allows(ctx, BxDFFlags::GlossyTransmission),
                   dr = allows(ctx, BxDFFlags::DiffuseReflection);
        const F pr = gr ? lane::select(front, F(1.f) - w_bsdf * (F(1.f) - fr), fr) : F(0.f);
        const F pt = lane::select(w_bsdf > F(0.f) && M(gt), lane::select(front, w_bsdf * (F(1.f) - fr), F(1.f) - fr), F(0.f));
        const F g_spec = lane::select(pr + pt > F(0.f), F(1.f), F(0.f));
        F p_cc = lane::select(front && o.clearcoat > F(0.f) && M(gr), F(0.25f) * o.clearcoat, F(0.f));
        F p_d = lane::select(front && o.w_brdf > F(0.f) && M(dr), o.w_brdf, F(0.f));
        const F total = g_spec + p_cc + p_d;
        const F inv_total = lane::select(total > F(0.f), F(1.f) / lane::select(total > F(0.f), total, F(1.f)), F(0.f));
        const M spec = g_spec > F(0.f);
        const F prt = lane::select(spec, pr + pt, F(1.f));
        const F p_r = lane::select(spec, pr / prt * inv_total, F(0.f));
        const F p_t = lane::select(spec, pt / prt * inv_total, F(0.f));
        p_cc = p_cc * inv_total;
        p_d = p_d * inv_total;

        const F aco = lane::abs(co), aci = lane::abs(ci);
        const F D = o.spec.D(h);
        const F G = lane::select(compatible, g1<F>(o.spec, wo, h) * g1<F>(o.spec, wi, h), F(0.f));
        const F vis = lane::select(compatible, o.spec.pdf_visible(wo, h), F(0.f));
        RGB<F> f(F(0.f));
        F pdf(F(0.f));
        // Reflection: the blended Fresnel (front) or the bare interface (back), the clear coat and
        // the diffuse and sheen (front).
        {
            const F jac = F(1.f) / (F(4.f) * lane::abs(dot_i));
            const M lobe = reflect && compatible && fr > F(0.f);
            RGB<F> Fp = lane::select(front, RGB<F>((F(1.f) - o.metallic) * (F(1.f) - o.spec_tint) * fr), RGB<F>(w_bsdf * fr));
            const M metal = front && o.metallic > F(0.f), tinted = front && o.spec_tint > F(0.f);
            if (lane::any(where && lobe && metal)) Fp = lane::select(metal, Fp + schlick<F>(o.base, dot_o, o.eta) * o.metallic, Fp);
            if (lane::any(where && lobe && tinted)) {
                const F eta_it = lane::select(dot_o >= F(0.f), o.eta, F(1.f) / o.eta);
                const F r = (eta_it - F(1.f)) / (eta_it + F(1.f));
                Fp = lane::select(tinted, Fp + schlick<F>(o.tint * (r * r), dot_o, o.eta) * ((F(1.f) - o.metallic) * o.spec_tint), Fp);
            }
            f = lane::select(lobe, f + Fp * (D * G / (F(4.f) * aco)), f);
            pdf = lane::select(reflect, pdf + p_r * vis * jac, pdf);
            const M cc = reflect && front && o.clearcoat > F(0.f);
            if (lane::any(where && cc)) {
                const F Dc = gtr1<F>(h.z, o.cc_alpha, o.cc_log_a2);
                const F Fc = schlick<F>(F(0.04f), dot_o, o.eta);
                const GGXT<F> coat{F(0.25f), F(0.25f), M(false)};
                const F fc = F(0.25f) * o.clearcoat * Fc * Dc * (g1<F>(coat, wo, h) * g1<F>(coat, wi, h)) * aci;
                f = lane::select(cc && compatible, f + RGB<F>(fc), f);
                pdf = lane::select(cc, pdf + p_cc * Dc * h.z * jac, pdf);
            }
            const M diffuse = reflect && front && o.w_brdf > F(0.f);
            if (lane::any(where && diffuse)) {
                const RGB<F> ds = diffuse_sheen<F>(o.base, o.tint, o.roughness, o.flatness, o.sheen, o.sheen_tint, aco, aci,
                                                   dot_i, o.w_brdf, F(1.f) - o.metallic, where && diffuse);
                f = lane::select(diffuse, f + ds, f);
            }
            pdf = lane::select(reflect && front, pdf + p_d * aci * F(kInvPi), pdf);
        }
        // Transmission: Walter et al. 2007, eq. 21 × |cos θi| (Radiance divides by η'²), tinted by
        // √base; its density by eq. 17.
        {
            const M lobe = !reflect && compatible && denom > F(0.f);
            const M on = lobe && w_bsdf > F(0.f) && fr < F(1.f);
            F ft = w_bsdf * (F(1.f) - fr) * D * G * etap * etap * lane::abs(dot_o * dot_i) / (aco * lane::select(lobe, denom, F(1.f)));
            if (ctx.mode == TransportMode::Radiance) ft = ft / (etap * etap);
            const RGB<F> sqrt_base(lane::sqrt(o.base.r), lane::sqrt(o.base.g), lane::sqrt(o.base.b));
            f = lane::select(on, f + sqrt_base * ft, f);
            pdf = lane::select(lobe, pdf + p_t * vis * etap * etap * lane::abs(dot_i) / lane::select(lobe, denom, F(1.f)), pdf);
        }
        EvalPdf out;
        out.f = lane::select(pair && ok, f, RGB<F>(F(0.f)));
        out.pdf = lane::select(pair && ok, pdf, F(0.f));
        return out;
    }
    /// Mitsuba's lobe choice (header comment) on the lanes `where` (others: not valid, weight and
    /// density 0).
    BxDFSampleT<F> sample(const BxDFContext& ctx, const V3<F>& wo, const F& u_lobe, const V2<F>& u, const MaskT<F>& where) const {
        using namespace principled_detail;
        using M = MaskT<F>;
        const F co = wo.z;
        const M front = co > F(0.f);
        const bool gr = allows(ctx, BxDFFlags::GlossyReflection), gt = allows(ctx, BxDFFlags::GlossyTransmission),
                   dr = allows(ctx, BxDFFlags::DiffuseReflection);
        const M spec_ok = M(gr) || (w_bsdf > F(0.f) && M(gt));
        const F g_spec = lane::select(spec_ok, F(1.f), F(0.f));
        const F p_cc = lane::select(front && o.clearcoat > F(0.f) && M(gr), F(0.25f) * o.clearcoat, F(0.f));
        const F p_d = lane::select(front && o.w_brdf > F(0.f) && M(dr), o.w_brdf, F(0.f));
        const F total = g_spec + p_cc + p_d;
        const F x = u_lobe * total;
        const M is_d = x < p_d, is_cc = !is_d && x < p_d + p_cc, is_spec = !is_d && !is_cc;
        const V3<F> up(F(0.f), F(0.f), F(1.f));
        V3<F> wd, wc;
        M ok_c;
        diffuse_coat_directions<F>(wo, u, o.cc_alpha, where && is_d, where && is_cc, &wd, &wc, &ok_c);
        V3<F> ws = up;
        M ok_s(false), refracted(false);
        F etap(1.f);
        if (lane::any(where && is_spec)) {
            const V3<F> m = o.spec.sample_visible(wo, u);
            const F fr = fresnel_dielectric<F>(dot(wo, m), o.eta);
            const F pr = gr ? lane::select(front, F(1.f) - w_bsdf * (F(1.f) - fr), fr) : F(0.f);
            const F pt = lane::select(w_bsdf > F(0.f) && M(gt), lane::select(front, w_bsdf * (F(1.f) - fr), F(1.f) - fr), F(0.f));
            const M any_lobe = pr + pt > F(0.f);
            const F v = lane::min((x - p_d - p_cc) / g_spec, F(kOneMinusEpsilon));
            const M refl = v * (pr + pt) < pr;
            const V3<F> wr = -wo + F(2.f) * dot(wo, m) * m;
            V3<F> wt;
            const M tir_free = refract<F>(wo, m, o.eta, &etap, &wt);
            refracted = !refl;
            ws = lane::select(refl, wr, wt);
            ok_s = any_lobe && lane::select(refl, wr.z * co > F(0.f), tir_free && wt.z * co < F(0.f));
        }
        const V3<F> wi = lane::select(is_d, wd, lane::select(is_cc, wc, ws));
        const M ok = where && co != F(0.f) && total > F(0.f) && (is_d || (is_cc && ok_c) || (is_spec && ok_s));
        const EvalPdf ep = eval_pdf(ctx, wo, wi, ok);
        BxDFSampleT<F> s;
        s.valid = ok && ep.pdf > F(0.f);
        s.wi = wi;
        s.pdf = lane::select(s.valid, ep.pdf, F(0.f));
        s.weight = lane::select(s.valid, ep.f / lane::select(s.valid, ep.pdf, F(1.f)), RGB<F>(F(0.f)));
        const M t = is_spec && refracted;
        s.eta = lane::select(s.valid && t, etap, F(1.f));
        s.lobe = lane::select(lane::int_mask(is_d), IntT<F>(int32_t(BxDFFlags::DiffuseReflection)),
                              lane::select(lane::int_mask(t), IntT<F>(int32_t(BxDFFlags::GlossyTransmission)),
                                           IntT<F>(int32_t(BxDFFlags::GlossyReflection))));
        return s;
    }
};
/// The path tracer's packet parameters of a solid with a transmission lobe (kPrincipledSolidParams
/// floats): the opaque form's (principled_packet_params), then 19 w_bsdf.
inline constexpr int kPrincipledSolidParams = 20;
inline void principled_solid_packet_params(const PrincipledSolidT<float>& l, float* q) {
    principled_packet_params(l.o, q);
    q[19] = l.w_bsdf;
}
/// The solid from packet parameters q(k) on the lanes `where` (other lanes: principled_lanes' and no
/// transmission).
template <class F, class Q>
inline PrincipledSolidT<F> principled_solid_lanes(const MaskT<F>& where, Q q) {
    return {principled_lanes<F>(where, q), lane::select(where, q(19), F(0.f))};
}

/// The thin sheet (header comment, THIN) over a lane type F: per-lane parameters. PrincipledBSDF's
/// eval, pdf and sample are its float instantiation where thin(), and the path tracer shades thin
/// sheets with it (kPacketPrincipledThin). Every operation is one IEEE operation per lane (the half
/// vector of the mirrored pair in float, the dielectric Fresnel fresnel_dielectric<F>), so every lane
/// type gives the same bits.
template <class F>
struct PrincipledThinT {
    RGB<F> base, tint;  ///< base colour and c_tint
    F roughness, spec_tint, sheen, sheen_tint, flatness, eta;
    F st, dt;           ///< spec_trans and d_t = diffuse_transmission/2
    GGXT<F> spec, trans;  ///< the reflection lobe's and the transmission lobe's (roughness × (0.65η − 0.35))

    using EvalPdf = principled_detail::EvalPdf<F>;
    /// The four lobes' probabilities (specular reflection, specular transmission, diffuse
    /// reflection, diffuse transmission; 0 for a lobe outside ctx.allowed), unnormalised.
    void lobes(const BxDFContext& ctx, F p[4]) const {
        using principled_detail::allows;
        p[0] = allows(ctx, BxDFFlags::GlossyReflection) ? F(0.5f) * st : F(0.f);
        p[1] = allows(ctx, BxDFFlags::GlossyTransmission) ? F(0.5f) * st : F(0.f);
        p[2] = allows(ctx, BxDFFlags::DiffuseReflection) ? (F(1.f) - st) * (F(1.f) - dt) : F(0.f);
        p[3] = allows(ctx, BxDFFlags::DiffuseTransmission) ? (F(1.f) - st) * dt : F(0.f);
    }
    /// f·|cos θi| and the density of sample(), on the lanes `where` (others: unspecified). The pair
    /// is mirrored together so that wo is on +z; transmission is reflection mirrored through the sheet.
    EvalPdf eval_pdf(const BxDFContext& ctx, const V3<F>& wo_in, const V3<F>& wi_in, const MaskT<F>& where) const {
        using namespace principled_detail;
        using M = MaskT<F>;
        const M pair = wo_in.z != F(0.f) && wi_in.z != F(0.f);
        const M flip = wo_in.z < F(0.f);
        const V3<F> wo = lane::select(flip, -wo_in, wo_in), wi = lane::select(flip, -wi_in, wi_in);
        const M reflect = wi.z > F(0.f);
        const F co = wo.z, aci = lane::abs(wi.z);
        const V3<F> wi_r(wi.x, wi.y, aci);
        const V3<F> h = normalize(wo + wi_r);
        const F dot_o = dot(wo, h), dot_ih = dot(wi, h);
        const F jac = F(1.f) / (F(4.f) * lane::abs(dot(wi_r, h)));
        F p[4];
        lobes(ctx, p);
        F total = p[0] + p[1] + p[2] + p[3];
        total = lane::select(total > F(0.f), total, F(1.f));
        const F fr = fresnel_dielectric<F>(dot_o, eta);
        RGB<F> f(F(0.f));
        F pdf(F(0.f));
        // Specular reflection, and where the sheet transmits, Mitsuba's visibility test for the
        // mirrored lobe: wo in front of h, wi behind it.
        const M spec_r = reflect && st > F(0.f) && dot_o > F(0.f);
        if (lane::any(where && spec_r)) {
            RGB<F> Ft(fr);
            const M tinted = spec_tint > F(0.f);
            if (lane::any(where && spec_r && tinted)) {
                const F r = (eta - F(1.f)) / (eta + F(1.f));
                const RGB<F> s = schlick<F>(tint * (r * r), dot_o, eta);
                const RGB<F> lerped(Ft.r + (s.r - Ft.r) * spec_tint, Ft.g + (s.g - Ft.g) * spec_tint,
                                    Ft.b + (s.b - Ft.b) * spec_tint);
                Ft = lane::select(tinted, lerped, Ft);
            }
            const F g = g1<F>(spec, wo, h) * g1<F>(spec, wi, h);
            f = lane::select(spec_r, f + Ft * (st * spec.D(h) * g / (F(4.f) * co)), f);
            pdf = lane::select(spec_r, pdf + p[0] / total * spec.pdf_visible(wo, h) * jac, pdf);
        }
        const M diff_r = reflect && st < F(1.f) && dt < F(1.f);
        if (lane::any(where && diff_r)) {
            const F w = (F(1.f) - st) * (F(1.f) - dt);
            const RGB<F> ds = diffuse_sheen<F>(base, tint, roughness, flatness, sheen, sheen_tint, co, aci, dot_ih, w, w,
                                               where && diff_r);
            f = lane::select(diff_r, f + ds, f);
        }
        pdf = lane::select(reflect, pdf + p[2] / total * aci * F(kInvPi), pdf);
        const M spec_t = !reflect && st > F(0.f) && dot_o > F(0.f) && dot_ih < F(0.f);
        if (lane::any(where && spec_t)) {
            const F g = g1<F>(trans, wo, h) * g1<F>(trans, wi, h);
            f = lane::select(spec_t, f + base * (st * (F(1.f) - fr) * trans.D(h) * g / (F(4.f) * co)), f);
            pdf = lane::select(spec_t, pdf + p[1] / total * trans.pdf_visible(wo, h) * jac, pdf);
        }
        const M diff_t = !reflect && st < F(1.f) && dt > F(0.f);
        f = lane::select(diff_t, f + base * ((F(1.f) - st) * dt * F(kInvPi) * aci), f);
        pdf = lane::select(!reflect, pdf + p[3] / total * aci * F(kInvPi), pdf);
        EvalPdf out;
        out.f = lane::select(pair, f, RGB<F>(F(0.f)));
        out.pdf = lane::select(pair, pdf, F(0.f));
        return out;
    }
    /// A lobe by its probability (the last positive one on round-off), its direction, then the whole
    /// model evaluated toward it, on the lanes `where` (others: not valid).
    BxDFSampleT<F> sample(const BxDFContext& ctx, const V3<F>& wo_in, const F& u_lobe, const V2<F>& u,
                          const MaskT<F>& where) const {
        using M = MaskT<F>;
        using I = IntT<F>;
        const F sgn = lane::select(wo_in.z < F(0.f), F(-1.f), F(1.f));
        const V3<F> wo(wo_in.x * sgn, wo_in.y * sgn, wo_in.z * sgn);
        F p[4];
        lobes(ctx, p);
        const F total = p[0] + p[1] + p[2] + p[3];
        F x = u_lobe * total;
        I lobe(-1);
        M chosen(false);
        for (int k = 0; k < 4; ++k) {
            const M take = !chosen && p[k] > F(0.f);
            lobe = lane::select(lane::int_mask(take), I(k), lobe);
            const M stop = take && x < p[k];
            chosen = chosen || stop;
            x = lane::select(take && !stop, x - p[k], x);
        }
        const M is_spec = lane::float_mask(lobe == I(0) || lobe == I(1)), is_t = lane::float_mask(lobe == I(1));
        const M diff = lane::float_mask(lobe == I(2) || lobe == I(3));
        const V3<F> up(F(0.f), F(0.f), F(1.f));
        // Specular: a visible normal of the lobe's distribution, reflected about; through the sheet,
        // unbent, for transmission (with eval's visibility test).
        V3<F> ws = up;
        M ok_s(false);
        if (lane::any(where && is_spec)) {
            const GGXT<F> d{lane::select(is_t, trans.ax, spec.ax), lane::select(is_t, trans.ay, spec.ay), MaskT<F>(false)};
            const V3<F> m = d.sample_visible(wo, u);
            const V3<F> r = -wo + F(2.f) * dot(wo, m) * m;
            ok_s = r.z > F(0.f) && dot(wo, m) > F(0.f);
            ws = V3<F>(r.x, r.y, lane::select(is_t, lane::neg(r.z), r.z));
            ok_s = ok_s && (!is_t || dot(ws, m) < F(0.f));
        }
        V3<F> wd = up;
        if (lane::any(where && diff)) {
            const V3<F> c = square_to_cosine_hemisphere<F>(u);
            wd = V3<F>(c.x, c.y, lane::select(lane::float_mask(lobe == I(3)), lane::neg(c.z), c.z));
        }
        const V3<F> wsel = lane::select(is_spec, ws, lane::select(diff, wd, up));  // (up: no lobe)
        const V3<F> wi(wsel.x * sgn, wsel.y * sgn, wsel.z * sgn);
        const M ok = where && wo_in.z != F(0.f) && total > F(0.f) && ((is_spec && ok_s) || diff);
        const EvalPdf ep = eval_pdf(ctx, wo_in, wi, ok);
        // (Lanes without a sample get weight and density 0: eval_pdf's terms outside `ok` are not
        // computed alike on every lane type.)
        BxDFSampleT<F> s;
        s.valid = ok && ep.pdf > F(0.f);
        s.wi = wi;
        s.pdf = lane::select(s.valid, ep.pdf, F(0.f));
        s.weight = lane::select(s.valid, ep.f / lane::select(s.valid, ep.pdf, F(1.f)), RGB<F>(F(0.f)));
        s.eta = F(1.f);
        s.lobe = lane::select(lobe == I(0), I(int32_t(BxDFFlags::GlossyReflection)),
                              lane::select(lobe == I(1), I(int32_t(BxDFFlags::GlossyTransmission)),
                                           lane::select(lobe == I(2), I(int32_t(BxDFFlags::DiffuseReflection)),
                                                        I(int32_t(BxDFFlags::DiffuseTransmission)))));
        return s;
    }
};

/// The path tracer's packet parameters of a thin sheet (kPrincipledThinParams floats): 0–2 base,
/// 3–5 c_tint, 6 roughness, 7 specular_tint, 8 sheen, 9 sheen_tint, 10 flatness, 11 η, 12
/// spec_trans, 13 d_t, 14–15 the reflection lobe's αx, αy, 16–17 the transmission lobe's.
inline constexpr int kPrincipledThinParams = 18;
inline void principled_thin_packet_params(const PrincipledThinT<float>& l, float* q) {
    for (int c = 0; c < 3; ++c) q[c] = l.base[c], q[3 + c] = l.tint[c];
    q[6] = l.roughness, q[7] = l.spec_tint, q[8] = l.sheen, q[9] = l.sheen_tint, q[10] = l.flatness, q[11] = l.eta;
    q[12] = l.st, q[13] = l.dt, q[14] = l.spec.ax, q[15] = l.spec.ay, q[16] = l.trans.ax, q[17] = l.trans.ay;
}
/// The thin sheet from packet parameters q(k) on the lanes `where`; the other lanes (other models)
/// get a black diffuse sheet of α 1.
template <class F, class Q>
inline PrincipledThinT<F> principled_thin_lanes(const MaskT<F>& where, Q q) {
    auto at = [&](int k, float other) { return lane::select(where, q(k), F(other)); };
    return {RGB<F>(at(0, 0.f), at(1, 0.f), at(2, 0.f)),
            RGB<F>(at(3, 1.f), at(4, 1.f), at(5, 1.f)),
            at(6, 1.f), at(7, 0.f), at(8, 0.f), at(9, 0.f), at(10, 0.f), at(11, 1.5f),
            at(12, 0.f), at(13, 0.f),
            GGXT<F>{at(14, 1.f), at(15, 1.f), MaskT<F>(false)},
            GGXT<F>{at(16, 1.f), at(17, 1.f), MaskT<F>(false)}};
}

class PrincipledBSDF {
public:
    /// Reads the 2015 fields of `p` (the `variant` field is not consulted). Scalars are clamped to
    /// their ranges ([0, 1]; diffuse_transmission [0, 2]; η > 0).
    explicit PrincipledBSDF(const PrincipledInputs& p = PrincipledInputs{});
    Spectrum eval(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const;
    float pdf(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const;
    std::optional<BxDFSample> sample(const BxDFContext& ctx, const Vec3f& wo, float u_lobe, const Vec2f& u) const;
    BxDFFlags flags() const;
    std::string to_string() const;

    float eta() const { return m_eta; }
    bool thin() const { return m_thin; }
    /// Whether the model is exactly its packet form: a solid without a transmission lobe.
    bool has_lanes() const { return !m_thin && !(m_w_bsdf > 0.f); }
    /// The packet form's parameters (PrincipledBSDFT<float>; meaningful where has_lanes()).
    PrincipledBSDFT<float> lanes() const {
        return {m_base,     m_tint,       m_metallic, m_roughness, m_spec_tint, m_sheen,
                m_sheen_tint, m_flatness, m_clearcoat, m_cc_alpha,  m_cc_log_a2, m_eta,
                m_w_brdf,   m_spec.lanes()};
    }
    /// The solid's packet form's parameters with its transmission lobe (PrincipledSolidT<float>;
    /// meaningful where neither has_lanes() nor thin()).
    PrincipledSolidT<float> solid_lanes() const { return {lanes(), m_w_bsdf}; }
    /// The thin sheet's packet form's parameters (PrincipledThinT<float>; meaningful where thin()).
    PrincipledThinT<float> thin_lanes() const {
        return {m_base,       m_tint,     m_roughness, m_spec_tint, m_sheen,        m_sheen_tint,
                m_flatness,   m_eta,      m_spec_trans, m_diff_trans, m_spec.lanes(), m_trans.lanes()};
    }
    const GGX& specular_distribution() const { return m_spec; }
    /// The thin sheet's transmission distribution (roughness × (0.65η − 0.35)).
    const GGX& thin_transmission_distribution() const { return m_trans; }

    /// η from `specular`: ((η − 1)/(η + 1))² = 0.08·specular ⇔ η = 2/(1 − √(0.08·specular)) − 1.
    static float eta_from_specular(float specular);
    /// α of the specular lobe (αx, αy) from roughness and anisotropic (header comment).
    static Vec2f alpha_from_roughness(float roughness, float anisotropic);
    /// Schlick's Fresnel with reflectance r0 at normal incidence, as a function of the cosine
    /// cos_i between the incident direction and the microfacet normal at an interface of
    /// relative IOR eta; when the incident side is the denser one the transmitted cosine is used
    /// (1 on total internal reflection).
    static float schlick(float r0, float cos_i, float eta);
    static Spectrum schlick(const Spectrum& r0, float cos_i, float eta);

private:
    Spectrum m_base, m_tint;  // base colour, c_tint
    float m_metallic, m_roughness, m_spec_trans, m_spec_tint, m_sheen, m_sheen_tint, m_flatness;
    float m_clearcoat, m_cc_alpha, m_cc_log_a2, m_diff_trans, m_eta;
    float m_w_brdf, m_w_bsdf;
    GGX m_spec, m_trans;
    bool m_thin;
};
}  // namespace pellucid
