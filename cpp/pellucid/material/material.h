// Materials: the scene-facing models. Each holds its parameters (a `*Params` struct of constants)
// and the constants precomputed from them at construction (Fresnel averages, fresnel.h; the rough
// plastic's coat table), and builds its BxDF from Params: get_bxdf() from its own, bxdf_for(p) from
// a copy with textured fields written in (material/textured.h).
// SPDX-License-Identifier: Apache-2.0
//
// A material holds no BxDF: the scene builds each material's untextured BxDF once
// (Scene::material_bxdfs), and the textured ones are built per hit. Type names and parameter
// tables: the family headers (diffuse.h, conductor.h, dielectric.h, plastic.h, principled.h,
// subsurface.h) and docs/scene-format.md.
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

using Material = std::variant<DiffuseMaterial, OrenNayarMaterial, ConductorMaterial, RoughConductorMaterial,
                              DielectricMaterial, RoughDielectricMaterial, ThinDielectricMaterial,
                              PlasticMaterial, RoughPlasticMaterial, PrincipledMaterial, SubsurfaceMaterial>;

inline BxDF get_bxdf(const Material& m, const SurfaceInteraction& si) {
    return std::visit([&](const auto& x) { return x.get_bxdf(si); }, m);
}
inline std::string to_string(const Material& m) {
    return std::visit([](const auto& x) { return x.to_string(); }, m);
}
}  // namespace pellucid
