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
#pragma once
#include <optional>
#include <string>

#include "pellucid/bxdf/bxdf_types.h"
#include "pellucid/bxdf/microfacet.h"
#include "pellucid/bxdf/principled.h"

namespace pellucid {

class PrincipledBSDF {
public:
    /// Reads the 2015 fields of `p` (the `variant` field is not consulted). Scalars are clamped to
    /// their ranges ([0, 1]; diffuse_transmission [0, 2]; η > 0).
    explicit PrincipledBSDF(const PrincipledParams& p = PrincipledParams{});
    Spectrum eval(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const;
    float pdf(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const;
    std::optional<BxDFSample> sample(const BxDFContext& ctx, const Vec3f& wo, float u_lobe, const Vec2f& u) const;
    BxDFFlags flags() const;
    std::string to_string() const;

    float eta() const { return m_eta; }
    bool thin() const { return m_thin; }
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
    struct EvalPdf {
        Spectrum f{0.f};
        float pdf = 0.f;
    };
    EvalPdf eval_pdf_solid(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const;
    EvalPdf eval_pdf_thin(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const;
    std::optional<BxDFSample> sample_solid(const BxDFContext& ctx, const Vec3f& wo, float u_lobe,
                                           const Vec2f& u) const;
    std::optional<BxDFSample> sample_thin(const BxDFContext& ctx, const Vec3f& wo, float u_lobe,
                                          const Vec2f& u) const;
    /// w_diffuse·(diffuse, retro-reflection, fake subsurface) + w_sheen·sheen for a reflected pair
    /// on the +z side, as f·ci.
    Spectrum diffuse_sheen(float co, float ci, float cos_d, float w_diffuse, float w_sheen) const;

    Spectrum m_base, m_sqrt_base, m_tint;  // base colour, √base, c_tint
    float m_metallic, m_roughness, m_spec_trans, m_spec_tint, m_sheen, m_sheen_tint, m_flatness;
    float m_clearcoat, m_cc_alpha, m_diff_trans, m_eta;
    float m_w_brdf, m_w_bsdf;
    GGX m_spec, m_trans;
    bool m_thin;
};
}  // namespace pellucid
