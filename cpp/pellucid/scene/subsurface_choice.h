// Which model renders each object of a `subsurface` material (docs/subsurface.md, "Choosing the
// model"): the material's own `model`, or for "auto" the simplest one accurate enough for that
// object, from its lengths (REFERENCE: "model no more than a scene needs").
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <string>
#include <vector>

#include "pellucid/material/subsurface.h"

namespace pellucid {
class Scene;

/// The thresholds of the auto rules, from the measurements of docs/subsurface.md and the charts of
/// bench/results/subsurface/:
///  * thin: T < kThinRatio·ℓd → random walk. For a slab of thickness t, T ≈ 2t, so this is t < 2ℓd,
///    where the thinness error C·e^(−2t/ℓd) (C ≈ 0.32–0.47, thin_slab.csv) reaches 1 % of the
///    reflectance;
///  * low albedo: min reduced albedo α' < kLowAlbedo → random walk: below it the better dipole's
///    total reflectance is off by more than 5 % (−4.7 % at 0.95, −7.4 % at 0.9; profiles_error.csv);
///  * far: ℓd < kFootprintRatio·w → coated Lambertian with the profile's total reflectance: at
///    ℓd = w its squared bias is 2.9e-5 relMSE on a half-lit sphere, 1/700 of the better dipole's
///    variance at 64 spp (lod.csv);
///  * else the better dipole.
/// T = 4V/A is the object's mean chord length (Cauchy's formula; 4r/3 for a sphere), ℓd = 1/σtr
/// the longest diffusion length over the channels, w the pixel footprint at the object's nearest
/// point to the camera.
struct SubsurfaceThresholds {
    static constexpr float kThinRatio = 4.f;
    static constexpr float kLowAlbedo = 0.95f;
    static constexpr float kFootprintRatio = 1.f;
};

/// One object's choice, as the render log states it.
struct SubsurfaceChoice {
    uint32_t shape = 0;
    SubsurfaceModel model = SubsurfaceModel::BetterDipole;
    std::string reason;
    float thickness = 0.f, diffusion_length = 0.f, mean_free_path = 0.f, footprint = 0.f, min_albedo = 0.f;
};

/// Resolve every shape of a `subsurface` material: fills scene.subsurface / shape_subsurface for
/// the diffusion models, adds an interior medium for the random walk, swaps in the coated
/// Lambertian material, and logs each choice with its reason (and warnings for open meshes, absurd
/// mean free paths, and no scattering). Runs at scene build, after shapes, camera and lights.
void resolve_subsurface(Scene& scene, const std::string& source);
}  // namespace pellucid
