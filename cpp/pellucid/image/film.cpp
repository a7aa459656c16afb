// Film accumulation.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/image/film.h"

#include <algorithm>
#include <cmath>

namespace pellucid {

namespace {
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
    constexpr int kMaxTaps = 2 * 16 + 1;  // filters are limited to a 16-pixel radius (registry.cpp)
    const int m = std::min(m_margin, 16), n_taps = 2 * m + 1;
    // Row and column weights of this sample and of the previous sample of the same pixel (zero if
    // there is none): the pair gives each target one successive difference (film.h).
    float wx[kMaxTaps], wy[kMaxTaps], px[kMaxTaps], py[kMaxTaps];
    eval_filter_taps(*m_splat, float(x - m) + 0.5f - fx, n_taps, wx);
    eval_filter_taps(*m_splat, float(y - m) + 0.5f - fy, n_taps, wy);
    SplatPixel& src = m_splats[size_t(y) * m_width + x];
    const bool has_prev = src.n > 0;
    if (has_prev) {
        eval_filter_taps(*m_splat, float(x - m) + 0.5f - src.last_fx, n_taps, px);
        eval_filter_taps(*m_splat, float(y - m) + 0.5f - src.last_fy, n_taps, py);
    } else {
        std::fill(px, px + n_taps, 0.f);
        std::fill(py, py + n_taps, 0.f);
    }
    const double l[3] = {L[0], L[1], L[2]};
    const double lp[3] = {src.last_l[0], src.last_l[1], src.last_l[2]};
    for (int j = -m; j <= m; ++j) {
        const int ty = y + j;
        if (ty < 0 || ty >= m_height || !(wy[j + m] > 0.f || py[j + m] > 0.f)) continue;
        for (int i = -m; i <= m; ++i) {
            const int tx = x + i;
            if (tx < 0 || tx >= m_width) continue;
            const double w = double(wx[i + m]) * double(wy[j + m]);
            const double wp = double(px[i + m]) * double(py[j + m]);
            if (!(w > 0.0) && !(wp > 0.0)) continue;
            SplatPixel& t = m_splats[size_t(ty) * m_width + tx];
            t.w += w;
            for (int k = 0; k < 3; ++k) t.wl[k] += w * l[k];
            if (has_prev) {
                const double dw = w - wp;
                t.dw2 += dw * dw;
                for (int k = 0; k < 3; ++k) {
                    const double dl = w * l[k] - wp * lp[k];
                    t.dl2[k] += dl * dl;
                    t.dldw[k] += dl * dw;
                }
            }
        }
    }
    src.n += 1;
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
    // n/(2(n − 1)) turns the n − 1 successive differences of each stratum into n Var_q (film.h).
    const double n = double(p.n);
    const double scale = p.n > 1 ? n / (2.0 * (n - 1.0)) / (p.w * p.w) : 0.0;
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
