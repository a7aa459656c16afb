// Tiled progressive render loop.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/integrator/render_loop.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>

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

RenderResult render_loop(const Scene& scene, const RenderOptions& opts, const TileFn& tile_fn) {
    const int W = scene.width, H = scene.height;
    const int spp = opts.spp > 0 ? opts.spp : scene.spp;
    if (opts.spp == 0) throw Error("spp: value 0 must be >= 1");
    const uint64_t seed = opts.seed >= 0 ? uint64_t(opts.seed) : scene.seed;
    const bool adaptive = opts.time_budget > 0.0 || opts.target_rel_error > 0.0;
    const int total_spp = adaptive && opts.spp <= 0 ? (1 << 24) : spp;

    Film film(W, H, scene.film_splatting ? std::optional<Filter>(scene.filter) : std::nullopt);
    // Tiles of one colour (tx mod P, ty mod P) are (P − 1)·kTile pixels apart, at least twice the
    // splat margin, so their splats never overlap.
    const int P = 1 + (2 * film.splat_margin() + kTile - 1) / kTile;
    const int tiles_x = (W + kTile - 1) / kTile, tiles_y = (H + kTile - 1) / kTile;
    std::atomic<uint64_t> invalid{0};
    std::atomic<int64_t> tiles_done{0};
    ProgressBar bar(opts.progress);
    auto t0 = std::chrono::steady_clock::now();
    auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
    auto cancelled = [&] { return opts.cancel && opts.cancel->load(std::memory_order_relaxed); };

    RenderStats stats;
    int done = 0;
    // Passes double in size (1, 1, 2, 4, ... spp) so budgets are checked often early and rarely later.
    int pass = std::max(1, std::min(total_spp, adaptive ? 1 : std::max(1, spp / 8)));
    while (done < total_spp && !stats.cancelled) {
        int s0 = done, s1 = std::min(total_spp, done + pass);
        int64_t n_tiles = int64_t(tiles_x) * tiles_y;
        for (int colour = 0; colour < P * P; ++colour) {
            const int cx = colour % P, cy = colour / P;
            const int64_t gx = (tiles_x - cx + P - 1) / P, gy = (tiles_y - cy + P - 1) / P;  // tiles of this colour
            if (gx <= 0 || gy <= 0) continue;
            parallel_for(gx * gy, opts.threads, [&](int64_t g) {
                if (cancelled()) return;
                const int tx = (cx + int(g % gx) * P) * kTile, ty = (cy + int(g / gx) * P) * kTile;
                TileJob job{tx, ty, std::min(tx + kTile, W), std::min(ty + kTile, H), s0, s1, seed};
                uint64_t bad = tile_fn(job, film);
                invalid += bad;
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
        if (cancelled()) {
            stats.cancelled = true;
            // Tiles that finished this pass keep their samples; report the least-sampled pixel.
        } else {
            done = s1;
        }
        if (opts.time_budget > 0.0 && elapsed() >= opts.time_budget) break;
        if (opts.target_rel_error > 0.0 && done >= 2 &&
            std::sqrt(film.mean_relative_variance()) <= opts.target_rel_error)
            break;
        pass = adaptive ? std::max(1, std::min(done, 64)) : pass;
    }
    bar.finish();
    if (opts.progress_out) opts.progress_out->fraction.store(1.0, std::memory_order_relaxed);
    stats.seconds = elapsed();
    stats.invalid_samples = invalid.load();
    uint64_t min_n = ~0ull, total = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            min_n = std::min(min_n, film.samples(x, y));
            total += film.samples(x, y);
        }
    stats.spp = int(min_n == ~0ull ? 0 : min_n);
    stats.samples = total + stats.invalid_samples;
    return RenderResult{film.mean(), film.variance(), stats};
}
}  // namespace pellucid
