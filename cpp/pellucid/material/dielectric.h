// Dielectric materials: `dielectric`, `rough_dielectric`, `thin_dielectric`.
// SPDX-License-Identifier: Apache-2.0
//
// `dielectric` (SmoothDielectric) and `thin_dielectric` (ThinDielectric), bxdf/dielectric.h:
// | parameter              | type         | default | meaning                                          |
// |------------------------|--------------|---------|--------------------------------------------------|
// | int_ior                | float/string | "bk7"   | interior IOR > 0, or a name of bxdf/ior.h ("water", "diamond", ...) |
// | ext_ior                | float/string | "air"   | exterior IOR > 0 (the side the normal points to) |
// | specular_reflectance   | colour       | 1       | multiplier on reflection, in [0, 1]              |
// | specular_transmittance | colour       | 1       | multiplier on transmission, in [0, 1]            |
// JSON: {"type": "dielectric", "int_ior": "water", "ext_ior": "air"}
//
// `rough_dielectric` (RoughDielectric<GGX|Beckmann>, Walter et al. 2007): the above plus
// `distribution` ("ggx" or "beckmann"), `alpha`, `alpha_u`/`alpha_v` or `roughness`, and
// `shadowing`, exactly as for `rough_conductor`, and `multiple_scattering` (bool, default false:
// Kulla–Conty compensation of the reflection + transmission energy, ggx only; bxdf/kulla_conty.h).
// JSON: {"type": "rough_dielectric", "int_ior": 1.5, "alpha": 0.3, "multiple_scattering": true}
#pragma once
#include "pellucid/bxdf/bxdf.h"
#include "pellucid/material/params.h"

namespace pellucid {

/// `dielectric`.
struct DielectricParams {
    Tex<float> int_ior{1.5046f}, ext_ior{1.000277f};
    Tex<Spectrum> specular_reflectance{Spectrum(1.f)}, specular_transmittance{Spectrum(1.f)};
};
/// The relative IOR int_ior / ext_ior at a hit (or of the constants, TexEval{}).
inline float relative_eta(const DielectricParams& p, const TexEval& tex) { return tex(p.int_ior) / tex(p.ext_ior); }

/// `thin_dielectric`: the parameters of `dielectric`.
struct ThinDielectricParams : DielectricParams {};

/// `rough_dielectric`.
struct RoughDielectricParams {
    MicrofacetParams microfacet;
    DielectricParams dielectric;
    bool multiple_scattering = false;
    /// Derived at load (prepare_material): the Kulla–Conty set-up's Fresnel average of the constant
    /// η (RoughDielectric::multiscatter_fresnel_average), used wherever a hit's η is that one.
    DielectricFresnelAverage fresnel_avg;
};
}  // namespace pellucid
