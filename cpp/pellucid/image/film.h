// Film: per-pixel accumulation in double precision, with running mean and variance (Welford 1962),
// so the renderer can report the variance of every pixel's estimate.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <vector>

#include "pellucid/image/image.h"
#include "pellucid/math/spectrum.h"

namespace pellucid {

class Film {
public:
    Film(int width, int height);
    int width() const { return m_width; }
    int height() const { return m_height; }

    /// Add one sample of pixel (x, y). Not thread-safe for the same pixel; tiles own their pixels.
    void add_sample(int x, int y, const Spectrum& L) {
        Pixel& p = m_pixels[size_t(y) * m_width + x];
        p.n += 1;
        double inv_n = 1.0 / double(p.n);
        for (int k = 0; k < 3; ++k) {
            double d = double(L[k]) - p.mean[k];
            p.mean[k] += d * inv_n;
            p.m2[k] += d * (double(L[k]) - p.mean[k]);
        }
    }
    /// Per-pixel mean, float RGB.
    Image mean() const;
    /// Per-pixel variance of the mean estimate (sample variance / n), float RGB.
    Image variance() const;
    uint64_t samples(int x, int y) const { return m_pixels[size_t(y) * m_width + x].n; }
    /// Mean over pixels of the relative variance of each pixel's estimate, Var/(mean²+1e-4), on
    /// luminance; the quantity target_rel_error drives to e². The luminance variance is the weighted
    /// sum of channel variances, ignoring cross-channel covariance: a stopping estimate, not a
    /// statistic tests rely on.
    double mean_relative_variance() const;

private:
    struct Pixel {
        double mean[3] = {0, 0, 0};
        double m2[3] = {0, 0, 0};
        uint64_t n = 0;
    };
    int m_width, m_height;
    std::vector<Pixel> m_pixels;
};
}  // namespace pellucid
