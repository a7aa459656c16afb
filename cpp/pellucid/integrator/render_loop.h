// Render options and results, and the tiled, progressive render loop shared by all integrators.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "pellucid/image/film.h"
#include "pellucid/image/image.h"
#include "pellucid/math/spectrum.h"
#include "pellucid/sampling/sampler.h"
#include "pellucid/scene/scene.h"

namespace pellucid {

/// Progress of a running render, written by the render loop and polled by another thread (the
/// Python tqdm bar reads it while the render runs without the GIL): no callback, no lock.
struct RenderProgress {
    std::atomic<uint64_t> samples{0};  ///< camera samples finished so far (valid or not)
    std::atomic<double> fraction{0.0};  ///< estimated completed fraction in [0, 1]
};

struct RenderOptions {
    int spp = -1;                 ///< samples per pixel; -1 = the scene's sample_count
    int64_t seed = -1;            ///< -1 = the scene's seed (on resume: the state's)
    int threads = 0;              ///< 0 = all hardware threads
    double time_budget = 0.0;     ///< seconds; > 0 stops after the pass that exceeds it
    double target_rel_error = 0;  ///< > 0 stops once the mean relative standard error falls below it
    bool progress = false;        ///< draw a progress bar on stderr if stderr is a terminal
    /// Set to true (from any thread or a signal handler) to stop: the render returns within one
    /// pass or, for long passes, within the tiles in flight (see render_loop).
    const std::atomic<bool>* cancel = nullptr;
    RenderProgress* progress_out = nullptr;     ///< if set, updated after every tile
    std::string sampler;          ///< "" = the scene's sampler type; else "independent" | "sobol"
    /// Estimate each pixel's variance (RenderResult::variance). Off, a splatting film keeps only the
    /// sums of the mean (no pair sums); the image is the same, bit for bit.
    /// target_rel_error turns it on. A resumed film state keeps the setting it was rendered with
    /// (asking for variance from a state without it is an error).
    bool variance = true;
    /// Continue this film state (a render of the same scene, size, filter, seed and sampler)
    /// up to `spp` instead of starting from an empty film.
    std::shared_ptr<const FilmState> resume;
};

struct RenderStats {
    int spp = 0;               ///< samples per pixel in every pixel (complete passes)
    double seconds = 0.0;      ///< wall time of the render loop (on resume: including the state's)
    uint64_t samples = 0;      ///< camera samples taken
    uint64_t invalid_samples = 0;  ///< NaN/Inf/negative samples, kept out of the film
    bool cancelled = false;
};

struct RenderResult {
    Image image;     ///< per-pixel mean radiance
    Image variance;  ///< per-pixel variance of that mean (empty, 0×0, when the film kept none)
    RenderStats stats;
    /// The film after stats.spp samples per pixel, to continue with RenderOptions::resume or to
    /// save with save_film_state (the front ends fill in FilmState::integrator).
    std::shared_ptr<FilmState> state;
};

/// One unit of parallel work: pixels [x0, x1) × [y0, y1), sample indices [s0, s1).
struct TileJob {
    int x0, y0, x1, y1, s0, s1;
    uint64_t seed;
};
/// Renders one tile into the film (it owns those pixels) and returns the number of invalid samples.
using TileFn = std::function<uint64_t(const TileJob&, Film&)>;

/// Render with a per-tile function: tiles of 16×16 pixels run in parallel, in passes over the whole
/// film, so that after every pass each pixel has the same number of samples. The std::function is
/// called once per tile, never per sample or per ray.
///
/// Passes. With filter sampling, a pixel's samples enter the film in sample order however the
/// samples are cut into passes, so pass sizes follow the measured speed: a pass takes about 0.1 s
/// (at least 1 spp), and the image does not depend on them. A splatting film
/// (scene.film_splatting) writes past a tile's edge, so each pass runs in P×P colour groups of tiles
/// at least one splat radius apart: no two tiles running together touch the same pixel. The order
/// in which a pixel receives its neighbours' splats then depends on where passes begin, so those
/// passes are fixed by the film's size: samples [nk, nk + n), n from 2 to 16 and even, so whole
/// variance pairs (film.h) per pixel (render_loop.cpp, splat_pass_spp), the same for every thread
/// count and every run. With target_rel_error, passes also end at spp 2, 4, 8, ..., 64 and every
/// multiple of 64, where the error is tested, so where the render stops does not depend on speed.
///
/// Cancellation (RenderOptions::cancel). A pass expected to take longer than 0.25 s keeps a copy of
/// the film from before it: on cancellation the tiles not yet started are skipped and the film goes
/// back to that copy. A shorter pass is finished. Either way the render stops within about 0.25 s
/// (plus the tiles in flight) and returns a film of whole passes.
///
/// Resume (RenderOptions::resume). The film continues from the state's spp with the state's seed;
/// a different size, reconstruction filter or sampler is an error (pellucid::Error). Every pass
/// boundary of a finished or cancelled render is a pass boundary of a longer one, so a resumed render
/// is bit-identical to an uninterrupted render with the same seed (for splatting films this needs
/// the state's spp to be even, as it is for every cancelled render).
RenderResult render_loop(const Scene& scene, const RenderOptions& opts, const TileFn& tile_fn);

/// The most samples per pixel a splatting pass takes.
constexpr int kMaxSplatPassSpp = 16;

/// Samples per pixel of every splatting pass of a W×H film (without a time budget): even, from 2 to
/// kMaxSplatPassSpp, fixed by the film's size and never by the speed (render_loop.cpp).
int splat_pass_spp(int W, int H);

/// Which estimates the film accepts: radiance must be finite and non-negative; signed outputs
/// (normals, for the AOV integrator) only finite.
enum class SampleValues { NonNegative, Signed };

/// The sampler type of a render: RenderOptions::sampler if set (an unknown name throws
/// pellucid::Error), else the scene's.
inline SamplerType sampler_type(const Scene& scene, const RenderOptions& opts) {
    return opts.sampler.empty() ? scene.sampler : parse_sampler_type(opts.sampler, "sampler");
}

/// The film position of sample `sampler` in pixel (x, y), from the sample's dimensions 0 and 1:
/// splatting films take a uniform position in the pixel, the others an offset drawn from the filter.
inline void film_position(const Scene& scene, bool splat, int x, int y, Sampler& sampler, float* fx, float* fy) {
    const Vec2f u_px = sampler.get_pixel_2d();
    const Vec2f off = splat ? u_px - Vec2f(0.5f) : sample_filter(scene.filter, u_px);
    *fx = float(x) + 0.5f + off.x;
    *fy = float(y) + 0.5f + off.y;
}
/// The camera ray of sample `sampler` in pixel (x, y), through its film position (film_position),
/// which (fx, fy) receives. Differentials only where materials read footprints (Scene::needs_footprints).
inline void camera_sample(const Scene& scene, bool splat, int x, int y, Sampler& sampler, float* fx, float* fy,
                          RayDifferential* out) {
    film_position(scene, splat, x, y, sampler, fx, fy);
    if (scene.needs_footprints) {
        *out = scene.camera.generate_ray_differential(*fx, *fy);
    } else {
        const Ray r = scene.camera.generate_ray(*fx, *fy);
        out->set(r.o, r.d, r.tmax);
    }
}
inline RayDifferential camera_sample(const Scene& scene, bool splat, int x, int y, Sampler& sampler, float* fx, float* fy) {
    RayDifferential r;
    camera_sample(scene, splat, x, y, sampler, fx, fy, &r);
    return r;
}

/// Whether an estimate may enter the film: finite, and not negative under SampleValues::NonNegative.
template <SampleValues kValues>
bool valid_sample(const Spectrum& L) {
    return L.is_finite() && !(kValues == SampleValues::NonNegative && L.has_negative());
}

/// Hand one estimate to the film, or reject it (NaN, infinite, or negative under
/// SampleValues::NonNegative); returns false if rejected.
template <SampleValues kValues>
bool film_add(Film& film, int x, int y, float fx, float fy, const Spectrum& L) {
    if (!valid_sample<kValues>(L)) return false;
    if (film.splats()) film.splat(x, y, fx, fy, L);
    else film.add_sample(x, y, L);
    return true;
}

/// The per-sample loop every integrator instantiates with its own estimator Li(ray, sampler): every
/// (pixel, sample index, seed) has its own Sampler (sampling/sampler.h), so images are bit-identical
/// for any thread count. Rejected samples are counted and kept out of the film.
template <SampleValues kValues = SampleValues::NonNegative, class LiFn>
uint64_t render_tile(const Scene& scene, const TileJob& job, Film& film, SamplerType type, LiFn&& Li) {
    uint64_t bad = 0;
    const bool splat = film.splats();
    const uint64_t width = uint64_t(scene.width);
    for (int y = job.y0; y < job.y1; ++y)
        for (int x = job.x0; x < job.x1; ++x) {
            const uint64_t pixel = uint64_t(y) * width + uint64_t(x);
            for (int s = job.s0; s < job.s1; ++s) {
                Sampler sampler(type, pixel, uint64_t(s), job.seed);
                float fx, fy;
                const RayDifferential ray = camera_sample(scene, splat, x, y, sampler, &fx, &fy);
                if (!film_add<kValues>(film, x, y, fx, fy, Li(ray, sampler))) ++bad;
            }
        }
    return bad;
}
}  // namespace pellucid
