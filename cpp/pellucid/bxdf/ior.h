// Named indices of refraction: conductors as RGB complex IOR (η, k), dielectrics as real η.
// SPDX-License-Identifier: Apache-2.0
//
// RGB convention: channel r, g, b hold the optical constants at 650, 550 and 450 nm (vacuum
// wavelength), linearly interpolated in wavelength between the tabulated points of the cited data
// set (refractiveindex.info database). This is a point sample per channel, not a spectral
// integral against the sRGB matching functions; good enough for an RGB renderer's named metals.
#pragma once
#include <string>
#include <vector>

#include "pellucid/math/spectrum.h"

namespace pellucid {

struct ConductorIOR {
    Spectrum eta, k;
};

/// Look up a metal by (case-sensitive) chemical symbol, e.g. "Au". "none" is a perfect mirror
/// (η = 0, k = 1 → F ≡ 1). Throws pellucid::Error("unknown metal 'xyz'; known: ...") otherwise.
ConductorIOR conductor_ior(const std::string& name);
/// Names accepted by conductor_ior, in table order.
std::vector<std::string> conductor_names();

/// Look up a dielectric's real IOR by name ("water", "glass", "bk7", "diamond", "air", ...).
/// Throws pellucid::Error("unknown dielectric 'xyz'; known: ...") otherwise.
float dielectric_ior(const std::string& name);
std::vector<std::string> dielectric_names();
}  // namespace pellucid
