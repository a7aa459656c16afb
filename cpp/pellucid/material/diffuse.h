// Diffuse materials: `lambertian` and `oren_nayar` (scene-facing types; BxDFs in bxdf/).
// SPDX-License-Identifier: Apache-2.0
//
// `lambertian`: f = ρ/π (bxdf/lambertian.h).
// | parameter   | type   | default | meaning                          |
// |-------------|--------|---------|----------------------------------|
// | reflectance | colour | 0.5     | albedo ρ, each channel in [0, 1] |
// JSON: {"type": "lambertian", "reflectance": [0.8, 0.2, 0.2]}
//
// `oren_nayar`: rough diffuse (bxdf/oren_nayar.h), two variants.
// | parameter   | type   | default | meaning                                                        |
// |-------------|--------|---------|----------------------------------------------------------------|
// | reflectance | colour | 0.5     | ρ, each channel in [0, 1]                                      |
// | variant     | string | "eon"   | "eon" (energy-preserving, Portsmouth et al. 2025) or "classic" |
// | sigma       | float  | 20      | classic only: facet-slope std. dev. σ in DEGREES, ≥ 0; > 90 is clamped to 90 |
// | roughness   | float  | 0.5     | eon only: r ∈ [0, 1], ≥ 0; > 1 is clamped to 1                |
// σ is in degrees because every other angle in the scene format is (Oren & Nayar 1994 quote σ in
// degrees in their figures; the model uses σ in radians internally). σ = 0 / r = 0 is exactly
// Lambertian. There is no mapping between σ and r: they are different models.
// JSON: {"type": "oren_nayar", "reflectance": 0.7, "variant": "classic", "sigma": 30}
#pragma once
#include "pellucid/bxdf/bxdf.h"
#include "pellucid/material/params.h"

namespace pellucid {

/// `lambertian` (the default material of shapes without one).
struct LambertianParams {
    Tex<Spectrum> reflectance{Spectrum(0.5f)};
};

/// `oren_nayar`.
struct OrenNayarParams {
    Tex<Spectrum> reflectance{Spectrum(0.5f)};
    OrenNayarVariant variant = OrenNayarVariant::EON;
    Tex<float> sigma_degrees{20.f};  ///< classic
    Tex<float> roughness{0.5f};      ///< eon
};
}  // namespace pellucid
