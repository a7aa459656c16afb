// Film: per-pixel accumulation in double precision that also estimates the variance of every
// pixel's estimate. Two reconstructions of the filtered image:
//  - filter sampling (default): one sample, one pixel, weight 1; running mean and variance by
//    Welford 1962, exact for independent samples;
//  - splatting: each sample is added to every pixel within the filter radius with weight w = f(Δx)f(Δy)
//    and the pixel is the ratio Σ wL / Σ w (Mitsuba 3's ImageBlock). Neighbouring samples share
//    pixels, so per-pixel noise is lower at equal spp (neighbouring pixels are correlated instead).
//    Its variance is the delta-method (linearised) variance of the ratio estimator,
//    Var R ≈ Σ w²(L − R)² / (Σ w)² (Cochran 1977, Sampling Techniques, eq. 6.13), kept from the
//    running sums Σw, Σw², Σw²L and Σw²L², with the small-sample factor n_eff/(n_eff − 1),
//    n_eff = (Σw)²/Σw² (Kish 1965), so that w = 1 gives the unbiased sample variance again.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <optional>
#include <vector>

#include "pellucid/image/filter.h"
#include "pellucid/image/image.h"
#include "pellucid/math/spectrum.h"

namespace pellucid {

class Film {
public:
    /// splat: the filter to splat with, or nullopt for filter sampling (add_sample).
    Film(int width, int height, std::optional<Filter> splat = std::nullopt);
    int width() const { return m_width; }
    int height() const { return m_height; }
    bool splats() const { return m_splat.has_value(); }
    /// How many pixels beyond its own a splat reaches (0 without splatting). Tiles closer than
    /// this must not be rendered at the same time (render_loop colours them).
    int splat_margin() const { return m_margin; }

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
    /// Splat one sample taken at film position (fx, fy) (pixel units) inside pixel (x, y) to every
    /// pixel whose centre lies within the filter radius. Writes pixels up to splat_margin() away.
    void splat(int x, int y, float fx, float fy, const Spectrum& L);

    /// Per-pixel estimate, float RGB.
    Image mean() const;
    /// Per-pixel variance of that estimate, float RGB.
    Image variance() const;
    /// Camera samples taken inside pixel (x, y).
    uint64_t samples(int x, int y) const {
        size_t i = size_t(y) * m_width + x;
        return splats() ? m_splats[i].n : m_pixels[i].n;
    }
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
    struct SplatPixel {
        double wl[3] = {0, 0, 0};    ///< Σ w L
        double w2l[3] = {0, 0, 0};   ///< Σ w² L
        double w2l2[3] = {0, 0, 0};  ///< Σ w² L²
        double w = 0, w2 = 0;        ///< Σ w, Σ w²
        uint64_t n = 0;              ///< samples taken in this pixel
    };
    // Estimate and variance of pixel i, channel k.
    void pixel_stats(size_t i, double mean[3], double var[3]) const;

    int m_width, m_height;
    std::optional<Filter> m_splat;
    int m_margin = 0;
    std::vector<Pixel> m_pixels;      // filter sampling
    std::vector<SplatPixel> m_splats; // splatting
};
}  // namespace pellucid
