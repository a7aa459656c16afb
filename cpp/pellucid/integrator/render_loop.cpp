// Tiled progressive render loop.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/integrator/render_loop.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <vector>

#include "pellucid/scene/scene.h"
#include "pellucid/util/error.h"
#include "pellucid/util/parallel.h"

namespace pellucid {
namespace {
constexpr int kTile = 16;

/// a = max(a, v) atomically: tiles finish out of order across threads, the fraction must not go back.
void store_max(std::atomic<double>& a, double v) {
    double seen = a.load(std::memory_order_relaxed);
    while (seen < v && !a.compare_exchange_weak(seen, v, std::memory_order_relaxed)) {
    }
}

class ProgressBar {
public:
    explicit ProgressBar(bool enabled) : m_enabled(enabled && isatty(STDERR_FILENO)) {}
    void update(double fraction, double seconds) {
        if (!m_enabled) return;
        std::lock_guard<std::mutex> lock(m_mutex);
        int width = 40, filled = int(std::round(fraction * width));
        std::fprintf(stderr, "\rrendering [%.*s%*s] %5.1f%% %6.1fs", filled,
                     "########################################", width - filled, "", 100.0 * fraction, seconds);
        std::fflush(stderr);
    }
    void finish() {
        if (m_enabled) std::fprintf(stderr, "\n");
    }

private:
    bool m_enabled;
    std::mutex m_mutex;
};
}  // namespace

namespace {
constexpr double kPassSeconds = 0.1;   ///< aimed-for duration of a filter-sampling pass
/// The samples a splatting pass adds to the whole film: passes take 2–16 spp, the most (in steps of
/// two, so that every pass holds whole variance pairs) that stays within this. Each pass costs its
/// tiles' setup, P² synchronisations (one per tile colour) and the partly filled packets at the end of
/// each tile, so small films gain from longer passes: a 256×256 film took 5–9 % less time with 8 spp
/// a pass than with 2, and 2–6 % less with 16 than with 8 on four of five suite scenes (the fifth 3 %
/// more, within the noise), but no less with 32 (bench/suite, 2
/// threads, bench/README.md); the bound keeps passes of large films, which an interrupt may discard,
/// short.
constexpr int64_t kSplatPassSamples = int64_t(1) << 21;

constexpr double kUndoSeconds = 0.25;  ///< passes expected to be longer keep a copy to cancel into

bool same_filter(const Filter& a, const Filter& b) {
    if (a.index() != b.index()) return false;
    if (const auto* g = std::get_if<GaussianFilter>(&a))
        return g->stddev == std::get<GaussianFilter>(b).stddev && g->shift == std::get<GaussianFilter>(b).shift;
    return filter_radius(a) == filter_radius(b);
}

/// The state's film, checked against the scene and options of the render that continues it.
void check_resume(const FilmState& st, const Scene& scene, const RenderOptions& opts, const std::string& sampler) {
    auto fail = [](const std::string& what) { throw Error("resume: " + what); };
    if (st.film.width() != scene.width || st.film.height() != scene.height)
        fail("the film state is " + std::to_string(st.film.width()) + "x" + std::to_string(st.film.height()) +
             " pixels, the scene " + std::to_string(scene.width) + "x" + std::to_string(scene.height));
    const bool splats = Film(1, 1, scene.film_splatting ? std::optional<Filter>(scene.filter) : std::nullopt).splats();
    if (st.film.splats() != splats)
        fail(std::string("the film state ") + (st.film.splats() ? "splats samples" : "samples the filter") +
             ", the scene's film " + (splats ? "splats samples" : "samples the filter"));
    if (!same_filter(st.filter, scene.filter))
        fail("the film state's filter is " + to_string(st.filter) + ", the scene's " + to_string(scene.filter));
    if (st.sampler != sampler)
        fail("the film state used the " + st.sampler + " sampler, this render the " + sampler +
             " sampler (set the sampler to '" + st.sampler + "')");
    if (!st.film.has_variance() && (opts.variance || opts.target_rel_error > 0.0))
        fail(std::string("the film state was rendered without variance, and this render ") +
             (opts.target_rel_error > 0.0 ? "stops at a target_rel_error, which needs it"
                                          : "asks for variance (the variance AOV, or render_with_stats' variance=True)") +
             ": resume it without");
    if (opts.seed >= 0 && uint64_t(opts.seed) != st.seed)
        fail("the film state used seed " + std::to_string(st.seed) + ", this render asks for seed " +
             std::to_string(opts.seed) + " (leave the seed unset to continue with the state's)");
}

/// The end of the target_rel_error test point after `done`: 2, 4, 8, ..., 64, then every 64.
int next_error_test(int done) {
    if (done < 2) return 2;
    if (done < 64) {
        int p = 2;
        while (p <= done) p *= 2;
        return p;
    }
    return (done / 64 + 1) * 64;
}
}  // namespace

int splat_pass_spp(int W, int H) {
    const int64_t n = kSplatPassSamples / std::max<int64_t>(1, int64_t(W) * H);
    return int(std::clamp<int64_t>(n / 2 * 2, 2, kMaxSplatPassSpp));
}

RenderResult render_loop(const Scene& scene, const RenderOptions& opts, const TileFn& tile_fn) {
    const int W = scene.width, H = scene.height;
    if (opts.spp == 0) throw Error("spp: value 0 must be >= 1");
    const int spp = opts.spp > 0 ? opts.spp : scene.spp;
    const std::string sampler = to_string(sampler_type(scene, opts));
    if (opts.resume) check_resume(*opts.resume, scene, opts, sampler);
    const uint64_t seed = opts.resume ? opts.resume->seed : opts.seed >= 0 ? uint64_t(opts.seed) : scene.seed;
    const bool adaptive = opts.time_budget > 0.0 || opts.target_rel_error > 0.0;
    const int total_spp = adaptive && opts.spp <= 0 ? (1 << 24) : spp;
    const int start_spp = opts.resume ? opts.resume->spp : 0;
    if (total_spp < start_spp)
        throw Error("spp: value " + std::to_string(total_spp) + " is below the " + std::to_string(start_spp) +
                    " spp the resumed film state already has");

    const std::optional<Filter> splat_filter =
        scene.film_splatting ? std::optional<Filter>(scene.filter) : std::nullopt;
    const bool variance = opts.resume ? opts.resume->film.has_variance() : opts.variance || opts.target_rel_error > 0.0;
    auto state = std::make_shared<FilmState>(FilmState{
        opts.resume ? opts.resume->film : Film(W, H, splat_filter, variance), scene.filter, start_spp, seed, sampler, "", 0,
        0.0});
    Film& film = state->film;
    // Tiles of one colour (tx mod P, ty mod P) are (P − 1)·kTile pixels apart, at least twice the
    // splat margin, so their splats never overlap.
    const int P = 1 + (2 * film.splat_margin() + kTile - 1) / kTile;
    const int tiles_x = (W + kTile - 1) / kTile, tiles_y = (H + kTile - 1) / kTile;
    const int64_t n_tiles = int64_t(tiles_x) * tiles_y;
    uint64_t invalid = opts.resume ? opts.resume->invalid_samples : 0;
    const double seconds0 = opts.resume ? opts.resume->seconds : 0.0;
    std::atomic<uint64_t> pass_invalid{0};
    std::atomic<int64_t> tiles_done{0};
    std::atomic<bool> skipped{false};
    std::optional<Film> backup;  // the film before the current pass, when it can be cancelled midway
    ProgressBar bar(opts.progress);
    auto t0 = std::chrono::steady_clock::now();
    auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
    auto cancelled = [&] { return opts.cancel && opts.cancel->load(std::memory_order_relaxed); };

    // Each tile's render seconds per spp in the last pass (the order of the next pass's tiles).
    std::vector<float> tile_cost(size_t(n_tiles), 0.f);
    std::vector<int64_t> order;
    RenderStats stats;
    int done = start_spp;
    double seconds_per_spp = -1.0;  // measured on the previous pass; < 0 until one has run
    while (done < total_spp && !stats.cancelled) {
        // This pass: samples [s0, s1).
        const int s0 = done;
        int s1;
        if (film.splats()) {
            // (A time budget keeps passes of 2 spp, so that the render stops close to it.)
            const int k = opts.time_budget > 0.0 ? 2 : splat_pass_spp(W, H);
            s1 = s0 / k * k + k;
        } else if (seconds_per_spp < 0.0) {
            s1 = s0 + 1;
        } else {
            double n = kPassSeconds / std::max(seconds_per_spp, 1e-9);
            if (opts.time_budget > 0.0) n = std::min(n, (opts.time_budget - elapsed()) / std::max(seconds_per_spp, 1e-9));
            s1 = s0 + int(std::clamp(n, 1.0, double(1 << 24)));
        }
        if (opts.target_rel_error > 0.0) s1 = std::min(s1, next_error_test(s0));
        s1 = std::min(s1, total_spp);
        // A pass that may run long keeps the film to return to if it is cancelled midway.
        const bool undoable = seconds_per_spp < 0.0 || seconds_per_spp * (s1 - s0) > kUndoSeconds;
        if (undoable && done > 0) backup = film;
        skipped = false;
        pass_invalid = 0;
        const double pass_t0 = elapsed();
        for (int colour = 0; colour < P * P; ++colour) {
            const int cx = colour % P, cy = colour / P;
            const int64_t gx = (tiles_x - cx + P - 1) / P, gy = (tiles_y - cy + P - 1) / P;  // tiles of this colour
            if (gx <= 0 || gy <= 0) continue;
            // The colour's tiles, the costliest of the last pass first (in the first pass, in
            // raster order): the threads then finish together, with the cheapest tiles last. The
            // order does not change the image: tiles of one colour write disjoint pixels.
            order.resize(size_t(gx * gy));
            for (int64_t g = 0; g < gx * gy; ++g) order[size_t(g)] = g;
            auto tile_of = [&](int64_t g) { return (cy + g / gx * P) * tiles_x + cx + g % gx * P; };
            if (done > start_spp)
                std::stable_sort(order.begin(), order.end(), [&](int64_t a, int64_t b) {
                    return tile_cost[size_t(tile_of(a))] > tile_cost[size_t(tile_of(b))];
                });
            parallel_for_in_order(gx * gy, opts.threads, [&](int64_t rank) {
                if (undoable && cancelled()) {
                    skipped.store(true, std::memory_order_relaxed);
                    return;
                }
                const int64_t g = order[size_t(rank)];
                const int tx = (cx + int(g % gx) * P) * kTile, ty = (cy + int(g / gx) * P) * kTile;
                TileJob job{tx, ty, std::min(tx + kTile, W), std::min(ty + kTile, H), s0, s1, seed};
                const auto tile_t0 = std::chrono::steady_clock::now();
                pass_invalid += tile_fn(job, film);
                tile_cost[size_t(tile_of(g))] =
                    std::chrono::duration<float>(std::chrono::steady_clock::now() - tile_t0).count() / float(s1 - s0);
                int64_t k = ++tiles_done;
                double frac = opts.time_budget > 0.0
                                  ? elapsed() / opts.time_budget
                                  : (double(s0) * n_tiles + double(s1 - s0) * double(k)) / (double(total_spp) * n_tiles);
                bar.update(std::min(1.0, frac), elapsed());
                if (opts.progress_out) {
                    uint64_t n = uint64_t(job.x1 - job.x0) * uint64_t(job.y1 - job.y0) * uint64_t(s1 - s0);
                    opts.progress_out->samples.fetch_add(n, std::memory_order_relaxed);
                    store_max(opts.progress_out->fraction, std::min(1.0, frac));
                }
            });
        }
        tiles_done = 0;
        if (skipped) {
            // Cancelled midway: back to the film of complete passes.
            if (done > 0) film = std::move(*backup);
            else film = Film(W, H, splat_filter, variance);
            stats.cancelled = true;
            break;
        }
        done = s1;
        invalid += pass_invalid.load();
        seconds_per_spp = (elapsed() - pass_t0) / double(s1 - s0);
        if (cancelled()) stats.cancelled = true;
        if (opts.time_budget > 0.0 && elapsed() >= opts.time_budget) break;
        if (opts.target_rel_error > 0.0 && done >= 2 && done == next_error_test(done - 1) &&
            std::sqrt(film.mean_relative_variance()) <= opts.target_rel_error)
            break;
    }
    backup.reset();
    bar.finish();
    if (opts.progress_out) opts.progress_out->fraction.store(1.0, std::memory_order_relaxed);
    stats.seconds = seconds0 + elapsed();
    stats.invalid_samples = invalid;
    stats.spp = done;
    stats.samples = uint64_t(W) * uint64_t(H) * uint64_t(done);
    state->spp = done;
    state->invalid_samples = invalid;
    state->seconds = stats.seconds;
    RenderResult r{film.mean(), film.has_variance() ? film.variance() : Image(), stats, nullptr};
    r.state = std::move(state);
    return r;
}
}  // namespace pellucid
