// Rough diffuse reflection: classic Oren–Nayar and the energy-preserving EON model.
// SPDX-License-Identifier: Apache-2.0
//
// variant = "classic": Oren & Nayar 1994, "Generalization of Lambert's Reflectance Model",
//   SIGGRAPH, eq. 30 (the "qualitative model"):
//     f = ρ/π (A + B max(0, cos(φi − φo)) sin α tan β),  α = max(θi, θo), β = min(θi, θo),
//     A = 1 − 0.5 σ²/(σ² + 0.33),  B = 0.45 σ²/(σ² + 0.09),  σ = facet slope std. dev. (radians).
//   Written without tan: cos(φi − φo) sin θi sin θo = wi·wo − cos θi cos θo =: s and
//   sin α tan β = sin θi sin θo / max(cos θi, cos θo), so the term is max(0, s)/max(cos θi, cos θo),
//   bounded by 1 and finite as cos θ → 0. Loses energy as σ grows (not energy-preserving).
// variant = "eon": Portsmouth, Kutz, Hill 2025, "EON: A practical energy-preserving rough diffuse
//   BRDF", JCGT 14(1) (adopted by OpenPBR). Single scattering is Fujii's improved Oren–Nayar
//     f_FON = ρ/π A_F (1 + r s/t),  t = max(μi, μo) if s > 0 else 1,  A_F = 1/(1 + (1/2 − 2/(3π)) r)
//   with roughness r ∈ [0, 1]; its white albedo is analytic (EON §3, verified by quadrature in
//   test_oren_nayar.cpp): E_F(μ) = A_F + (r A_F/π) G(μ),
//     G(μ) = sinθ (θ − sinθ cosθ) + 2/3 (sinθ (1 − sin³θ)/cosθ − sinθ),
//     Ē_F = A_F (1 + (2/3 − 28/(15π)) r),
//   and the multiple-scattering lobe (Kulla–Conty form, EON §4)
//     f_ms = ρ_ms/π (1 − E_F(μo)) (1 − E_F(μi)) / (1 − Ē_F),  ρ_ms = ρ² Ē_F / (1 − ρ (1 − Ē_F))
//   restores the lost energy exactly (white furnace = 1). Sampled by the cosine lobe (EON's LTC
//   sampler is not implemented; cosine sampling is unbiased, slightly noisier at high r).
// At σ = 0 (r = 0) both variants are exactly Lambertian (bit-identical eval/pdf/sample; tested).
//
// | parameter   | type     | default  | meaning                                           |
// |-------------|----------|----------|---------------------------------------------------|
// | reflectance | spectrum | 0.5      | ρ                                                 |
// | variant     | string   | "eon"    | "classic" or "eon"                                |
// | sigma       | float    | 0.3      | classic: slope std. dev. σ in radians, ≥ 0         |
// | roughness   | float    | 0.5      | eon: r ∈ [0, 1] (clamped)                          |
// The constructor takes σ in radians; scene files give `sigma` in DEGREES (material/diffuse.h).
// JSON: {"type": "oren_nayar", "reflectance": [0.7, 0.6, 0.5], "variant": "classic", "sigma": 23}
#pragma once
#include <optional>
#include <string>

#include "pellucid/bxdf/bxdf_types.h"
#include "pellucid/math/spherical.h"

namespace pellucid {

enum class OrenNayarVariant { Classic, EON };

class OrenNayar {
public:
    /// `roughness` is σ (radians) for Classic and r for EON.
    OrenNayar(const Spectrum& reflectance, float roughness, OrenNayarVariant variant = OrenNayarVariant::EON);

    Spectrum eval(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const;
    float pdf(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const;
    std::optional<BxDFSample> sample(const BxDFContext& ctx, const Vec3f& wo, float u_lobe, const Vec2f& u) const;
    BxDFFlags flags() const { return m_r.is_black() ? BxDFFlags::None : BxDFFlags::DiffuseReflection; }
    std::string to_string() const;

    /// EON: white directional albedo E_F(μ) of the FON single-scattering lobe and its average.
    static float eon_albedo(float mu, float r);
    static float eon_average_albedo(float r);

private:
    OrenNayarVariant m_variant;
    Spectrum m_r;
    float m_rough;
    float m_a, m_b;          // classic A, B; EON A_F, B_F = r A_F
    float m_eavg = 1.f;      // EON Ē_F
    Spectrum m_rho_ms{0.f};  // EON ρ_ms
};
}  // namespace pellucid
