// The `principled` material (Burley 2012; BxDF and maths in bxdf/principled.h).
// SPDX-License-Identifier: Apache-2.0
//
// | parameter       | type   | default | meaning                                        |
// |-----------------|--------|---------|------------------------------------------------|
// | base_color      | colour | 0.8     | albedo / metal colour, in [0, 1]               |
// | metallic        | float  | 0       | [0, 1]                                         |
// | roughness       | float  | 0.5     | [0, 1]; specular α = roughness²                |
// | specular        | float  | 0.5     | [0, 1] (0.5 ↔ F0 = 0.04)                        |
// | specular_tint   | float  | 0       | [0, 1]                                         |
// | sheen           | float  | 0       | [0, 1]                                         |
// | sheen_tint      | float  | 0.5     | [0, 1]                                         |
// | clearcoat       | float  | 0       | [0, 1]                                         |
// | clearcoat_gloss | float  | 1       | [0, 1]                                         |
// | anisotropic     | float  | 0       | [0, 1]                                         |
// Values outside [0, 1] are errors. Not energy-conserving at grazing angles for high roughness
// (Burley's retro-reflection; docs/materials.md).
// JSON: {"type": "principled", "base_color": [0.8, 0.2, 0.1], "roughness": 0.4, "clearcoat": 1}
#pragma once
#include <string>

#include "pellucid/bxdf/bxdf.h"
#include "pellucid/geometry/interaction.h"
#include "pellucid/material/params.h"

namespace pellucid {

class PrincipledMaterial {
public:
    explicit PrincipledMaterial(const PrincipledParams& p) : m_p(p), m_bxdf(Principled(p)) {}
    BxDF get_bxdf(const SurfaceInteraction&) const { return m_bxdf; }
    const PrincipledParams& params() const { return m_p; }
    std::string to_string() const;

private:
    PrincipledParams m_p;
    BxDF m_bxdf;
};
}  // namespace pellucid
