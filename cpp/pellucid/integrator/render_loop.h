// Render options and results, and the tiled, progressive render loop shared by all integrators.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>

#include "pellucid/image/film.h"
#include "pellucid/image/image.h"
#include "pellucid/math/spectrum.h"
#include "pellucid/sampling/rng.h"

namespace pellucid {
class Scene;
struct Ray;

struct RenderOptions {
    int spp = -1;                 ///< samples per pixel; -1 = the scene's sample_count
    int64_t seed = -1;            ///< -1 = the scene's seed
    int threads = 0;              ///< 0 = all hardware threads
    double time_budget = 0.0;     ///< seconds; > 0 stops after the pass that exceeds it
    double target_rel_error = 0;  ///< > 0 stops once the mean relative standard error falls below it
    bool progress = false;        ///< draw a progress bar on stderr if stderr is a terminal
    const std::atomic<bool>* cancel = nullptr;  ///< set to true to stop after the current tiles
};

struct RenderStats {
    int spp = 0;               ///< samples per pixel actually reached (minimum over pixels)
    double seconds = 0.0;      ///< wall time of the render loop
    uint64_t samples = 0;      ///< camera samples taken
    uint64_t invalid_samples = 0;  ///< NaN/Inf/negative samples, kept out of the film
    bool cancelled = false;
};

struct RenderResult {
    Image image;     ///< per-pixel mean radiance
    Image variance;  ///< per-pixel variance of that mean
    RenderStats stats;
};

/// Per-sample radiance estimator: L(ray, rng).
using SampleFn = std::function<Spectrum(const Ray&, PCG32&)>;

/// Render `scene` into a film with the given estimator: tiles of 16×16 pixels run in parallel,
/// in passes of samples; every (pixel, sample index, seed) has its own PCG32 stream, so the image
/// is bit-identical for any thread count.
RenderResult render_loop(const Scene& scene, const RenderOptions& opts,
                         const std::function<Spectrum(const Scene&, const Ray&, PCG32&)>& Li);
}  // namespace pellucid
