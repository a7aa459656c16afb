// The lane kernel: the path tracer of path.cpp for the scenes that need no more than it models,
// with 64 paths shaded side by side in structure-of-arrays form so that every step of a vertex is
// one vectorised loop over the paths (AVX-512: 16 paths per instruction).
// SPDX-License-Identifier: Apache-2.0
//
// It models: triangle meshes with flat shading (the shading normal is the geometric one),
// untextured Lambertian materials, and area lights on meshes; every strategy, any max_depth and
// rr_depth, either sampler, either film reconstruction. A scene that needs more
// (another BSDF, textures, smooth normals, spheres, point or infinite lights) renders with the
// general vertex loop (path.cpp) instead; `integrator.lanes: false` asks for that loop always.
//
// The estimator is path.cpp's, term for term: emission found by BSDF sampling weighted by the power
// heuristic against light sampling, next-event estimation of one point on one emitting triangle
// (chosen with the same probability as picking its light by power, then the triangle by area), a
// cosine-weighted bounce, Russian roulette on max β from rr_depth on. It uses the same sample
// dimensions. Its images are not bit-identical to path.cpp's (its random numbers go through
// different, equally distributed warps), but they agree within noise: tests/cpp/integrator/
// test_path_lanes.cpp z-tests them per pixel and checks analytic scenes.
#pragma once
#include <memory>
#include <string>

#include "pellucid/image/film.h"
#include "pellucid/integrator/render_loop.h"
#include "pellucid/scene/scene.h"

namespace pellucid {

/// What the lane kernel reads of a scene: per-triangle hit records and the emitting triangles.
struct LaneScene;

/// The lane kernel's tables for `scene` rendered with `settings`, or nullptr when the scene needs
/// more than the kernel models; `why` (if given) then says what.
std::shared_ptr<const LaneScene> make_lane_scene(const Scene& scene, const IntegratorSettings& settings,
                                                 std::string* why = nullptr);

/// The path tracer's settings as PathIntegrator resolves them from the strategy.
struct LaneSettings {
    int max_depth = -1;  ///< -1 = unbounded ("direct" = 2)
    int rr_depth = 5;
    bool use_nee = true;  ///< next-event estimation (all strategies but "bsdf")
    bool use_mis = true;  ///< power-heuristic weights ("mis", "direct"); without, "nee" leaves emission hits to NEE
};

/// render_tile for the lane kernel.
uint64_t render_tile_lanes(const LaneScene& lanes, const Scene& scene, const LaneSettings& settings, const TileJob& job,
                           Film& film, SamplerType type);
}  // namespace pellucid
