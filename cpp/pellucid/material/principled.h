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
#include <string>

#include "pellucid/bxdf/bxdf.h"
#include "pellucid/geometry/interaction.h"
#include "pellucid/material/params.h"

namespace pellucid {

class PrincipledMaterial {
public:
    explicit PrincipledMaterial(const PrincipledParams& p) : m_p(p) {}
    BxDF get_bxdf(const SurfaceInteraction&) const { return bxdf_for(m_p); }
    /// The BxDF of `p`: params() with textured fields written in (material/textured.h).
    BxDF bxdf_for(const PrincipledParams& p) const {
        return p.variant == PrincipledVariant::Burley2015 ? BxDF(PrincipledBSDF(p)) : BxDF(Principled(p));
    }
    const PrincipledParams& params() const { return m_p; }
    std::string to_string() const;

private:
    PrincipledParams m_p;
};
}  // namespace pellucid
