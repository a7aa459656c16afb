// The `subsurface` material: a dielectric boundary (smooth, or rough with a microfacet
// distribution) over a scattering interior, rendered by a BSSRDF diffusion profile or by a random
// walk through the interior as a participating medium (docs/subsurface.md).
// SPDX-License-Identifier: Apache-2.0
//
// | parameter          | type         | default      | meaning                                          |
// |--------------------|--------------|--------------|--------------------------------------------------|
// | model              | string       | "auto"       | "dipole" (Jensen et al. 2001), "better_dipole" (d'Eon 2012), "random_walk", "coated" (the far-field limit: a coated Lambertian), or "auto" (chosen per object, docs/subsurface.md) |
// | int_ior, ext_ior   | float/string | 1.33, "air"  | boundary IOR (η = int_ior/ext_ior), as for `dielectric` |
// | sigma_a, sigma_s   | colour       | —            | absorption and scattering coefficients, per scene unit (≥ 0) |
// | scale              | float        | 1            | multiplies sigma_a and sigma_s (unit conversion) |
// | albedo             | colour       | 0.8          | instead of sigma_a/sigma_s: the diffuse colour (total diffuse reflectance of the profile), in [0, 1) |
// | mfp                | colour       | 0.05         | with albedo: the mean free path 1/σ't per channel, in scene units (> 0) |
// | g                  | float        | 0            | Henyey–Greenstein anisotropy of the interior, in (−1, 1) |
// | alpha / roughness / alpha_u, alpha_v, distribution, shadowing | | smooth | a rough boundary, as for `rough_dielectric` |
// Every colour and g may be a texture; the boundary's IOR and roughness too.
// JSON: {"type": "subsurface", "albedo": [0.9, 0.6, 0.5], "mfp": [0.02, 0.01, 0.005], "int_ior": 1.4}
#pragma once
#include <cstdint>
#include <string>

#include "pellucid/bxdf/bxdf.h"
#include "pellucid/material/dielectric.h"
#include "pellucid/material/params.h"

namespace pellucid {

/// Which model renders a `subsurface` material. Auto is resolved per object at scene build
/// (scene/subsurface_choice.h) into one of the others; Coated is the far-field limit (auto's choice
/// where the diffusion length is below the pixel footprint): the coated Lambertian with the better
/// dipole's total reflectance.
enum class SubsurfaceModel : uint8_t { Dipole, BetterDipole, RandomWalk, Auto, Coated };
std::string to_string(SubsurfaceModel m);

struct SubsurfaceParams {
    DielectricParams boundary;  ///< IORs (specular multipliers stay 1)
    MicrofacetParams microfacet;
    bool rough = false;
    SubsurfaceModel model = SubsurfaceModel::Auto;
    /// from_albedo: the interior is given by albedo + mfp (inverted per channel by the diffusion
    /// model's closed form, bssrdf/profile.h from_diffuse), else by sigma_a, sigma_s (× scale).
    bool from_albedo = true;
    Tex<Spectrum> sigma_a{Spectrum(0.f)}, sigma_s{Spectrum(0.f)};
    float scale = 1.f;
    Tex<Spectrum> albedo{Spectrum(0.8f)}, mfp{Spectrum(0.05f)};
    Tex<float> g{0.f};
};
}  // namespace pellucid
