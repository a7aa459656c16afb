// Spectrum: the RGB value type carried along paths (deliberately not glm::vec3, so that colours and
// geometry never mix by accident). A later switch to spectral rendering changes this one header.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <algorithm>
#include <cmath>
#include <string>

namespace pellucid {

class Spectrum {
public:
    float r = 0.f, g = 0.f, b = 0.f;

    constexpr Spectrum() = default;
    constexpr explicit Spectrum(float v) : r(v), g(v), b(v) {}
    constexpr Spectrum(float r_, float g_, float b_) : r(r_), g(g_), b(b_) {}

    constexpr float operator[](int i) const { return i == 0 ? r : (i == 1 ? g : b); }
    float& operator[](int i) { return i == 0 ? r : (i == 1 ? g : b); }

    constexpr Spectrum operator+(const Spectrum& o) const { return {r + o.r, g + o.g, b + o.b}; }
    constexpr Spectrum operator-(const Spectrum& o) const { return {r - o.r, g - o.g, b - o.b}; }
    constexpr Spectrum operator*(const Spectrum& o) const { return {r * o.r, g * o.g, b * o.b}; }
    constexpr Spectrum operator/(const Spectrum& o) const { return {r / o.r, g / o.g, b / o.b}; }
    constexpr Spectrum operator*(float s) const { return {r * s, g * s, b * s}; }
    constexpr Spectrum operator/(float s) const { return {r / s, g / s, b / s}; }
    constexpr Spectrum operator-() const { return {-r, -g, -b}; }
    Spectrum& operator+=(const Spectrum& o) { r += o.r; g += o.g; b += o.b; return *this; }
    Spectrum& operator*=(const Spectrum& o) { r *= o.r; g *= o.g; b *= o.b; return *this; }
    Spectrum& operator*=(float s) { r *= s; g *= s; b *= s; return *this; }
    Spectrum& operator/=(float s) { r /= s; g /= s; b /= s; return *this; }
    constexpr bool operator==(const Spectrum& o) const { return r == o.r && g == o.g && b == o.b; }
    constexpr bool operator!=(const Spectrum& o) const { return !(*this == o); }

    constexpr bool is_black() const { return r == 0.f && g == 0.f && b == 0.f; }
    constexpr float max_component() const { return std::max(r, std::max(g, b)); }
    constexpr float min_component() const { return std::min(r, std::min(g, b)); }
    constexpr float average() const { return (r + g + b) * (1.f / 3.f); }
    /// Rec. 709 / sRGB-primaries luminance.
    constexpr float luminance() const { return 0.2126f * r + 0.7152f * g + 0.0722f * b; }
    bool is_finite() const { return std::isfinite(r) && std::isfinite(g) && std::isfinite(b); }
    bool has_negative() const { return r < 0.f || g < 0.f || b < 0.f; }
    std::string to_string() const {
        return "[" + std::to_string(r) + ", " + std::to_string(g) + ", " + std::to_string(b) + "]";
    }
};
constexpr Spectrum operator*(float s, const Spectrum& c) { return c * s; }
inline Spectrum sqrt(const Spectrum& c) { return {std::sqrt(c.r), std::sqrt(c.g), std::sqrt(c.b)}; }
inline Spectrum exp(const Spectrum& c) { return {std::exp(c.r), std::exp(c.g), std::exp(c.b)}; }
inline Spectrum clamp_zero(const Spectrum& c) {
    return {std::max(0.f, c.r), std::max(0.f, c.g), std::max(0.f, c.b)};
}
}  // namespace pellucid
