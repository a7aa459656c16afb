// Film accumulation.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/image/film.h"

#include <algorithm>
#include <atomic>
#include <cmath>

namespace pellucid {

namespace {
constexpr int kMaxTaps = 2 * 16 + 1;  // filters are limited to a 16-pixel radius (registry.cpp)

/// The tap rows of the first sample of the pair this thread is splatting: a pixel's samples arrive
/// one after another, so the second sample finds its partner's taps here instead of evaluating them
/// again (the same numbers; the lookup checks film, pixel and sample count).
struct TapCache {
    uint64_t film = 0;  ///< Film::m_id, 0 = empty
    size_t pixel = 0;
    uint64_t n = 0;     ///< the pixel's sample count after the cached sample
    float wx[kMaxTaps], wy[kMaxTaps];
};
thread_local TapCache t_taps;
std::atomic<uint64_t> g_film_ids{0};

/// A box of radius ½ gives each sample weight 1 in its own pixel and 0 elsewhere: splatting with it
/// is filter sampling.
bool is_one_pixel_box(const Filter& f) {
    const auto* b = std::get_if<BoxFilter>(&f);
    return b && b->radius == 0.5f;
}
}  // namespace

Film::Film(int width, int height, std::optional<Filter> splat)
    : m_width(width), m_height(height), m_splat(std::move(splat)) {
    if (m_splat && is_one_pixel_box(*m_splat)) m_splat.reset();
    if (m_splat) {
        m_id = g_film_ids.fetch_add(1, std::memory_order_relaxed) + 1;
        // Pixel centres px + ½ within the radius r of a sample in [x, x + 1) satisfy
        // |px − x| <= ⌈r − ½⌉.
        m_margin = std::max(0, int(std::ceil(filter_radius(*m_splat) - 0.5f)));
        m_splats.resize(size_t(width) * height);
    } else {
        m_pixels.resize(size_t(width) * height);
    }
}

void Film::splat(int x, int y, float fx, float fy, const Spectrum& L) {
    if (!m_splat) {
        add_sample(x, y, L);
        return;
    }
    const int m = std::min(m_margin, 16), n_taps = 2 * m + 1;
    // Row and column weights of this sample and, for the second sample of a pair, of the first
    // (film.h); zero otherwise.
    float wx[kMaxTaps], wy[kMaxTaps], px[kMaxTaps], py[kMaxTaps];
    eval_filter_taps(*m_splat, float(x - m) + 0.5f - fx, n_taps, wx);
    eval_filter_taps(*m_splat, float(y - m) + 0.5f - fy, n_taps, wy);
    const size_t src_index = size_t(y) * m_width + x;
    SplatPixel& src = m_splats[src_index];
    const bool second = src.n % 2 == 1;
    TapCache& cache = t_taps;
    if (!second) {
        std::fill(px, px + n_taps, 0.f);
        std::fill(py, py + n_taps, 0.f);
        cache.film = m_id;
        cache.pixel = src_index;
        cache.n = src.n + 1;
        std::copy(wx, wx + n_taps, cache.wx);
        std::copy(wy, wy + n_taps, cache.wy);
    } else if (cache.film == m_id && cache.pixel == src_index && cache.n == src.n) {
        std::copy(cache.wx, cache.wx + n_taps, px);
        std::copy(cache.wy, cache.wy + n_taps, py);
    } else {
        eval_filter_taps(*m_splat, float(x - m) + 0.5f - src.last_fx, n_taps, px);
        eval_filter_taps(*m_splat, float(y - m) + 0.5f - src.last_fy, n_taps, py);
    }
    // Targets with a nonzero weight inside the film: columns x + i0 .. x + i1, rows y + j0 .. y + j1
    // (a filter's support is an interval, so zero taps lie only at the ends of a row).
    int i0 = -m, i1 = m, j0 = -m, j1 = m;
    while (i0 < i1 && !(wx[i0 + m] > 0.f) && !(px[i0 + m] > 0.f)) ++i0;
    while (i1 > i0 && !(wx[i1 + m] > 0.f) && !(px[i1 + m] > 0.f)) --i1;
    while (j0 < j1 && !(wy[j0 + m] > 0.f) && !(py[j0 + m] > 0.f)) ++j0;
    while (j1 > j0 && !(wy[j1 + m] > 0.f) && !(py[j1 + m] > 0.f)) --j1;
    i0 = std::max(i0, -x), i1 = std::min(i1, m_width - 1 - x);
    j0 = std::max(j0, -y), j1 = std::min(j1, m_height - 1 - y);
    const double l[3] = {L[0], L[1], L[2]};
    const double lp[3] = {src.last_l[0], src.last_l[1], src.last_l[2]};
    for (int j = j0; j <= j1; ++j) {
        const double wyj = wy[j + m], pyj = py[j + m];
        SplatPixel* row = &m_splats[size_t(y + j) * m_width + x];
        if (!second) {
            for (int i = i0; i <= i1; ++i) {
                const double w = double(wx[i + m]) * wyj;
                SplatPixel& t = row[i];
                t.w += w;
                for (int k = 0; k < 3; ++k) t.wl[k] += w * l[k];
            }
            continue;
        }
        for (int i = i0; i <= i1; ++i) {
            const double w = double(wx[i + m]) * wyj, wp = double(px[i + m]) * pyj, dw = w - wp;
            SplatPixel& t = row[i];
            t.w += w;
            t.dw2 += dw * dw;
            for (int k = 0; k < 3; ++k) {
                t.wl[k] += w * l[k];
                const double dl = w * l[k] - wp * lp[k];
                t.dl2[k] += dl * dl;
                t.dldw[k] += dl * dw;
            }
        }
    }
    src.n += 1;
    if (second) return;
    src.last_fx = fx;
    src.last_fy = fy;
    for (int k = 0; k < 3; ++k) src.last_l[k] = L[k];
}

void Film::pixel_stats(size_t i, double mean[3], double var[3]) const {
    if (!splats()) {
        const Pixel& p = m_pixels[i];
        for (int k = 0; k < 3; ++k) {
            mean[k] = p.mean[k];
            var[k] = p.n > 1 ? p.m2[k] / double(p.n - 1) / double(p.n) : 0.0;
        }
        return;
    }
    const SplatPixel& p = m_splats[i];
    if (!(p.w > 0.0)) {
        for (int k = 0; k < 3; ++k) mean[k] = var[k] = 0.0;
        return;
    }
    // ⌊n/2⌋ pairs of each stratum estimate 2⌊n/2⌋ Var_q; its share of Var(Σ z) is n Var_q (film.h).
    const double scale = p.n > 1 ? double(p.n) / (2.0 * double(p.n / 2)) / (p.w * p.w) : 0.0;
    for (int k = 0; k < 3; ++k) {
        const double r = p.wl[k] / p.w;
        const double s = p.dl2[k] - 2.0 * r * p.dldw[k] + r * r * p.dw2;  // Σ (Δ(wL) − R Δw)²
        mean[k] = r;
        var[k] = std::max(0.0, s) * scale;
    }
}

Image Film::mean() const {
    Image img(m_width, m_height, 3);
    double m[3], v[3];
    for (size_t i = 0; i < size_t(m_width) * m_height; ++i) {
        pixel_stats(i, m, v);
        for (int k = 0; k < 3; ++k) img.data[3 * i + k] = float(m[k]);
    }
    return img;
}

Image Film::variance() const {
    Image img(m_width, m_height, 3);
    double m[3], v[3];
    for (size_t i = 0; i < size_t(m_width) * m_height; ++i) {
        pixel_stats(i, m, v);
        for (int k = 0; k < 3; ++k) img.data[3 * i + k] = float(v[k]);
    }
    return img;
}

double Film::mean_relative_variance() const {
    double sum = 0.0, m[3], v[3];
    const size_t n = size_t(m_width) * m_height;
    for (size_t i = 0; i < n; ++i) {
        if ((splats() ? m_splats[i].n : m_pixels[i].n) < 2) return 1e30;
        pixel_stats(i, m, v);
        double lm = 0.2126 * m[0] + 0.7152 * m[1] + 0.0722 * m[2];
        double lv = 0.2126 * v[0] + 0.7152 * v[1] + 0.0722 * v[2];
        sum += lv / (lm * lm + 1e-4);
    }
    return sum / double(n);
}
}  // namespace pellucid
