// Film accumulation.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/image/film.h"

#include <algorithm>
#include <cmath>

namespace pellucid {

Film::Film(int width, int height, std::optional<Filter> splat)
    : m_width(width), m_height(height), m_splat(std::move(splat)) {
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
    constexpr int kMaxTaps = 2 * 16 + 1;  // filters are limited to a 16-pixel radius (registry.cpp)
    const int m = std::min(m_margin, 16);
    float wx[kMaxTaps], wy[kMaxTaps];
    eval_filter_taps(*m_splat, float(x - m) + 0.5f - fx, 2 * m + 1, wx);
    eval_filter_taps(*m_splat, float(y - m) + 0.5f - fy, 2 * m + 1, wy);
    m_splats[size_t(y) * m_width + x].n += 1;
    const double l[3] = {L[0], L[1], L[2]};
    for (int j = -m; j <= m; ++j) {
        int py = y + j;
        if (py < 0 || py >= m_height || !(wy[j + m] > 0.f)) continue;
        for (int i = -m; i <= m; ++i) {
            int px = x + i;
            if (px < 0 || px >= m_width) continue;
            double w = double(wx[i + m]) * double(wy[j + m]);
            if (!(w > 0.0)) continue;
            SplatPixel& p = m_splats[size_t(py) * m_width + px];
            double w2 = w * w;
            p.w += w;
            p.w2 += w2;
            for (int k = 0; k < 3; ++k) {
                p.wl[k] += w * l[k];
                p.w2l[k] += w2 * l[k];
                p.w2l2[k] += w2 * l[k] * l[k];
            }
        }
    }
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
    const double n_eff = p.w * p.w / p.w2;
    const double correction = n_eff > 1.0 + 1e-9 ? n_eff / (n_eff - 1.0) : 0.0;
    for (int k = 0; k < 3; ++k) {
        double r = p.wl[k] / p.w;
        double s = p.w2l2[k] - 2.0 * r * p.w2l[k] + r * r * p.w2;  // Σ w²(L − R)²
        mean[k] = r;
        var[k] = std::max(0.0, s) / (p.w * p.w) * correction;
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
