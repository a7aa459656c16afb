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
#include <type_traits>

#include "pellucid/bxdf/bxdf_types.h"
#include "pellucid/math/spherical.h"
#include "pellucid/sampling/warp.h"

namespace pellucid {

enum class OrenNayarVariant { Classic, EON };

/// EON: white directional albedo E_F(μ) of the FON single-scattering lobe at roughness r (in
/// double, with acos; rounded to float).
float eon_albedo(float mu, float r);

/// eon_albedo over a lane type F, one lane at a time (each lane exactly the float function): E_F at
/// μo and μi on the lanes `where`, 0 on the others.
template <class F>
inline void eon_albedo_lanes(const F& mu_o, const F& mu_i, const F& r, const MaskT<F>& where, F* eo, F* ei) {
    if constexpr (std::is_same_v<F, float>) {
        *eo = where ? eon_albedo(mu_o, r) : 0.f;
        *ei = where ? eon_albedo(mu_i, r) : 0.f;
    } else {
        constexpr int W = kLaneWidth<F>;
        alignas(64) float mo[W], mi[W], rr[W], o[W], i_[W];
        alignas(64) bool on[W];
        lane::store(mo, mu_o), lane::store(mi, mu_i), lane::store(rr, r), lane::store(on, where);
        for (int k = 0; k < W; ++k) {
            o[k] = on[k] ? eon_albedo(mo[k], rr[k]) : 0.f;
            i_[k] = on[k] ? eon_albedo(mi[k], rr[k]) : 0.f;
        }
        *eo = lane::load_as<F>(o), *ei = lane::load_as<F>(i_);
    }
}

/// Both variants over a lane type F (simd/lane.h), per lane: `classic` chooses the variant; a, b are
/// classic A, B or EON A_F, B_F; `rough` is σ or r; eavg is EON's Ē_F and rho_ms its ρ_ms (1 and 0
/// for classic). OrenNayar (the variant's alternative) is its float instantiation behind the scalar
/// BxDF API; the path tracer's packets use it directly. Only IEEE-exact lane operations run on the
/// packet (std::max's choice written as a select, so that signed zeros and NaNs pick as it does);
/// EON's albedo E_F is the float function, a lane at a time (eon_albedo_lanes).
template <class F>
struct OrenNayarT {
    RGB<F> r;
    F a, b, rough, eavg;
    RGB<F> rho_ms;
    MaskT<F> classic;

    /// std::max(x, y): y where x < y, else x.
    static F max_of(const F& x, const F& y) { return lane::select(x < y, y, x); }

    RGB<F> eval(const BxDFContext&, const V3<F>& wo, const V3<F>& wi) const {
        using M = MaskT<F>;
        const M same = wo.z * wi.z > F(0.f);
        const F co = lane::abs(wo.z), ci = lane::abs(wi.z);
        const F s = dot(wo, wi) - wo.z * wi.z;  // sin θi sin θo cos(φi − φo)
        const F cmax = max_of(max_of(co, ci), F(1e-7f));
        // Classic: max(0, s) / max(cos θi, cos θo); EON: s / t.
        const F term = lane::select(classic, max_of(F(0.f), s) / cmax, s / lane::select(s > F(0.f), cmax, F(1.f)));
        const RGB<F> f_ss = r * (F(kInvPi) * ci * (a + b * term));
        // EON's multiple-scattering lobe.
        const M ms = same && !classic && rough > F(0.f);
        RGB<F> f_eon = f_ss;
        if (lane::any(ms)) {
            F eo, ei;
            eon_albedo_lanes<F>(co, ci, rough, ms, &eo, &ei);
            const F m = (F(1.f) - eo) * (F(1.f) - ei) / max_of(F(1e-6f), F(1.f) - eavg);
            f_eon = lane::select(ms, f_ss + rho_ms * (F(kInvPi) * ci * max_of(F(0.f), m)), f_ss);
        }
        f_eon = RGB<F>(max_of(F(0.f), f_eon.r), max_of(F(0.f), f_eon.g), max_of(F(0.f), f_eon.b));  // clamp_zero
        return lane::select(same, lane::select(classic, f_ss, f_eon), RGB<F>(F(0.f)));
    }
    /// Cosine-weighted on wo's side.
    F pdf(const BxDFContext& ctx, const V3<F>& wo, const V3<F>& wi) const {
        if (!has_flag(ctx.allowed, BxDFFlags::DiffuseReflection)) return F(0.f);
        return lane::select(wo.z * wi.z > F(0.f), square_to_cosine_hemisphere_pdf<F>(V3<F>(wi.x, wi.y, lane::abs(wi.z))),
                            F(0.f));
    }
    /// Cosine-weighted about the normal on wo's side; at σ = 0 (r = 0) the weight is ρ exactly.
    BxDFSampleT<F> sample(const BxDFContext& ctx, const V3<F>& wo, const F& /*u_lobe*/, const V2<F>& u) const {
        BxDFSampleT<F> s;
        s.wi = square_to_cosine_hemisphere<F>(u);
        s.wi.z = lane::select(wo.z < F(0.f), lane::neg(s.wi.z), s.wi.z);
        s.pdf = square_to_cosine_hemisphere_pdf<F>(V3<F>(s.wi.x, s.wi.y, lane::abs(s.wi.z)));
        s.valid = wo.z != F(0.f) && s.pdf > F(0.f);
        if (!has_flag(ctx.allowed, BxDFFlags::Reflection)) s.valid = MaskT<F>(false);
        s.weight = lane::select(rough == F(0.f), r, eval(ctx, wo, s.wi) / s.pdf);
        s.eta = F(1.f);
        s.lobe = IntT<F>(int32_t(BxDFFlags::DiffuseReflection));
        return s;
    }
};

/// The path tracer's packet parameters of an Oren–Nayar material (kOrenNayarParams floats): 0–2 ρ,
/// 3 a, 4 b, 5 σ or r, 6 Ē_F, 7–9 ρ_ms, 10 classic (1 or 0).
inline constexpr int kOrenNayarParams = 11;
inline void oren_nayar_packet_params(const OrenNayarT<float>& l, float* q) {
    for (int c = 0; c < 3; ++c) q[c] = l.r[c], q[7 + c] = l.rho_ms[c];
    q[3] = l.a, q[4] = l.b, q[5] = l.rough, q[6] = l.eavg, q[10] = l.classic ? 1.f : 0.f;
}
/// The packet form from packet parameters q(k) on the lanes `where`; the other lanes (other models,
/// whose parameters are not Oren–Nayar's) get a black classic model.
template <class F, class Q>
inline OrenNayarT<F> oren_nayar_lanes(const MaskT<F>& where, Q q) {
    auto at = [&](int k, float other) { return lane::select(where, q(k), F(other)); };
    return {RGB<F>(at(0, 0.f), at(1, 0.f), at(2, 0.f)), at(3, 0.f), at(4, 0.f), at(5, 0.f), at(6, 1.f),
            RGB<F>(at(7, 0.f), at(8, 0.f), at(9, 0.f)), at(10, 1.f) != F(0.f)};
}

class OrenNayar {
public:
    /// `roughness` is σ (radians) for Classic and r for EON.
    OrenNayar(const Spectrum& reflectance, float roughness, OrenNayarVariant variant = OrenNayarVariant::EON);

    Spectrum eval(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const { return m_l.eval(ctx, wo, wi); }
    float pdf(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const { return m_l.pdf(ctx, wo, wi); }
    std::optional<BxDFSample> sample(const BxDFContext& ctx, const Vec3f& wo, float u_lobe, const Vec2f& u) const {
        return to_optional(m_l.sample(ctx, wo, u_lobe, u));
    }
    BxDFFlags flags() const { return m_l.r.is_black() ? BxDFFlags::None : BxDFFlags::DiffuseReflection; }
    std::string to_string() const;
    /// The packet form's parameters (OrenNayarT<float>).
    const OrenNayarT<float>& lanes() const { return m_l; }

    /// EON: white directional albedo E_F(μ) of the FON single-scattering lobe and its average.
    static float eon_albedo(float mu, float r) { return pellucid::eon_albedo(mu, r); }
    static float eon_average_albedo(float r);

private:
    OrenNayarVariant m_variant;
    OrenNayarT<float> m_l{};
};
}  // namespace pellucid
