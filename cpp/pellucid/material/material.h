// Materials: the scene-facing models, a closed variant of plain Params structs. A Params struct
// holds the model's parameters, each one that may vary over a surface a Tex (material/tex.h), and
// the constants derived from them once at load (prepare_material: Fresnel averages, the rough
// plastic's coat table). make_bxdf builds the model's BxDF from its Params and a texture
// evaluation: one function per model, serving both the scene's prebuilt BxDF of an untextured
// material (TexEval{}, Scene::material_bxdfs) and the per-hit BxDF of a textured one.
// SPDX-License-Identifier: Apache-2.0
//
// Type names and parameter tables: the family headers (diffuse.h, conductor.h, dielectric.h,
// plastic.h, principled.h, subsurface.h) and docs/scene-format.md.
#pragma once
#include <string>
#include <variant>

#include "pellucid/material/conductor.h"
#include "pellucid/material/dielectric.h"
#include "pellucid/material/diffuse.h"
#include "pellucid/material/plastic.h"
#include "pellucid/material/principled.h"
#include "pellucid/material/subsurface.h"

namespace pellucid {

using Material = std::variant<LambertianParams, OrenNayarParams, ConductorParams, RoughConductorParams,
                              DielectricParams, RoughDielectricParams, ThinDielectricParams, PlasticParams,
                              RoughPlasticParams, PrincipledParams, SubsurfaceParams>;

/// The BxDF of each model, its parameters read through `tex` (one function per model; material.cpp).
BxDF make_bxdf(const LambertianParams& p, const TexEval& tex);
BxDF make_bxdf(const OrenNayarParams& p, const TexEval& tex);
BxDF make_bxdf(const ConductorParams& p, const TexEval& tex);
BxDF make_bxdf(const RoughConductorParams& p, const TexEval& tex);
BxDF make_bxdf(const DielectricParams& p, const TexEval& tex);
BxDF make_bxdf(const RoughDielectricParams& p, const TexEval& tex);
BxDF make_bxdf(const ThinDielectricParams& p, const TexEval& tex);
BxDF make_bxdf(const PlasticParams& p, const TexEval& tex);
BxDF make_bxdf(const RoughPlasticParams& p, const TexEval& tex);
BxDF make_bxdf(const PrincipledParams& p, const TexEval& tex);
/// The boundary's BxDF: SmoothDielectric, or RoughDielectric of the distribution.
BxDF make_bxdf(const SubsurfaceParams& p, const TexEval& tex);

inline BxDF make_bxdf(const Material& m, const TexEval& tex = TexEval{}) {
    return std::visit([&](const auto& p) { return make_bxdf(p, tex); }, m);
}

/// Computes the constants derived from a material's constant parameters (the Params' fields marked
/// "derived at load"). The builders call it; Params assembled by hand need it before make_bxdf.
void prepare_material(Material& m);

/// "type[key=value, ...]" with the scene format's type and key names; a textured parameter shows
/// its texture.
std::string to_string(const Material& m);
}  // namespace pellucid
