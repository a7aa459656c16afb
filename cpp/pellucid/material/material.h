// Materials: parameters (later textures) evaluated at a hit, returning a concrete BxDF by value.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <string>
#include <variant>

#include "pellucid/bxdf/bxdf.h"
#include "pellucid/geometry/interaction.h"

namespace pellucid {

/// `lambertian`: see bxdf/lambertian.h for its parameter table.
struct DiffuseMaterial {
    Spectrum reflectance{0.5f};
    BxDF get_bxdf(const SurfaceInteraction&) const { return Lambertian(reflectance); }
    std::string to_string() const { return "DiffuseMaterial[reflectance=" + reflectance.to_string() + "]"; }
};

using Material = std::variant<DiffuseMaterial>;

inline BxDF get_bxdf(const Material& m, const SurfaceInteraction& si) {
    return std::visit([&](const auto& x) { return x.get_bxdf(si); }, m);
}
inline std::string to_string(const Material& m) {
    return std::visit([](const auto& x) { return x.to_string(); }, m);
}
}  // namespace pellucid
