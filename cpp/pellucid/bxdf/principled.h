// Disney "principled" BRDF (reflection only): Burley 2012, "Physically-Based Shading at Disney",
// SIGGRAPH course notes, §5 and Appendix B. One BxDF; sample() picks a lobe.
// SPDX-License-Identifier: Apache-2.0
//
//   f = (1 − metallic) [ base/π · F_d + F_sheen ] + D_s G_s F_s/(4 cos θo cos θi)
//       + ¼ clearcoat · D_c G_c F_c/(4 cos θo cos θi)
//   F_d     = (1 + (F_D90 − 1)(1 − cos θi)^5)(1 + (F_D90 − 1)(1 − cos θo)^5),
//             F_D90 = 0.5 + 2 roughness cos² θd                                   (§5.3, eq. 3)
//   F_sheen = sheen · lerp(1, C_tint, sheen_tint) · (1 − cos θd)^5                    (§5.5)
//   specular: anisotropic GGX, α = roughness², aspect = sqrt(1 − 0.9 anisotropic),
//             αx = max(1e-3, α/aspect), αy = max(1e-3, α·aspect)                      (§5.4)
//             F_s = Schlick(C_spec0), C_spec0 = lerp(0.08 specular lerp(1, C_tint, specular_tint),
//             base, metallic); G_s = height-correlated Smith (instead of Burley's separable G)
//   clearcoat: GTR1 (γ = 1) with α_c = lerp(0.1, 0.001, clearcoat_gloss), F_c = Schlick(0.04),
//             G_c = Smith GGX with α = 0.25                                         (§5.6, App. B)
// C_tint = base/luminance(base). Omitted: subsurface, transmission (the 2015 variant, principled_bsdf.h).
// Not energy-conserving in general: the retro-reflective diffuse exceeds ρ at grazing angles for
// high roughness (a documented property of the model); the property suite uses base ≤ 0.6.
//
// | parameter       | type     | default | meaning                          |
// |-----------------|----------|---------|----------------------------------|
// | base_color      | spectrum | 0.8     | albedo / metal colour            |
// | metallic        | float    | 0       | [0, 1]                           |
// | roughness       | float    | 0.5     | [0, 1], α = roughness²           |
// | specular        | float    | 0.5     | [0, 1] (0.5 ↔ F0 = 0.04)          |
// | specular_tint   | float    | 0       | [0, 1]                           |
// | sheen           | float    | 0       | [0, 1]                           |
// | sheen_tint      | float    | 0.5     | [0, 1]                           |
// | clearcoat       | float    | 0       | [0, 1]                           |
// | clearcoat_gloss | float    | 1       | [0, 1]                           |
// | anisotropic     | float    | 0       | [0, 1]                           |
// JSON: {"type": "principled", "base_color": [0.8, 0.2, 0.1], "metallic": 0.0, "roughness": 0.4,
//        "clearcoat": 1.0, "clearcoat_gloss": 0.9}
#pragma once
#include <cstdint>
#include <optional>
#include <string>

#include "pellucid/bxdf/bxdf_types.h"
#include "pellucid/bxdf/microfacet.h"

namespace pellucid {

/// Which Disney model: the 2012 BRDF (this file) or the 2015 BSDF (principled_bsdf.h).
enum class PrincipledVariant : uint8_t { Burley2012, Burley2015 };

/// Parameters of both models; the 2015 fields are read only by PrincipledBSDF.
struct PrincipledParams {
    Spectrum base_color{0.8f};
    float metallic = 0.f, roughness = 0.5f, specular = 0.5f, specular_tint = 0.f;
    float sheen = 0.f, sheen_tint = 0.5f, clearcoat = 0.f, clearcoat_gloss = 1.f, anisotropic = 0.f;
    // 2015 only.
    float specular_transmission = 0.f;  ///< [0, 1]: blends the dielectric BRDF toward rough glass
    float flatness = 0.f;               ///< [0, 1]: diffuse toward Hanrahan–Krueger subsurface
    float diffuse_transmission = 0.f;   ///< [0, 2], thin only: 0 all reflected, 2 all transmitted
    float eta = 0.f;                    ///< relative IOR; 0 = derived from `specular`
    PrincipledVariant variant = PrincipledVariant::Burley2012;
    bool thin = false;                  ///< 2015 thin sheet (principled_bsdf.h)
};

class Principled {
public:
    explicit Principled(const PrincipledParams& p = PrincipledParams{});
    Spectrum eval(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const;
    float pdf(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const;
    std::optional<BxDFSample> sample(const BxDFContext& ctx, const Vec3f& wo, float u_lobe, const Vec2f& u) const;
    BxDFFlags flags() const;
    std::string to_string() const;

    /// GTR1 ("Berry") distribution, Burley 2012 App. B eq. 4, normalised: ∫ D cos θh dω = 1.
    static float gtr1(float cos_h, float alpha);

private:
    // Lobe selection probabilities: diffuse(+sheen), specular, clearcoat.
    void lobe_probs(const BxDFContext& ctx, float p[3]) const;
    float lobe_pdf(int lobe, const Vec3f& o, const Vec3f& i) const;

    PrincipledParams m_p;
    Spectrum m_cspec0, m_csheen;
    GGX m_spec, m_cc_g{0.25f};
    float m_cc_alpha;
};
}  // namespace pellucid
