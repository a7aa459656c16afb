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
// |          | shift     | false   | subtract the value at the radius (pbrt-v4, Mitsuba 3)       |
#pragma once
#include <algorithm>
#include <cmath>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

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
/// A Gaussian of standard deviation σ, cut at the radius r = 4σ, with one of two profiles:
///  - truncated (default): g(x) = exp(−x²/2σ²) for |x| < r, which steps down by g(r) = e⁻⁸ ≈ 3.4e-4
///    at the radius;
///  - shifted (shift = true): max(0, g(x) − g(r)), which reaches 0 continuously at the radius (the
///    Gaussian of pbrt-v4 §8.8.4 and of Mitsuba 3's `gaussian` rfilter; the Mitsuba importer selects
///    it). The two differ in the tail: at |x| = 2σ the shifted weight is 99.7 % of the truncated
///    one, at 3.8σ 54 %.
/// Filter sampling draws offsets from the same profile: the truncated one by inverting the normal CDF,
/// the shifted one by solving its CDF, A·erf(x/(σ√2)) − g(r)·x with A = σ√(π/2), by safeguarded
/// Newton steps from the truncated inverse.
struct GaussianFilter {
    float stddev = 0.5f;
    bool shift = false;

    explicit GaussianFilter(float s = 0.5f, bool shift_to_zero = false)
        : stddev(s), shift(shift_to_zero), m_radius(4.f * s), m_k(1.f / (2.f * s * s)),
          m_bias(shift_to_zero ? std::exp(-8.f) : 0.f),
          m_erf_r(std::erf(4.f * s / (s * 1.41421356f))), m_q(std::exp(-2.f * m_k)) {}

    Vec2f sample(Vec2f u) const { return Vec2f(sample_1d(u.x), sample_1d(u.y)); }
    /// One axis: an offset in [−r, r] with density proportional to eval.
    float sample_1d(float u) const {
        const float x = sample_truncated_gaussian(u, stddev, m_radius, m_erf_r);
        if (!shift) return x;
        // Solve G(t) = |2u − 1|·G(r) for t in [0, r], G(t) = A·erf(t/(σ√2)) − b·t, G' = g(t) − b.
        const double sig = stddev, b = m_bias, r = m_radius, a = 1.0 / (sig * 1.4142135623730951);
        const double A = sig * 1.2533141373155003;  // σ√(π/2)
        const double s = 2.0 * double(u) - 1.0, target = std::fabs(s) * (A * std::erf(a * r) - b * r);
        double t = std::min(double(std::fabs(x)), r), lo = 0.0, hi = r;
        for (int it = 0; it < 32; ++it) {
            const double G = A * std::erf(a * t) - b * t - target;
            if (G > 0.0) hi = t;
            else lo = t;
            const double dG = std::exp(-t * t * double(m_k)) - b;
            double next = dG > 0.0 ? t - G / dG : 0.5 * (lo + hi);
            if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);  // Newton left the bracket: bisect
            if (std::fabs(next - t) <= 1e-7 * r) {
                t = next;
                break;
            }
            t = next;
        }
        return float(s < 0.0 ? -t : t);
    }
    float eval(float x) const {
        if (!(std::fabs(x) < m_radius)) return 0.f;
        const float g = std::exp(-x * x * m_k);
        return shift ? std::max(0.f, g - m_bias) : g;
    }
    float radius_px() const { return m_radius; }
    std::string to_string() const {
        return "GaussianFilter[stddev=" + std::to_string(stddev) + (shift ? ", shift" : "") + "]";
    }

    float m_radius;  ///< 4σ
    float m_k;       ///< 1/(2σ²)
    float m_bias;    ///< g(r) = e⁻⁸ when shifted, else 0
    float m_erf_r;   ///< erf(r/(σ√2)), the CDF range of the truncated Gaussian
    float m_q;       ///< exp(−2k), the step of eval_filter_taps16's ratio
};
using Filter = std::variant<BoxFilter, TentFilter, GaussianFilter>;
inline Vec2f sample_filter(const Filter& f, Vec2f u) {
    return std::visit([&](const auto& x) { return x.sample(u); }, f);
}
/// The filter's 1D profile (all filters here are separable: f(x, y) = f(x)·f(y)).
inline float eval_filter(const Filter& f, float x) {
    return std::visit([&](const auto& k) { return k.eval(x); }, f);
}
/// The most taps a row of splat weights has: filters are limited to a 16-pixel radius
/// (registry.cpp), and a sample in pixel x reaches pixels x − 16 .. x + 16.
constexpr int kMaxFilterTaps = 2 * 16 + 1;
/// Sixteen rows of splat weights at once: w[i][r] = f(x0[r] + i) for i < n ≤ kMaxFilterTaps, r < 16
/// (the film evaluates the column and row weights of four pairs of samples in one call). The
/// Gaussian takes two exponentials per row instead of n: with k = 1/(2σ²), e(x + 1) = e(x)·exp(−(2x
/// + 1)k), that ratio shrinks by exp(−2k) a step, and the ratio leftwards is exp(−2k) over the one
/// rightwards; each row starts at its middle tap and walks outwards, so the rounding compounds over
/// at most m steps (within 1.5e-6 of the profile, relative, for σ ≤ 1.2; test_filter.cpp). The
/// exponentials are film.cpp's own (Cody–Waite reduction and a polynomial, IEEE-rounded operations
/// only) and the recurrence runs on the sixteen rows side by side, in blocks of one register's
/// width (3, 5 and 7 taps in fixed-size code, the same operations), compiled for the baseline (4
/// rows a block) and, on x86-64, for AVX2 (8) and AVX-512 (16) (FilterTapsVariant): every variant gives the same bits, so the weights are the same on every
/// machine and for every SIMD target of the path tracer. Each row's arithmetic depends only on its
/// own x0: a row's weights do not depend on the other rows of the call.
void eval_filter_taps16(const Filter& f, const float x0[16], int n, float (*w)[16]);
/// The instruction-set variants of eval_filter_taps16 (the same bits); the call above takes the
/// widest this CPU runs.
enum class FilterTapsVariant { Baseline, AVX2, AVX512 };
/// The variants this build and CPU run, narrowest first (Baseline always).
std::vector<FilterTapsVariant> filter_taps_variants();
/// eval_filter_taps16 with the given variant (one of filter_taps_variants(); tests compare them).
void eval_filter_taps16(const Filter& f, const float x0[16], int n, float (*w)[16], FilterTapsVariant variant);
/// w[i] = f(x0 + i) for i < n ≤ kMaxFilterTaps: one row of eval_filter_taps16, the same numbers.
inline void eval_filter_taps(const Filter& f, float x0, int n, float* w) {
    float x16[16], rows[kMaxFilterTaps][16];
    for (float& v : x16) v = x0;
    eval_filter_taps16(f, x16, n, rows);
    for (int i = 0; i < n; ++i) w[i] = rows[i][0];
}
inline float filter_radius(const Filter& f) {
    return std::visit([](const auto& k) { return k.radius_px(); }, f);
}
inline std::string to_string(const Filter& f) {
    return std::visit([](const auto& x) { return x.to_string(); }, f);
}
}  // namespace pellucid
