// Materials: the scene-facing models. Each holds its parameters (a `*Params` struct of constants;
// textures will replace fields later) and returns a concrete BxDF by value from get_bxdf().
// SPDX-License-Identifier: Apache-2.0
//
// While every parameter is a constant, materials whose BxDF constructor does real work (Fresnel
// averages, Kulla–Conty setup, EON constants) build it once at scene build and get_bxdf() copies
// it; the cheap ones construct it per call. Type names and parameter tables: the family headers
// (diffuse.h, conductor.h, dielectric.h, plastic.h, principled.h) and docs/scene-format.md.
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
