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
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <type_traits>

#include "pellucid/bxdf/bxdf_types.h"
#include "pellucid/bxdf/conductor.h"
#include "pellucid/bxdf/fresnel.h"
#include "pellucid/bxdf/microfacet.h"

namespace pellucid {

enum class PlasticVariant { Coupled, Sum, Linear };
std::string to_string(PlasticVariant v);
enum class CoatTransmittance { Smooth, Rough };
std::string to_string(CoatTransmittance c);

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
/// α (x, y), shadowing and η, computing it on the first request, outside the cache's lock (about
/// 10 ms for GGX and 100 ms for Beckmann, whose visible-normal sampling inverts a CDF by Newton). Entries are never freed (about 300 bytes each; a process
/// builds one per distinct rough coat), so the pointers BxDFs hold stay valid for the whole run.
/// Materials resolve the pointer once at scene build; a BxDF rebuilt per hit (textured Kd) is
/// handed the same pointer and only compares the key (RoughPlastic's constructor), so no hit
/// computes, locks or allocates. α or η varying per hit would need a table per hit: the material
/// builder rejects a textured α, roughness or IOR with coat_transmittance = "rough".
class RoughCoatTable {
public:
    static constexpr int kSize = 64;
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

/// The Lambertian base under the coat, shared by both plastics.
class PlasticBase {
public:
    /// coat = nullptr: the smooth coat's t = 1 − F and R̄ = F_dri; otherwise the rough coat's table.
    PlasticBase(float eta, const Spectrum& kd, const Spectrum& ks, PlasticVariant variant,
                const RoughCoatTable* coat = nullptr);
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

private:
    float m_eta;
    Spectrum m_kd, m_ks;
    PlasticVariant m_variant;
    const RoughCoatTable* m_coat;  // nullptr: smooth transmittance
    float m_rbar = 0.f;
    Spectrum m_diffuse_scale;  // coupled: Kd/(η² (1 − Kd R̄)); linear: Kd/(η² (1 − R̄)); sum: Kd
};

class SmoothPlastic {
public:
    SmoothPlastic(float eta = 1.49f, const Spectrum& kd = Spectrum(0.5f), const Spectrum& ks = Spectrum(1.f),
                  PlasticVariant variant = PlasticVariant::Coupled)
        : m_base(eta, kd, ks, variant) {}
    /// From an already-configured base (no Fresnel-average quadrature).
    explicit SmoothPlastic(const PlasticBase& base) : m_base(base) {}
    Spectrum eval(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const;
    float pdf(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const;
    std::optional<BxDFSample> sample(const BxDFContext& ctx, const Vec3f& wo, float u_lobe, const Vec2f& u) const;
    BxDFFlags flags() const;
    std::string to_string() const { return "SmoothPlastic[" + m_base.params() + "]"; }
    const PlasticBase& base() const { return m_base; }

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
                 const RoughCoatTable* table = nullptr)
        : m_base(eta, kd, ks, variant, coat_table(d, eta, variant, coat_transmittance, table)),
          m_coat(d, DielectricFresnel{eta}, ks) {}
    Spectrum eval(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const;
    float pdf(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const;
    std::optional<BxDFSample> sample(const BxDFContext& ctx, const Vec3f& wo, float u_lobe, const Vec2f& u) const;
    BxDFFlags flags() const;
    std::string to_string() const {
        return "RoughPlastic[" + m_coat.distribution().to_string() + ", " + m_base.params() + "]";
    }

    const PlasticBase& base() const { return m_base; }

private:
    static const RoughCoatTable* coat_table(const Distribution& d, float eta, PlasticVariant v, CoatTransmittance c,
                                            const RoughCoatTable* table) {
        if (c != CoatTransmittance::Rough || v == PlasticVariant::Sum || d.effectively_smooth()) return nullptr;
        return table && table->matches(d, eta) ? table : &RoughCoatTable::get(d, eta);
    }
    // An effectively smooth coat evaluates as SmoothPlastic (conductor.h rule).
    bool smooth() const { return m_coat.distribution().effectively_smooth(); }
    PlasticBase m_base;
    MicrofacetReflection<Distribution, DielectricFresnel> m_coat;
};
extern template class RoughPlastic<GGX>;
extern template class RoughPlastic<Beckmann>;
extern template const RoughCoatTable& RoughCoatTable::get<GGX>(const GGX&, float);
extern template const RoughCoatTable& RoughCoatTable::get<Beckmann>(const Beckmann&, float);
extern template RoughCoatTable RoughCoatTable::compute<GGX>(const GGX&, float);
extern template RoughCoatTable RoughCoatTable::compute<Beckmann>(const Beckmann&, float);
}  // namespace pellucid
