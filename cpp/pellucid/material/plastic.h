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
#include "pellucid/bxdf/bxdf.h"
#include "pellucid/material/params.h"

namespace pellucid {

/// `plastic`.
struct PlasticParams {
    Tex<Spectrum> diffuse_reflectance{Spectrum(0.5f)}, specular_reflectance{Spectrum(1.f)};
    Tex<float> int_ior{1.49f}, ext_ior{1.000277f};
    PlasticVariant variant = PlasticVariant::Coupled;
    /// Derived at load (prepare_material): the Fresnel average of R̄ for the constant η, used
    /// wherever a hit's η is that one (none for the sum variant, which has no R̄).
    DielectricFresnelAverage fresnel_avg;
};
/// The coat's relative IOR int_ior / ext_ior at a hit (or of the constants, TexEval{}).
inline float relative_eta(const PlasticParams& p, const TexEval& tex) { return tex(p.int_ior) / tex(p.ext_ior); }

/// `rough_plastic`.
struct RoughPlasticParams {
    MicrofacetParams microfacet;
    PlasticParams plastic;
    CoatTransmittance coat_transmittance = CoatTransmittance::Smooth;
    /// Derived at load (prepare_material): the coat table of the constant α and η (nullptr for the
    /// smooth transmittance); the builder allows no texture on those with the rough one.
    const RoughCoatTable* coat_table = nullptr;
};
}  // namespace pellucid
