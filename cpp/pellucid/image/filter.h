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
inline float filter_radius(const Filter& f) {
    return std::visit([](const auto& k) { return k.radius_px(); }, f);
}
inline std::string to_string(const Filter& f) {
    return std::visit([](const auto& x) { return x.to_string(); }, f);
}
}  // namespace pellucid
