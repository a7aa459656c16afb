// Plastic: a dielectric coat (smooth or rough) over a Lambertian base, in two documented variants.
// SPDX-License-Identifier: Apache-2.0
//
// variant = "coupled" (default; energy-conserving, reciprocal):
//   f_d(wo, wi) = Kd (1 − F(θi)) (1 − F(θo)) / (π η² (1 − Kd F_dri)),
//   F_dri = 1 − (1 − F_avg(η))/η²  (internal diffuse reflectance, from the reciprocity of the
//   interface: η² (1 − F_dri) = 1 − F_avg).
// Derivation: light refracts in with 1 − F(θi), meets the Lambertian base (albedo Kd), and each
// time the diffuse internal radiance meets the coat, 1 − F_dri of it escapes and F_dri returns to
// the base; summing the series gives Kd (1 − F_dri)/(1 − Kd F_dri) of escaping energy, distributed
// outside as (1 − F(θo)) cos θo/(π η²) (radiance compression by η²). This is the model of
// Weidlich & Wilkie 2007, "Arbitrarily Layered Micro-Facet Surfaces" (GRAPHITE), §3, and of
// Mitsuba's "plastic" with nonlinear = true. Total albedo = F(θo)·Ks + (1 − F(θo)) ·
// Kd (1 − F_dri)/(1 − Kd F_dri) ≤ 1, = 1 for Kd = Ks = 1 (smooth coat; tested).
// variant = "sum" (the lecture-notes plastic): f = Kd/π + Ks · coat(F), the Lambertian and the
// specular lobes simply added. Conserves energy only if max(Kd) + max(Ks) ≤ 1.
// The rough coat uses the smooth-interface transmittances 1 − F(θ) for the diffuse part (the
// approximation Mitsuba's roughplastic makes with a table; here without the table).
//
// | parameter            | type     | default  | meaning                                    |
// |----------------------|----------|----------|--------------------------------------------|
// | int_ior, ext_ior     | float/str| 1.49, air| coat IOR (η = int_ior/ext_ior)             |
// | diffuse_reflectance  | spectrum | 0.5      | base albedo Kd                             |
// | specular_reflectance | spectrum | 1        | coat multiplier Ks                         |
// | variant              | string   | coupled  | "coupled" or "sum"                         |
// | distribution, alpha  |          | ggx, 0.1 | rough coat only ("rough_plastic")          |
// JSON: {"type": "rough_plastic", "diffuse_reflectance": [0.1, 0.3, 0.6], "int_ior": "polypropylene",
//        "distribution": "ggx", "alpha": 0.2, "variant": "coupled"}
#pragma once
#include <optional>
#include <string>

#include "pellucid/bxdf/bxdf_types.h"
#include "pellucid/bxdf/conductor.h"
#include "pellucid/bxdf/fresnel.h"
#include "pellucid/bxdf/microfacet.h"

namespace pellucid {

enum class PlasticVariant { Coupled, Sum };
std::string to_string(PlasticVariant v);

/// The Lambertian base under a smooth-Fresnel coat, shared by both plastics.
class PlasticBase {
public:
    PlasticBase(float eta, const Spectrum& kd, const Spectrum& ks, PlasticVariant variant);
    /// f_d · |cos θi| of the header comment (both directions in the upper hemisphere).
    Spectrum diffuse(float cos_o, float cos_i) const;
    /// Probability of choosing the coat lobe when sampling from wo.
    float coat_probability(float cos_o) const;
    float eta() const { return m_eta; }
    const Spectrum& ks() const { return m_ks; }
    std::string params() const;

private:
    float m_eta;
    Spectrum m_kd, m_ks;
    PlasticVariant m_variant;
    Spectrum m_diffuse_scale;  // coupled: Kd/(η² (1 − Kd F_dri)); sum: Kd
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

private:
    PlasticBase m_base;
};

template <class Distribution>
class RoughPlastic {
public:
    RoughPlastic(const Distribution& d, float eta = 1.49f, const Spectrum& kd = Spectrum(0.5f),
                 const Spectrum& ks = Spectrum(1.f), PlasticVariant variant = PlasticVariant::Coupled)
        : m_base(eta, kd, ks, variant), m_coat(d, DielectricFresnel{eta}, ks) {}
    Spectrum eval(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const;
    float pdf(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const;
    std::optional<BxDFSample> sample(const BxDFContext& ctx, const Vec3f& wo, float u_lobe, const Vec2f& u) const;
    BxDFFlags flags() const;
    std::string to_string() const {
        return "RoughPlastic[" + m_coat.distribution().to_string() + ", " + m_base.params() + "]";
    }

private:
    // An effectively smooth coat evaluates as SmoothPlastic (conductor.h rule).
    bool smooth() const { return m_coat.distribution().effectively_smooth(); }
    PlasticBase m_base;
    MicrofacetReflection<Distribution, DielectricFresnel> m_coat;
};
extern template class RoughPlastic<GGX>;
extern template class RoughPlastic<Beckmann>;
}  // namespace pellucid
