// Image checks shared by the scene-level tests.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "pellucid/api.h"
#include "support/chi2.h"
#include "support/scene_util.h"

namespace pellucid::test {

/// The image mean of an image whose every pixel has the expected value `expected`, at α = 1e-4 with
/// its standard error from the spread of the pixel values (see below), and no invalid samples. Used
/// alone where estimates are heavy-tailed (long random walks behind total internal reflection), so
/// that a pixel's own sample variance is not a reliable scale at a test's sample count.
inline void expect_image_mean(const RenderResult& r, double expected, const std::string& what) {
    const size_t n = r.image.data.size();
    double sum = 0;
    for (size_t i = 0; i < n; ++i) sum += r.image.data[i];
    double mean = sum / double(n), spread = 0;
    for (size_t i = 0; i < n; ++i) spread += (r.image.data[i] - mean) * (r.image.data[i] - mean);
    double se = std::sqrt(spread / double(n - 1) / double(n));
    EXPECT_LT(std::fabs(mean - expected), z_two_sided(1e-4) * se + 1e-6)
        << what << ": image mean " << mean << " vs " << expected << " (standard error " << se << ")";
    EXPECT_EQ(r.stats.invalid_samples, 0u) << what;
}

/// An image whose every pixel has the expected value `expected` (white furnace, closed spheres...).
/// Per-pixel z-test as Mitsuba 3's render tests do it (../shared/REFERENCE.md §2.2): each pixel's own
/// variance, two-sided α = 0.01 Šidák-corrected over the pixel channels; no channel may fail. The
/// image mean is tested at α = 1e-4 with its standard error from the spread of the pixel values:
/// every pixel has the same expectation, so their spread measures the real per-pixel variance,
/// heavy tails included (NEE near a box's edges), which per-pixel sample variances miss when they
/// have not seen the rare large samples, and which Sobol samples' variances overestimate.
inline void expect_constant_image(const RenderResult& r, double expected, const std::string& what,
                                  bool pooled_variance = false) {
    const size_t n = r.image.data.size();
    const double z_max = z_two_sided(sidak_alpha(0.01, int(n)));
    double pooled = 0;
    if (pooled_variance) {
        for (size_t i = 0; i < n; ++i) pooled += r.variance.data[i];
        pooled /= double(n);
    }
    int fails = 0;
    for (size_t i = 0; i < n; ++i) {
        // Float rounding of a path's sum (~1e-6 relative) bounds how exact a zero-variance
        // estimator (NEE inside a closed sphere) can be.
        const double v = pooled_variance ? pooled : r.variance.data[i];
        double d = std::fabs(r.image.data[i] - expected), s2 = v + std::pow(1e-6 * expected, 2);
        if (d / std::sqrt(s2) > z_max) ++fails;
    }
    EXPECT_EQ(fails, 0) << what << ": pixels failing the per-pixel z-test (|z| > " << z_max << ")"
                        << (pooled_variance ? " against the pooled variance" : "");
    expect_image_mean(r, expected, what);
}
/// expect_constant_image for an image whose pixels are identically distributed (a uniform view of a
/// uniform scene): each pixel is tested against the pooled variance, the mean of all pixels' own
/// estimates, at the same α. A skewed estimator (a pixel's samples bounded above with a long lower
/// tail, as BSDF sampling of a smooth coat gives under uniform light) makes a pixel's own variance
/// small exactly where its mean is high, which the pooled estimate does not.
inline void expect_iid_constant_image(const RenderResult& r, double expected, const std::string& what) {
    expect_constant_image(r, expected, what, true);
}
}  // namespace pellucid::test
