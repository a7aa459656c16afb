// Named indices of refraction: conductors as RGB complex IOR (η, k), dielectrics as real η.
// SPDX-License-Identifier: Apache-2.0
//
// RGB convention: each channel of η and of k is the linear-sRGB value of the measured spectrum
// v(λ), as Mitsuba 3's RGB variants compute it for their named conductors, so scenes that name a
// metal render alike in both. tools/conductor_rgb.py generates the table from the spectral files:
// XYZ = Σ cmf(λ_i) v(λ_i) / Σ ȳ(λ_i) over λ_i = 360 + 470 i/999 nm (i < 1000), v linearly
// interpolated and taken as 0 outside the data's range, cmf the CIE 1931 2° colour-matching
// functions (1 nm table, no illuminant); then the linear XYZ → sRGB (BT.709 primaries, D65) matrix,
// and negative channels clamped to 0. Against Mitsuba 3.9.1's own values (tests/data/mitsuba/
// conductor_rgb.json) the normal-incidence reflectance differs by at most 2.4e-4 for every name.
#pragma once
#include <string>
#include <vector>

#include "pellucid/math/spectrum.h"

namespace pellucid {

struct ConductorIOR {
    Spectrum eta, k;
};

/// Look up a conductor by (case-sensitive) name: Mitsuba 3's material names ("Au", "Cu_palik",
/// "a-C", ...) plus "Fe", "Ti", "Ni". "none" is a perfect mirror (η = 0, k = 1 → F ≡ 1).
/// Throws pellucid::Error("unknown metal 'xyz'; known: ...") otherwise.
ConductorIOR conductor_ior(const std::string& name);
/// Names accepted by conductor_ior, in table order.
std::vector<std::string> conductor_names();

/// Look up a dielectric's real IOR by name ("water", "glass", "bk7", "diamond", "air", ...).
/// Throws pellucid::Error("unknown dielectric 'xyz'; known: ...") otherwise.
float dielectric_ior(const std::string& name);
std::vector<std::string> dielectric_names();
}  // namespace pellucid
