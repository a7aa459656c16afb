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
// JSON: {"type": "rough_dielectric", "int_ior": 1.5, "distribution": "ggx", "alpha": 0.3}
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

private:
    float m_eta;
    Spectrum m_r, m_t;
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

private:
    float m_eta;
    Spectrum m_r, m_t;
};

/// Rough dielectric interface: Walter, Marschner, Li, Torrance 2007, "Microfacet Models for
/// Refraction through Rough Surfaces", EGSR. Reflection eq. 20, transmission eq. 21, generalised
/// half vector eq. 16, Jacobians eqs. 14 and 17; VNDF sampling replaces their eq. 24–28 sampling.
template <class Distribution>
class RoughDielectric {
public:
    RoughDielectric(const Distribution& distrib, float eta, const Spectrum& specular_reflectance = Spectrum(1.f),
                    const Spectrum& specular_transmittance = Spectrum(1.f));
    Spectrum eval(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const;
    float pdf(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const;
    std::optional<BxDFSample> sample(const BxDFContext& ctx, const Vec3f& wo, float u_lobe, const Vec2f& u) const;
    BxDFFlags flags() const;
    std::string to_string() const;
    bool is_smooth() const { return m_d.effectively_smooth() || m_eta == 1.f; }

private:
    struct EvalPdf {
        Spectrum f{0.f};
        float pdf = 0.f;
    };
    EvalPdf eval_pdf(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const;

    Distribution m_d;
    float m_eta;
    Spectrum m_r, m_t;
};
extern template class RoughDielectric<GGX>;
extern template class RoughDielectric<Beckmann>;
}  // namespace pellucid
