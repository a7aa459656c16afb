// The `principled` material: the Disney model in two variants, "2012" (Burley 2012 BRDF, the
// default; bxdf/principled.h) and "2015" (Burley 2015 BSDF with specular transmission, flatness and
// a thin-sheet mode; bxdf/principled_bsdf.h, defined as Mitsuba 3's principled / principledthin).
// SPDX-License-Identifier: Apache-2.0
//
// | parameter             | type   | default  | variants   | meaning                                   |
// |-----------------------|--------|----------|------------|-------------------------------------------|
// | variant               | string | "2012"   |            | "2012" or "2015"                          |
// | base_color            | colour | 0.8      | all        | albedo / metal colour, in [0, 1]          |
// | metallic              | float  | 0        | not thin   | [0, 1]                                    |
// | roughness             | float  | 0.5      | all        | [0, 1]; specular α = roughness²           |
// | specular              | float  | 0.5      | all        | [0, 1]; 2012: F0 = 0.08·specular; 2015: η with R0(η) = 0.08·specular |
// | specular_tint         | float  | 0        | all        | [0, 1]                                    |
// | sheen                 | float  | 0        | all        | [0, 1]                                    |
// | sheen_tint            | float  | 0.5      | all        | [0, 1]                                    |
// | clearcoat             | float  | 0        | not thin   | [0, 1]                                    |
// | clearcoat_gloss       | float  | 1        | not thin   | [0, 1]                                    |
// | anisotropic           | float  | 0        | all        | [0, 1]                                    |
// | specular_transmission | float  | 0        | 2015       | [0, 1]; rough-glass share of the dielectric |
// | eta                   | float  | —        | 2015       | [1e-3, 10]; relative IOR (instead of `specular`; both: error) |
// | flatness              | float  | 0        | 2015       | [0, 1]; diffuse → Hanrahan–Krueger subsurface |
// | thin                  | bool   | false    | 2015       | thin sheet (no metallic, no clearcoat)    |
// | diffuse_transmission  | float  | 0        | 2015 thin  | [0, 2]; 0 reflects, 1 splits, 2 transmits the diffuse |
// Values outside their ranges, and keys of another variant, are errors. Neither variant conserves
// energy (docs/materials.md).
// JSON: {"type": "principled", "base_color": [0.8, 0.2, 0.1], "roughness": 0.4, "clearcoat": 1}
//       {"type": "principled", "variant": "2015", "specular_transmission": 1, "eta": 1.33, "roughness": 0.2}
#pragma once
#include "pellucid/bxdf/bxdf.h"
#include "pellucid/material/params.h"

namespace pellucid {

/// `principled`: the fields of PrincipledInputs (bxdf/principled.h), each a Tex but the variant and
/// `thin`.
struct PrincipledParams {
    Tex<Spectrum> base_color{Spectrum(0.8f)};
    Tex<float> metallic{0.f}, roughness{0.5f}, specular{0.5f}, specular_tint{0.f};
    Tex<float> sheen{0.f}, sheen_tint{0.5f}, clearcoat{0.f}, clearcoat_gloss{1.f}, anisotropic{0.f};
    Tex<float> specular_transmission{0.f}, flatness{0.f}, diffuse_transmission{0.f};
    Tex<float> eta{0.f};  ///< 0 = derived from `specular`
    PrincipledVariant variant = PrincipledVariant::Burley2012;
    bool thin = false;
};
}  // namespace pellucid
