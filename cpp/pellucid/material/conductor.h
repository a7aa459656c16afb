// Conductor materials: `conductor` (smooth mirror) and `rough_conductor` (microfacet).
// SPDX-License-Identifier: Apache-2.0
//
// `conductor` (bxdf/conductor.h, SmoothConductor):
// | parameter            | type     | default | meaning                                                  |
// |----------------------|----------|---------|----------------------------------------------------------|
// | material             | string   | "none"  | metal preset of bxdf/ior.h (Au, Ag, Cu, Al, Cr, Fe, Ti, Ni; "none" = ideal mirror, F ≡ 1) |
// | eta, k               | colour   | —, 0    | complex IOR instead of `material` (eta > 0 required, k ≥ 0); not with `material` |
// | specular_reflectance | colour   | 1       | multiplier on F, in [0, 1]                               |
// | fresnel              | string   | "exact" | "exact" or "schlick" (Schlick 1994 with the exact R0 = F(0°)) |
// JSON: {"type": "conductor", "material": "Au"}
//
// `rough_conductor` (MicrofacetReflection<GGX|Beckmann, ConductorFresnel>): the above plus
// | parameter           | type   | default | meaning                                                   |
// |---------------------|--------|---------|-----------------------------------------------------------|
// | distribution        | string | "ggx"   | "ggx" or "beckmann"                                       |
// | alpha               | float  | 0.1     | isotropic α ≥ 0 (> 1 clamped to 1; < 1e-3 → delta mirror) |
// | alpha_u, alpha_v    | float  | —       | anisotropic α (alpha_v defaults to alpha_u); not with alpha |
// | roughness           | float  | —       | perceptual r ∈ [0, 1] instead of α: α = r² (Burley 2012 §5.4) |
// | shadowing           | string | "height_correlated" | or "separable": the Smith G form (bxdf/microfacet.h) |
// | multiple_scattering | bool   | false   | Kulla–Conty energy compensation (ggx only; height_correlated only) |
// JSON: {"type": "rough_conductor", "material": "Al", "alpha_u": 0.05, "alpha_v": 0.3,
//        "multiple_scattering": true}
#pragma once
#include "pellucid/bxdf/bxdf.h"
#include "pellucid/material/params.h"

namespace pellucid {

/// `conductor`.
struct ConductorParams {
    ConductorIORParams ior;
    Tex<Spectrum> specular_reflectance{Spectrum(1.f)};
};

/// `rough_conductor`.
struct RoughConductorParams {
    MicrofacetParams microfacet;
    ConductorIORParams ior;
    Tex<Spectrum> specular_reflectance{Spectrum(1.f)};
    bool multiple_scattering = false;
    /// Derived at load (prepare_material): Kulla–Conty's Fresnel average of the constant η, k, used
    /// wherever a hit's η, k are those (ConductorFresnelAverage::get).
    ConductorFresnelAverage fresnel_avg;
};
}  // namespace pellucid
