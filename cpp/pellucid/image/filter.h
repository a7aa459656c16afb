// Pixel reconstruction filters. By default they are applied by filter importance sampling: each
// camera sample is offset from the pixel centre with a density proportional to the filter, so its
// weight is 1 and every sample lands in exactly one pixel (pbrt-v4 §8.8). With the film's
// "splatting" reconstruction, samples are uniform in their pixel and every sample is added to all
// pixels within the radius with weight f(x)·f(y) (Mitsuba 3's ImageBlock; image/film.h).
// SPDX-License-Identifier: Apache-2.0
//
// | type     | parameter | default | meaning                               |
// |----------|-----------|---------|---------------------------------------|
// | box      | radius    | 0.5     | half-width in pixels                  |
// | tent     | radius    | 1.0     | half-width in pixels                  |
// | gaussian | stddev    | 0.5     | standard deviation in pixels; radius 4·stddev (Mitsuba 3) |
#pragma once
#include <algorithm>
#include <cmath>
#include <string>
#include <type_traits>
#include <variant>

#include "pellucid/math/vec.h"
#include "pellucid/sampling/warp.h"

namespace pellucid {
struct BoxFilter {
    float radius = 0.5f;
    Vec2f sample(Vec2f u) const { return (2.f * u - Vec2f(1.f)) * radius; }
    float eval(float x) const { return std::fabs(x) <= radius ? 1.f : 0.f; }
    float radius_px() const { return radius; }
    std::string to_string() const { return "BoxFilter[radius=" + std::to_string(radius) + "]"; }
};
struct TentFilter {
    float radius = 1.f;
    Vec2f sample(Vec2f u) const { return Vec2f(sample_tent(u.x, radius), sample_tent(u.y, radius)); }
    float eval(float x) const { return std::max(0.f, radius - std::fabs(x)); }
    float radius_px() const { return radius; }
    std::string to_string() const { return "TentFilter[radius=" + std::to_string(radius) + "]"; }
};
struct GaussianFilter {
    float stddev = 0.5f;
    Vec2f sample(Vec2f u) const {
        // Separable: each axis is a Gaussian truncated at 4·stddev, sampled by inverting its CDF.
        return Vec2f(sample_truncated_gaussian(u.x, stddev, 4.f * stddev, m_erf_r),
                     sample_truncated_gaussian(u.y, stddev, 4.f * stddev, m_erf_r));
    }
    /// The same truncated Gaussian the sampler draws from (unnormalised: splat weights are ratios).
    float eval(float x) const {
        return std::fabs(x) < 4.f * stddev ? std::exp(-x * x / (2.f * stddev * stddev)) : 0.f;
    }
    float radius_px() const { return 4.f * stddev; }
    /// w[i] = eval(x0 + i) with two exponentials instead of n: with k = 1/(2σ²),
    /// e(x + 1) = e(x)·exp(−(2x + 1)k), and that ratio itself shrinks by exp(−2k) a step.
    void taps(float x0, int n, float* w) const {
        const float k = 1.f / (2.f * stddev * stddev), q = std::exp(-2.f * k), r_max = 4.f * stddev;
        float e = std::exp(-x0 * x0 * k), r = std::exp(-(2.f * x0 + 1.f) * k);
        for (int i = 0; i < n; ++i) {
            w[i] = std::fabs(x0 + float(i)) < r_max ? e : 0.f;
            e *= r;
            r *= q;
        }
    }
    explicit GaussianFilter(float s = 0.5f) : stddev(s), m_erf_r(std::erf(4.f * s / (s * 1.41421356f))) {}
    float m_erf_r;  ///< erf(radius/(σ√2)), the CDF range of the truncated Gaussian
    std::string to_string() const { return "GaussianFilter[stddev=" + std::to_string(stddev) + "]"; }
};
using Filter = std::variant<BoxFilter, TentFilter, GaussianFilter>;
inline Vec2f sample_filter(const Filter& f, Vec2f u) {
    return std::visit([&](const auto& x) { return x.sample(u); }, f);
}
/// The filter's 1D profile (all filters here are separable: f(x, y) = f(x)·f(y)).
inline float eval_filter(const Filter& f, float x) {
    return std::visit([&](const auto& k) { return k.eval(x); }, f);
}
/// w[i] = eval_filter(f, x0 + i) for i < n (one dispatch for a row of splat weights).
inline void eval_filter_taps(const Filter& f, float x0, int n, float* w) {
    std::visit([&](const auto& k) {
        if constexpr (std::is_same_v<std::decay_t<decltype(k)>, GaussianFilter>)
            k.taps(x0, n, w);
        else
            for (int i = 0; i < n; ++i) w[i] = k.eval(x0 + float(i));
    }, f);
}
inline float filter_radius(const Filter& f) {
    return std::visit([](const auto& k) { return k.radius_px(); }, f);
}
inline std::string to_string(const Filter& f) {
    return std::visit([](const auto& x) { return x.to_string(); }, f);
}
}  // namespace pellucid
