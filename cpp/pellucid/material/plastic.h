// Plastic materials: `plastic` (smooth coat) and `rough_plastic` (GGX or Beckmann coat) over a
// Lambertian base.
// SPDX-License-Identifier: Apache-2.0
//
// bxdf/plastic.h explains both variants.
// | parameter            | type         | default         | meaning                                   |
// |----------------------|--------------|-----------------|-------------------------------------------|
// | diffuse_reflectance  | colour       | 0.5             | base albedo Kd, in [0, 1]                 |
// | specular_reflectance | colour       | 1               | coat multiplier Ks, in [0, 1]             |
// | int_ior, ext_ior     | float/string | "polypropylene", "air" | coat IOR (η = int_ior/ext_ior), as for `dielectric` |
// | variant              | string       | "coupled"       | "coupled" (energy-conserving, Weidlich & Wilkie 2007), "linear" (Mitsuba's nonlinear = false) or "sum" (Kd/π + coat) |
// `rough_plastic` adds `distribution` ("ggx" or "beckmann"), `alpha` (default 0.1), `alpha_u`/`alpha_v`,
// `roughness` and `shadowing` ("height_correlated" or "separable"), as for `rough_conductor`, and
// | coat_transmittance   | string       | "smooth"        | "smooth" (1 − F) or "rough" (the rough coat's table; not with variant "sum") |
// With coat_transmittance = "rough" the table is built once per material at scene build
// (bxdf/plastic.h, RoughCoatTable), so α, roughness and the IORs must be constants there (a texture
// is an error); textured colours are fine (the per-hit BxDF reuses the table).
// JSON: {"type": "rough_plastic", "diffuse_reflectance": [0.1, 0.3, 0.6], "alpha": 0.2,
//        "variant": "linear", "coat_transmittance": "rough"}
#pragma once
#include <string>

#include "pellucid/bxdf/bxdf.h"
#include "pellucid/geometry/interaction.h"
#include "pellucid/material/params.h"

namespace pellucid {

struct PlasticParams {
    Spectrum diffuse_reflectance{0.5f}, specular_reflectance{1.f};
    float int_ior = 1.49f, ext_ior = 1.000277f;
    PlasticVariant variant = PlasticVariant::Coupled;
    std::string to_string() const;
};

class PlasticMaterial {
public:
    explicit PlasticMaterial(const PlasticParams& p);
    BxDF get_bxdf(const SurfaceInteraction&) const { return bxdf_for(m_p); }
    /// The BxDF of `p`: params() with textured fields written in (material/textured.h). The Fresnel
    /// average of R̄ comes from the one computed at construction while p's IOR is params()'s.
    BxDF bxdf_for(const PlasticParams& p) const;
    const PlasticParams& params() const { return m_p; }
    std::string to_string() const;

private:
    PlasticParams m_p;
    DielectricFresnelAverage m_fresnel_avg;  // of params()'s η (fresnel.h)
};

struct RoughPlasticParams {
    MicrofacetParams microfacet;
    PlasticParams plastic;
    CoatTransmittance coat_transmittance = CoatTransmittance::Smooth;
    /// Derived, not a scene parameter: the coat table the material resolved at build (nullptr for
    /// the smooth transmittance). Carried here so that the per-hit rebuild of a textured material
    /// (material/textured.h copies these Params) reuses it instead of looking it up.
    const RoughCoatTable* coat_table = nullptr;
};

class RoughPlasticMaterial {
public:
    /// Resolves params().coat_table and computes the Fresnel average of R̄ once.
    explicit RoughPlasticMaterial(const RoughPlasticParams& p);
    BxDF get_bxdf(const SurfaceInteraction&) const { return bxdf_for(m_p); }
    /// The BxDF of `p` (as PlasticMaterial::bxdf_for; p.coat_table is reused when it matches).
    BxDF bxdf_for(const RoughPlasticParams& p) const;
    const RoughPlasticParams& params() const { return m_p; }
    std::string to_string() const;

private:
    RoughPlasticParams m_p;
    DielectricFresnelAverage m_fresnel_avg;  // of params()'s η (fresnel.h)
};
}  // namespace pellucid
