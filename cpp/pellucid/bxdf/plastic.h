// Plastic: a dielectric coat (smooth or rough) over a Lambertian base, in three documented variants.
// SPDX-License-Identifier: Apache-2.0
//
// Notation: F(θ) the coat's dielectric Fresnel reflectance (η = int_ior/ext_ior), t(θ) the coat's
// transmittance seen from outside, R̄ the coat's internal diffuse reflectance (the fraction of
// diffuse light inside the coat that the coat sends back to the base). With the default smooth
// transmittance t(θ) = 1 − F(θ) and R̄ = F_dri = 1 − (1 − F_avg(η))/η², from the reciprocity of the
// interface: η² (1 − F_dri) = 1 − F_avg.
//
// variant = "coupled" (default; energy-conserving, reciprocal):
//   f_d(wo, wi) = Kd t(θi) t(θo) / (π η² (1 − Kd R̄)).
// Derivation: light refracts in with t(θi), meets the Lambertian base (albedo Kd), and each
// time the diffuse internal radiance meets the coat, 1 − R̄ of it escapes and R̄ returns to
// the base; summing the series gives Kd (1 − R̄)/(1 − Kd R̄) of escaping energy, distributed
// outside as t(θo) cos θo/(π η²) (radiance compression by η²). This is the model of
// Weidlich & Wilkie 2007, "Arbitrarily Layered Micro-Facet Surfaces" (GRAPHITE), §3, and of
// Mitsuba's "plastic" with nonlinear = true. Total albedo (smooth coat) = F(θo)·Ks + (1 − F(θo)) ·
// Kd (1 − F_dri)/(1 − Kd F_dri) ≤ 1, = 1 for Kd = Ks = 1 (tested).
// variant = "linear" (Mitsuba's plastic and roughplastic with their default nonlinear = false):
//   f_d(wo, wi) = Kd t(θi) t(θo) / (π η² (1 − R̄)),
// the coupled form with the base's own albedo left out of the internal bounces (Kd/(1 − R̄)
// instead of Kd/(1 − Kd R̄)): Kd is then the albedo of the base as seen through the coat, free of
// the colour shift (saturation) that repeated bounces on a coloured base give. Reciprocal. With the
// smooth coat and the exact F_dri its directional albedo is exactly
//   ρ(θo) = Ks F(θo) + Kd (1 − F(θo))
// (the diffuse part integrates to Kd (1 − F(θo)) (1 − F_avg)/(η² (1 − F_dri)) = Kd (1 − F(θo))), so it
// conserves energy for Kd, Ks ≤ 1 and is brighter than "coupled" for Kd < 1 (equal at Kd = 1).
// variant = "sum" (the lecture-notes plastic): f = Kd/π + Ks · coat(F), the Lambertian and the
// specular lobes simply added. Conserves energy only if max(Kd) + max(Ks) ≤ 1.
//
// coat_transmittance (rough_plastic only; "coupled" and "linear"):
//   "smooth" (default): t(θ) = 1 − F(θ) and R̄ = F_dri, the smooth interface's values, for any α.
//   "rough": t(μ) and R̄ of the rough coat itself, tabulated once per (distribution, α, shadowing,
//   η) by RoughCoatTable: t(μ) = ∫ D_wo(m) (1 − F(wo·m)) G2(wo, wt)/G1(wo) dm is the energy the
//   microfacet interface refracts into the coat from cos θo = μ (single scattering, masking of the
//   refracted direction included), and R̄ = 2∫₀¹ R_int(μ) μ dμ with R_int the interface's
//   single-scattering reflectance seen from inside (relative IOR 1/η). What the rough coat does
//   not reflect at grazing angles then reaches the base (the smooth form loses it). This is the
//   model of Mitsuba's roughplastic (whose table is the same quantity; see RoughCoatTable). As α → 0
//   both tend to the smooth values (tested). The coupled variant stays energy-conserving and both
//   stay reciprocal (a single-scattering coat only loses energy: R_coat(θ) + t(θ) ≤ 1).
//
// | parameter            | type     | default  | meaning                                    |
// |----------------------|----------|----------|--------------------------------------------|
// | int_ior, ext_ior     | float/str| 1.49, air| coat IOR (η = int_ior/ext_ior)             |
// | diffuse_reflectance  | spectrum | 0.5      | base albedo Kd                             |
// | specular_reflectance | spectrum | 1        | coat multiplier Ks                         |
// | variant              | string   | coupled  | "coupled", "linear" or "sum"               |
// | distribution, alpha  |          | ggx, 0.1 | rough coat only ("rough_plastic")          |
// | shadowing            | string   | height_correlated | rough coat only: Smith G form (microfacet.h) |
// | coat_transmittance   | string   | smooth   | rough coat only: "smooth" or "rough"       |
// JSON: {"type": "rough_plastic", "diffuse_reflectance": [0.1, 0.3, 0.6], "int_ior": "polypropylene",
//        "distribution": "ggx", "alpha": 0.2, "variant": "linear", "coat_transmittance": "rough"}
//
// Packet forms: SmoothPlasticT<F> and RoughPlasticT<F, Distribution> write both plastics once over
// a lane type F (simd/lane.h), every variant and both coat transmittances; the path tracer shades
// untextured plastics with them (kPacketPlastic; over Beckmann kPacketPlasticBeckmann;
// integrator/path_services.h), and
// SmoothPlastic and RoughPlastic call their float instantiations, so each model is one source. A
// lane's variant and transmittance live in its parameters (PlasticBaseT::coat); the rough table is
// read by a gather from the tables of the whole scene (PathSetup::coat_tables).
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "pellucid/bxdf/bxdf_types.h"
#include "pellucid/bxdf/conductor.h"
#include "pellucid/bxdf/fresnel.h"
#include "pellucid/bxdf/microfacet.h"
#include "pellucid/sampling/warp.h"

namespace pellucid {

enum class PlasticVariant { Coupled, Sum, Linear };
std::string to_string(PlasticVariant v);
enum class CoatTransmittance { Smooth, Rough };
std::string to_string(CoatTransmittance c);

/// The diffuse base's scale of one channel of Kd (PlasticBaseT::scale): Kd / (η² (1 − bounce)),
/// bounce = Kd·R̄ (coupled) or R̄ (linear), the denominator at least 1e-6·η²; Kd itself for the sum
/// variant. Over a lane type F: PlasticBase computes it for its constants, the path tracer's packet
/// pass for a texture's value at each lane (PathSetup::tex_lanes).
template <class F>
inline F plastic_diffuse_scale(const F& kd, float eta, float rbar, PlasticVariant variant) {
    if (variant == PlasticVariant::Sum) return kd;
    const F bounce = variant == PlasticVariant::Coupled ? kd * F(rbar) : F(rbar);
    return kd / (F(eta) * F(eta) * lane::max(F(1e-6f), F(1.f) - bounce));
}

/// Entries of a rough coat's transmittance table (RoughCoatTable).
constexpr int kCoatTableSize = 64;

/// t(μ) read from the kCoatTableSize values t[base + j] at μ_j = j/63 by linear interpolation
/// (RoughCoatTable::transmittance), over a lane type F: each lane reads its own table, by a gather.
/// μ is clamped to [0, 1]; the index is formed without a float-to-int conversion (floor, then the
/// bits of floor + 2²³), so float and packets compute it with the same exact operations.
template <class F>
inline F coat_table_lookup(const float* t, const IntT<F>& base, const F& mu) {
    using I = IntT<F>;
    const F x = lane::min(lane::max(mu, F(0.f)), F(1.f)) * F(float(kCoatTableSize - 1));
    const F two23(8388608.f);
    const I i = lane::max(lane::min(lane::as_int(lane::floor(x) + two23) - lane::as_int(two23), I(kCoatTableSize - 2)), I(0));
    const F f = x - lane::to_float(i);
    const F t0 = lane::gather(t, base + i), t1 = lane::gather(t + 1, base + i);
    return t0 + f * (t1 - t0);
}

/// The transmittance t(μ) and internal diffuse reflectance R̄ of a rough dielectric coat (header
/// comment, coat_transmittance = "rough"), for one (distribution, α, shadowing, η).
///
/// Table: kSize = 64 values t(μ_j) at μ_j = max(1e-6, j/63), read by linear interpolation (the
/// nodes of Mitsuba 3's roughplastic table, so both renderers' interpolation errors coincide).
/// Each t(μ_j) is a 32 × 32 Gauss–Legendre product rule over the visible-normal sample space
/// [0, 1]² (wm = sample_visible(wo, u), so the integrand is the per-normal weight (1 − F) G2/G1;
/// Heitz 2018, JCGT 7(4), §1), and R̄ the same rule for R_int at 32 Gauss–Legendre nodes in μ,
/// split at the critical cosine of the smooth interior (where R_int has a kink as α → 0).
/// An anisotropic coat (αx ≠ αy) is averaged over the azimuth of the direction (8 azimuths; the table
/// depends on θ only, which keeps the diffuse lobe reciprocal).
/// Accuracy (measured, test_plastic.cpp): a 128 × 128 composite rule moves t by < 2e-4 and R̄ by
/// < 4e-4 (α ≤ 0.3); at α = 1e-4 the nodes μ_j ≥ 1/63 are within 3e-5 of 1 − F and R̄ within 1e-5
/// of F_dri; linear interpolation adds up to 7e-4 for η > 1. For η < 1 (a coat less dense than
/// the outside) 1 − F has a √ onset at the critical cosine that 64 linear segments resolve poorly
/// for small α (an interpolation error up to 0.29 next to it).
///
/// Built once: get() returns a table from a process-wide cache keyed by the distribution kind,
/// α (x, y), shadowing and η, computing it on the first request, outside the cache's lock. Entries
/// are never freed (about 300 bytes each; a process
/// builds one per distinct rough coat), so the pointers BxDFs hold stay valid for the whole run.
/// Materials resolve the pointer once at scene build; a BxDF rebuilt per hit (textured Kd) is
/// handed the same pointer and only compares the key (RoughPlastic's constructor), so no hit
/// computes, locks or allocates. α or η varying per hit would need a table per hit: the material
/// builder rejects a textured α, roughness or IOR with coat_transmittance = "rough".
class RoughCoatTable {
public:
    static constexpr int kSize = kCoatTableSize;
    enum class Kind : uint8_t { GGX, Beckmann };

    /// The table of distribution d under a coat of relative IOR eta (cached; thread-safe).
    template <class Distribution>
    static const RoughCoatTable& get(const Distribution& d, float eta);
    /// Built for exactly this distribution and η (compares the key, bit for bit).
    template <class Distribution>
    bool matches(const Distribution& d, float eta) const { return key_of(d, eta) == m_key; }

    /// t(μ), μ = |cos θ| ∈ [0, 1], linearly interpolated.
    float transmittance(float mu) const;
    /// R̄ = 2∫₀¹ R_int(μ) μ dμ.
    float internal_reflectance() const { return m_rbar; }
    /// The kSize values t(μ_j) (coat_table_lookup reads them).
    const float* values() const { return m_t; }

    struct Key {
        Kind kind;
        SmithShadowing shadowing;
        float alpha_x, alpha_y, eta;
        bool operator<(const Key& o) const;
        bool operator==(const Key& o) const {
            return kind == o.kind && shadowing == o.shadowing && alpha_x == o.alpha_x && alpha_y == o.alpha_y &&
                   eta == o.eta;
        }
    };
    /// Computes the table (no caching): used by get() and by the tests.
    template <class Distribution>
    static RoughCoatTable compute(const Distribution& d, float eta);

private:
    template <class Distribution>
    static Key key_of(const Distribution& d, float eta) {
        Kind k = std::is_same_v<Distribution, GGX> ? Kind::GGX : Kind::Beckmann;
        return Key{k, d.shadowing(), d.alpha_x(), d.alpha_y(), eta};
    }
    Key m_key{};
    float m_t[kSize] = {};
    float m_rbar = 0.f;
};

/// The plastics over a lane type F (simd/lane.h): per-lane parameters of the base and the coat.
/// PlasticBase below fills the float instantiation once per BxDF; the path tracer loads a packet of
/// them per vertex (plastic_lanes).
class PlasticBase;

template <class F>
struct PlasticBaseT {
    /// `coat` values that are not a table offset.
    static constexpr float kSumCoat = -2.f;     ///< variant "sum": t ≡ 1 (no coupling through the coat)
    static constexpr float kSmoothCoat = -1.f;  ///< the smooth coat's t = 1 − F

    F eta;
    RGB<F> scale;      ///< the diffuse lobe's factor: coupled Kd/(η² (1 − Kd R̄)), linear Kd/(η² (1 − R̄)), sum Kd
    RGB<F> ks;         ///< specular_reflectance
    F ks_avg, kd_avg;  ///< Ks and Kd averaged over the channels (the coat lobe's probability)
    F coat;            ///< kSumCoat, kSmoothCoat, or the offset (≥ 0) of the lane's rough table in `tables`
    const float* tables = nullptr;

    /// t(μ) (header comment), given the coat's Fresnel reflectance fr = F(μ).
    F transmittance(const F& mu, const F& fr) const {
        F t = lane::select(coat == F(kSmoothCoat), F(1.f) - fr, F(1.f));
        return rough_table(mu, t);
    }
    F transmittance(const F& mu) const {
        const auto smooth = coat == F(kSmoothCoat);
        F t(1.f);
        if (lane::any(smooth)) t = lane::select(smooth, F(1.f) - fresnel_dielectric<F>(mu, eta), t);
        return rough_table(mu, t);
    }
    /// f_d·|cos θi| of the header comment at cos θi = ci, given t_o = t(cos θo) (both > 0).
    RGB<F> diffuse(const F& t_o, const F& ci) const {
        const F t = transmittance(ci) * t_o;
        return scale * (t * F(kInvPi) * ci);
    }
    /// The probability of the coat lobe, ∝ F·Ks against t·Kd (t = 1 for "sum"), from fr = F(cos θo)
    /// and t_o = t(cos θo). With the rough table, F rather than 1 − t (which also counts the coat's
    /// masking losses, and is > 0 even at η = 1 where the coat reflects nothing).
    F coat_probability(const F& fr, const F& t_o) const {
        const F s = fr * ks_avg, d = t_o * kd_avg;
        const F sd = s + d;
        const auto pos = sd > F(0.f);
        return lane::select(pos, s / lane::select(pos, sd, F(1.f)), F(0.f));
    }
    F coat_probability(const F& co) const {
        const F fr = fresnel_dielectric<F>(co, eta);
        return coat_probability(fr, transmittance(co, fr));
    }

private:
    // t where the lane has a rough table, else t_other.
    F rough_table(const F& mu, const F& t_other) const {
        const auto tab = coat >= F(0.f);
        if (!lane::any(tab)) return t_other;
        const F two23(8388608.f);  // an integral offset's bits, as in coat_table_lookup
        const IntT<F> base = lane::as_int(lane::select(tab, coat, F(0.f)) + two23) - lane::as_int(two23);
        return lane::select(tab, coat_table_lookup<F>(tables, base, mu), t_other);
    }
};

/// The smooth plastic over a lane type F: a mirror coat lobe chosen with probability
/// coat_probability, else the cosine-weighted base. SmoothPlastic is its float instantiation.
template <class F>
struct SmoothPlasticT {
    PlasticBaseT<F> base;

    RGB<F> eval(const BxDFContext&, const V3<F>& wo, const V3<F>& wi) const {
        const auto same = wo.z * wi.z > F(0.f);
        return lane::select(same, base.diffuse(base.transmittance(lane::abs(wo.z)), lane::abs(wi.z)), RGB<F>(F(0.f)));
    }
    F pdf(const BxDFContext& ctx, const V3<F>& wo, const V3<F>& wi) const {
        if (!has_flag(ctx.allowed, BxDFFlags::DiffuseReflection)) return F(0.f);
        const F p_coat = has_flag(ctx.allowed, BxDFFlags::Specular) ? base.coat_probability(lane::abs(wo.z)) : F(0.f);
        return diffuse_pdf(p_coat, wo, wi);
    }
    BxDFSampleT<F> sample(const BxDFContext& ctx, const V3<F>& wo, const F& u_lobe, const V2<F>& u) const {
        const bool spec_ok = has_flag(ctx.allowed, BxDFFlags::Specular), diff_ok = has_flag(ctx.allowed, BxDFFlags::Diffuse);
        const F co = lane::abs(wo.z);
        const F fr = fresnel_dielectric<F>(co, base.eta), t_o = base.transmittance(co, fr);
        const F p_coat = spec_ok ? (diff_ok ? base.coat_probability(fr, t_o) : F(1.f)) : F(0.f);
        const auto coat = u_lobe < p_coat;
        // The coat's mirror: weight Ks F / p_coat.
        const V3<F> wr(lane::neg(wo.x), lane::neg(wo.y), wo.z);
        const RGB<F> w_r = base.ks * (fr / lane::select(coat, p_coat, F(1.f)));
        // The base: cosine-weighted on wo's side, weight f·|cos θi| / pdf.
        V3<F> wd = square_to_cosine_hemisphere<F>(u);
        wd.z = lane::select(wo.z < F(0.f), lane::neg(wd.z), wd.z);
        const F pdf_d = diffuse_pdf(p_coat, wo, wd);
        const auto ok_d = pdf_d > F(0.f);
        const RGB<F> f_d = lane::select(wo.z * wd.z > F(0.f), base.diffuse(t_o, lane::abs(wd.z)), RGB<F>(F(0.f)));
        BxDFSampleT<F> s;
        s.valid = wo.z != F(0.f) && (coat || (ok_d && MaskT<F>(diff_ok)));
        if (!has_flag(ctx.allowed, BxDFFlags::Reflection)) s.valid = MaskT<F>(false);
        s.wi = lane::select(coat, wr, wd);
        s.pdf = lane::select(coat, p_coat, pdf_d);
        s.weight = lane::select(coat, w_r, f_d / lane::select(ok_d, pdf_d, F(1.f)));
        s.eta = F(1.f);
        s.lobe = lane::select(lane::int_mask(coat), IntT<F>(int32_t(BxDFFlags::SpecularReflection)),
                              IntT<F>(int32_t(BxDFFlags::DiffuseReflection)));
        return s;
    }
    /// The base's share of the density, (1 − p_coat) |cos θi|/π, on wo's side.
    static F diffuse_pdf(const F& p_coat, const V3<F>& wo, const V3<F>& wi) {
        return lane::select(wo.z * wi.z > F(0.f), (F(1.f) - p_coat) * lane::abs(wi.z) * F(kInvPi), F(0.f));
    }
};

/// The rough plastic over a lane type F and a distribution Dist (GGXT<F>; any type with D, G,
/// pdf_visible and sample_visible over V3<F>): the coat's Torrance–Sparrow lobe with the dielectric
/// Fresnel term plus the base, each sampled with its probability. Lanes whose coat is effectively
/// smooth take SmoothPlasticT's lobes (conductor.h rule). RoughPlastic is its float instantiation.
template <class F, class Dist>
struct RoughPlasticT {
    PlasticBaseT<F> base;
    Dist d;
    MaskT<F> smooth;  ///< the distribution is effectively smooth

    RGB<F> eval(const BxDFContext& ctx, const V3<F>& wo, const V3<F>& wi) const {
        RGB<F> f(F(0.f));
        if (lane::any(!smooth)) {
            const F co = lane::abs(wo.z);
            f = rough_eval(wo, wi, base.transmittance(co));
        }
        if (lane::any(smooth)) f = lane::select(smooth, SmoothPlasticT<F>{base}.eval(ctx, wo, wi), f);
        return f;
    }
    F pdf(const BxDFContext& ctx, const V3<F>& wo, const V3<F>& wi) const {
        F p(0.f);
        if (lane::any(!smooth)) {
            const bool spec_ok = has_flag(ctx.allowed, BxDFFlags::Glossy), diff_ok = has_flag(ctx.allowed, BxDFFlags::Diffuse);
            const F p_coat = spec_ok ? (diff_ok ? base.coat_probability(lane::abs(wo.z)) : F(1.f)) : F(0.f);
            p = mixture_pdf(p_coat, diff_ok, wo, wi, coat_pdf(ctx, wo, wi));
        }
        if (lane::any(smooth)) p = lane::select(smooth, SmoothPlasticT<F>{base}.pdf(ctx, wo, wi), p);
        return p;
    }
    /// eval and pdf in one pass: the coat's D(wm) and Λ(o) and the Fresnel term at θo once; the
    /// same bits as the two calls.
    EvalPdfT<F> eval_pdf(const BxDFContext& ctx, const V3<F>& wo, const V3<F>& wi) const {
        EvalPdfT<F> out{RGB<F>(F(0.f)), F(0.f)};
        if (lane::any(!smooth)) {
            const bool spec_ok = has_flag(ctx.allowed, BxDFFlags::Glossy), diff_ok = has_flag(ctx.allowed, BxDFFlags::Diffuse);
            const F co = lane::abs(wo.z);
            const F fr = fresnel_dielectric<F>(co, base.eta), t_o = base.transmittance(co, fr);
            RGB<F> coat;
            F pc;
            coat_eval_pdf(ctx, wo, wi, &coat, &pc);
            out.f = with_base(coat, wo, wi, t_o);
            const F p_coat = spec_ok ? (diff_ok ? base.coat_probability(fr, t_o) : F(1.f)) : F(0.f);
            out.pdf = mixture_pdf(p_coat, diff_ok, wo, wi, pc);
        }
        if (lane::any(smooth)) {
            const SmoothPlasticT<F> sp{base};
            out.f = lane::select(smooth, sp.eval(ctx, wo, wi), out.f);
            out.pdf = lane::select(smooth, sp.pdf(ctx, wo, wi), out.pdf);
        }
        return out;
    }
    BxDFSampleT<F> sample(const BxDFContext& ctx, const V3<F>& wo, const F& u_lobe, const V2<F>& u) const {
        BxDFSampleT<F> s{};  // initialised: where every lane is smooth the merge below reads it unset
        if (lane::any(!smooth)) {
            const bool spec_ok = has_flag(ctx.allowed, BxDFFlags::Glossy), diff_ok = has_flag(ctx.allowed, BxDFFlags::Diffuse);
            const F co = lane::abs(wo.z);
            const F fr = fresnel_dielectric<F>(co, base.eta), t_o = base.transmittance(co, fr);
            const F p_coat = spec_ok ? (diff_ok ? base.coat_probability(fr, t_o) : F(1.f)) : F(0.f);
            const auto coat = u_lobe < p_coat;
            // The coat: a visible normal, reflected about (math/spherical.h reflect).
            const auto flip = wo.z < F(0.f);
            const V3<F> o = lane::select(flip, -wo, wo);
            const V3<F> m = d.sample_visible(o, u);
            const V3<F> i = -o + F(2.f) * dot(o, m) * m;
            // The base: cosine-weighted on wo's side.
            V3<F> wd = square_to_cosine_hemisphere<F>(u);
            wd.z = lane::select(flip, lane::neg(wd.z), wd.z);
            s.wi = lane::select(coat, lane::select(flip, -i, i), wd);
            RGB<F> fc;
            F pc;
            coat_eval_pdf(ctx, wo, s.wi, &fc, &pc);
            s.pdf = mixture_pdf(p_coat, diff_ok, wo, s.wi, pc);
            s.valid = wo.z != F(0.f) && lane::select(coat, i.z > F(0.f) && pc > F(0.f), MaskT<F>(diff_ok)) && s.pdf > F(0.f);
            if (!has_flag(ctx.allowed, BxDFFlags::Reflection)) s.valid = MaskT<F>(false);
            s.weight = with_base(fc, wo, s.wi, t_o) / lane::select(s.valid, s.pdf, F(1.f));
            s.eta = F(1.f);
            s.lobe = lane::select(lane::int_mask(coat), IntT<F>(int32_t(BxDFFlags::GlossyReflection)),
                                  IntT<F>(int32_t(BxDFFlags::DiffuseReflection)));
        }
        if (lane::any(smooth)) {
            const BxDFSampleT<F> t = SmoothPlasticT<F>{base}.sample(ctx, wo, u_lobe, u);
            s.valid = lane::select(smooth, t.valid, s.valid);
            s.wi = lane::select(smooth, t.wi, s.wi);
            s.weight = lane::select(smooth, t.weight, s.weight);
            s.pdf = lane::select(smooth, t.pdf, s.pdf);
            s.eta = lane::select(smooth, t.eta, s.eta);
            s.lobe = lane::select(lane::int_mask(smooth), t.lobe, s.lobe);
        }
        return s;
    }

private:
    // The coat's Torrance–Sparrow lobe (f·|cos θi|) and density (Walter et al. 2007, eqs. 20 and 14;
    // MicrofacetReflection's), 0 off wo's hemisphere.
    RGB<F> coat_eval(const V3<F>& wo, const V3<F>& wi) const {
        const ReflectionPairT<F> r(wo, wi);
        const RGB<F> f = base.ks * fresnel_dielectric<F>(dot(r.o, r.wm), base.eta) * r.torrance_sparrow_cos(d);
        return lane::select(r.ok, f, RGB<F>(F(0.f)));
    }
    F coat_pdf(const BxDFContext& ctx, const V3<F>& wo, const V3<F>& wi) const {
        if (!has_flag(ctx.allowed, BxDFFlags::GlossyReflection)) return F(0.f);
        return ReflectionPairT<F>(wo, wi).pdf(d);
    }
    // coat_eval and coat_pdf together (ReflectionPairT::torrance_sparrow_cos_pdf): the same bits.
    void coat_eval_pdf(const BxDFContext& ctx, const V3<F>& wo, const V3<F>& wi, RGB<F>* f, F* pdf) const {
        const ReflectionPairT<F> r(wo, wi);
        F ts, p;
        r.torrance_sparrow_cos_pdf(d, &ts, &p);
        *f = lane::select(r.ok, base.ks * fresnel_dielectric<F>(dot(r.o, r.wm), base.eta) * ts, RGB<F>(F(0.f)));
        *pdf = has_flag(ctx.allowed, BxDFFlags::GlossyReflection) ? p : F(0.f);
    }
    // Coat plus base (f·|cos θi|), given t_o = t(|cos θo|).
    RGB<F> rough_eval(const V3<F>& wo, const V3<F>& wi, const F& t_o) const { return with_base(coat_eval(wo, wi), wo, wi, t_o); }
    // The coat's value (coat_eval's) plus the base, 0 off wo's hemisphere.
    RGB<F> with_base(const RGB<F>& coat, const V3<F>& wo, const V3<F>& wi, const F& t_o) const {
        const auto same = wo.z * wi.z > F(0.f);
        return lane::select(same, coat + base.diffuse(t_o, lane::abs(wi.z)), RGB<F>(F(0.f)));
    }
    // p_coat · pdf_coat + (1 − p_coat) |cos θi|/π (the latter when the base may be sampled).
    static F mixture_pdf(const F& p_coat, bool diff_ok, const V3<F>& wo, const V3<F>& wi, const F& pdf_coat) {
        const F p = lane::select(p_coat > F(0.f), p_coat * pdf_coat, F(0.f));
        const F q = p + (diff_ok ? (F(1.f) - p_coat) * lane::abs(wi.z) * F(kInvPi) : F(0.f));
        return lane::select(wo.z * wi.z > F(0.f), q, F(0.f));
    }
};

/// A plastic's packet parameters (PathSetup::packet_params, kPacketPlastic), kPlasticParams floats
/// into q: η, the diffuse scale (3), Ks (3), Ks and Kd averaged, αx, αy with the sign bit set for
/// separable shadowing (0 and 0 for a smooth coat: d null), and PlasticBaseT::coat, where a rough
/// coat's table is the offset of its values in *tables (appended there unless an equal table is
/// there already). plastic_lanes reads them back; the GGX rough form covers both plastics, as a
/// lane whose α is effectively smooth is the smooth plastic.
constexpr int kPlasticParams = 12;
/// Where among them PlasticBaseT::coat is (the rough coat table's offset, or kSumCoat/kSmoothCoat).
constexpr int kPlasticCoatParam = 11;
/// d: the rough coat's αx, αy and shadowing (GGXT or BeckmannT alike), or null for the smooth coat.
/// coat_offset: where the rough coat's table is already among the tables, its offset (tables is then
/// not read, and may be null).
void plastic_packet_params(const PlasticBase& base, const GGXT<float>* d, std::vector<float>* tables, float* q,
                           const float* coat_offset = nullptr);
/// The packet of plastics whose parameters load(k) gives (k < kPlasticParams), on the lanes of
/// `where` (other lanes get the smooth coat and no table, so they read no table and skip the rough
/// lobe where no lane has one).
/// DistT: the rough coat's lane distribution (GGXT, or BeckmannT for kPacketPlasticBeckmann).
template <class F, template <class> class DistT = GGXT, class Load>
inline RoughPlasticT<F, DistT<F>> plastic_lanes(const MaskT<F>& where, const Load& load, const float* tables) {
    const F ax = load(9), ay_signed = load(10), ay = lane::abs(ay_signed);
    const MaskT<F> smooth = !where || lane::max(ax, ay) < F(microfacet_detail::kSmoothAlpha);
    PlasticBaseT<F> b{load(0),
                      RGB<F>(load(1), load(2), load(3)),
                      RGB<F>(load(4), load(5), load(6)),
                      load(7),
                      load(8),
                      lane::select(where, load(kPlasticCoatParam), F(PlasticBaseT<F>::kSumCoat)),
                      tables};
    // (A distribution's α is at least kMinAlpha, so the sign is that of a non-zero number.)
    return {b, DistT<F>{lane::select(smooth, F(1.f), ax), lane::select(smooth, F(1.f), ay), ay_signed < F(0.f)}, smooth};
}

/// The distribution as the packet forms' float instantiation takes it: GGX as GGXT<float>, Beckmann
/// as BeckmannT<float>.
template <class D>
struct LaneDistribution {
    using type = D;
    static const D& of(const D& d) { return d; }
};
template <>
struct LaneDistribution<GGX> {
    using type = GGXT<float>;
    static GGXT<float> of(const GGX& d) { return d.lanes(); }
};
template <>
struct LaneDistribution<Beckmann> {
    using type = BeckmannT<float>;
    static BeckmannT<float> of(const Beckmann& d) { return d.lanes(); }
};

/// The Lambertian base under the coat, shared by both plastics.
class PlasticBase {
public:
    /// coat = nullptr: the smooth coat's t = 1 − F and R̄ = F_dri; otherwise the rough coat's table.
    /// fresnel_avg: F_dri precomputed (fresnel.h), or null to compute it here.
    PlasticBase(float eta, const Spectrum& kd, const Spectrum& ks, PlasticVariant variant,
                const RoughCoatTable* coat = nullptr, const DielectricFresnelAverage* fresnel_avg = nullptr);
    /// f_d · |cos θi| of the header comment (both directions in the upper hemisphere).
    Spectrum diffuse(float cos_o, float cos_i) const;
    /// Probability of choosing the coat lobe when sampling from wo.
    float coat_probability(float cos_o) const;
    /// The coat's transmittance t(μ) (header comment).
    float transmittance(float mu) const;
    /// R̄, the coat's internal diffuse reflectance used by the coupled and linear variants.
    float internal_reflectance() const { return m_rbar; }
    /// The rough coat's table, or nullptr for the smooth transmittance.
    const RoughCoatTable* coat_table() const { return m_coat; }
    float eta() const { return m_eta; }
    const Spectrum& ks() const { return m_ks; }
    std::string params() const;
    /// The packet forms' parameters (the table at offset 0 of its own values).
    const PlasticBaseT<float>& lanes() const { return m_lanes; }
    PlasticVariant variant() const { return m_variant; }

private:
    float m_eta;
    Spectrum m_kd, m_ks;
    PlasticVariant m_variant;
    const RoughCoatTable* m_coat;  // nullptr: smooth transmittance
    float m_rbar = 0.f;
    PlasticBaseT<float> m_lanes;   // scale: coupled Kd/(η² (1 − Kd R̄)); linear Kd/(η² (1 − R̄)); sum Kd
};

class SmoothPlastic {
public:
    SmoothPlastic(float eta = 1.49f, const Spectrum& kd = Spectrum(0.5f), const Spectrum& ks = Spectrum(1.f),
                  PlasticVariant variant = PlasticVariant::Coupled,
                  const DielectricFresnelAverage* fresnel_avg = nullptr)
        : m_base(eta, kd, ks, variant, nullptr, fresnel_avg) {}
    /// From an already-configured base (no Fresnel-average quadrature).
    explicit SmoothPlastic(const PlasticBase& base) : m_base(base) {}
    Spectrum eval(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const { return lanes().eval(ctx, wo, wi); }
    float pdf(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const { return lanes().pdf(ctx, wo, wi); }
    std::optional<BxDFSample> sample(const BxDFContext& ctx, const Vec3f& wo, float u_lobe, const Vec2f& u) const {
        return to_optional(lanes().sample(ctx, wo, u_lobe, u));
    }
    BxDFFlags flags() const;
    std::string to_string() const { return "SmoothPlastic[" + m_base.params() + "]"; }
    const PlasticBase& base() const { return m_base; }
    /// The packet form's parameters (SmoothPlasticT<float>).
    SmoothPlasticT<float> lanes() const { return {m_base.lanes()}; }

private:
    PlasticBase m_base;
};

template <class Distribution>
class RoughPlastic {
public:
    /// `coat_transmittance` = Rough uses `table` when it was built for (d, eta) (the materials
    /// pass the table they resolved at scene build) and otherwise RoughCoatTable::get(d, eta). An
    /// effectively smooth coat uses the smooth values (no table). The sum variant ignores it.
    RoughPlastic(const Distribution& d, float eta = 1.49f, const Spectrum& kd = Spectrum(0.5f),
                 const Spectrum& ks = Spectrum(1.f), PlasticVariant variant = PlasticVariant::Coupled,
                 CoatTransmittance coat_transmittance = CoatTransmittance::Smooth,
                 const RoughCoatTable* table = nullptr, const DielectricFresnelAverage* fresnel_avg = nullptr)
        : m_base(eta, kd, ks, variant, coat_table(d, eta, variant, coat_transmittance, table), fresnel_avg), m_d(d) {}
    Spectrum eval(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const { return lanes().eval(ctx, wo, wi); }
    float pdf(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const { return lanes().pdf(ctx, wo, wi); }
    std::optional<BxDFSample> sample(const BxDFContext& ctx, const Vec3f& wo, float u_lobe, const Vec2f& u) const {
        return to_optional(lanes().sample(ctx, wo, u_lobe, u));
    }
    BxDFFlags flags() const;
    std::string to_string() const { return "RoughPlastic[" + m_d.to_string() + ", " + m_base.params() + "]"; }

    const PlasticBase& base() const { return m_base; }
    const Distribution& distribution() const { return m_d; }
    /// The packet form's parameters (its float instantiation).
    using Lanes = RoughPlasticT<float, typename LaneDistribution<Distribution>::type>;
    Lanes lanes() const { return {m_base.lanes(), LaneDistribution<Distribution>::of(m_d), smooth()}; }

private:
    static const RoughCoatTable* coat_table(const Distribution& d, float eta, PlasticVariant v, CoatTransmittance c,
                                            const RoughCoatTable* table) {
        if (c != CoatTransmittance::Rough || v == PlasticVariant::Sum || d.effectively_smooth()) return nullptr;
        return table && table->matches(d, eta) ? table : &RoughCoatTable::get(d, eta);
    }
    // An effectively smooth coat evaluates as SmoothPlastic (conductor.h rule).
    bool smooth() const { return m_d.effectively_smooth(); }
    PlasticBase m_base;
    Distribution m_d;
};
extern template class RoughPlastic<GGX>;
extern template class RoughPlastic<Beckmann>;
extern template const RoughCoatTable& RoughCoatTable::get<GGX>(const GGX&, float);
extern template const RoughCoatTable& RoughCoatTable::get<Beckmann>(const Beckmann&, float);
extern template RoughCoatTable RoughCoatTable::compute<GGX>(const GGX&, float);
extern template RoughCoatTable RoughCoatTable::compute<Beckmann>(const Beckmann&, float);
}  // namespace pellucid
