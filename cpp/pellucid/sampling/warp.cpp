// Square-to-domain warps.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/sampling/warp.h"

#include <algorithm>
#include <cmath>

#include "pellucid/math/constants.h"

namespace pellucid {

Vec3f square_to_uniform_hemisphere(Vec2f u) {
    float z = u.x;
    float r = safe_sqrt(1.f - z * z);
    float phi = 2.f * kPi * u.y;
    return Vec3f(r * std::cos(phi), r * std::sin(phi), z);
}
float square_to_uniform_hemisphere_pdf(const Vec3f& w) { return w.z >= 0.f ? kInv2Pi : 0.f; }

Vec3f square_to_uniform_sphere(Vec2f u) {
    float z = 1.f - 2.f * u.x;
    float r = safe_sqrt(1.f - z * z);
    float phi = 2.f * kPi * u.y;
    return Vec3f(r * std::cos(phi), r * std::sin(phi), z);
}
float square_to_uniform_sphere_pdf(const Vec3f&) { return kInv4Pi; }

Vec3f square_to_uniform_cone(Vec2f u, float cos_theta_max) {
    float cos_t = (1.f - u.x) + u.x * cos_theta_max;
    float sin_t = safe_sqrt(1.f - cos_t * cos_t);
    float phi = 2.f * kPi * u.y;
    return Vec3f(sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t);
}
float square_to_uniform_cone_pdf(const Vec3f& w, float cos_theta_max) {
    return w.z >= cos_theta_max ? 1.f / (2.f * kPi * (1.f - cos_theta_max)) : 0.f;
}

float sample_tent(float u, float r) {
    // Invert the CDF of each half of the tent.
    if (u < 0.5f) {
        float v = 2.f * u;
        return r * (std::sqrt(v) - 1.f);
    }
    float v = 2.f * u - 1.f;
    return r * (1.f - std::sqrt(1.f - v));
}
float tent_pdf(float x, float r) { return std::fabs(x) >= r ? 0.f : (r - std::fabs(x)) / (r * r); }

namespace {
// Inverse error function, Giles 2010, "Approximating the erfinv function" (single precision).
float erfinv(float x) {
    float w = -std::log(std::max(1e-30f, (1.f - x) * (1.f + x))), p;
    if (w < 5.f) {
        w -= 2.5f;
        p = 2.81022636e-08f;
        p = 3.43273939e-07f + p * w;
        p = -3.5233877e-06f + p * w;
        p = -4.39150654e-06f + p * w;
        p = 0.00021858087f + p * w;
        p = -0.00125372503f + p * w;
        p = -0.00417768164f + p * w;
        p = 0.246640727f + p * w;
        p = 1.50140941f + p * w;
    } else {
        w = std::sqrt(w) - 3.f;
        p = -0.000200214257f;
        p = 0.000100950558f + p * w;
        p = 0.00134934322f + p * w;
        p = -0.00367342844f + p * w;
        p = 0.00573950773f + p * w;
        p = -0.0076224613f + p * w;
        p = 0.00943887047f + p * w;
        p = 1.00167406f + p * w;
        p = 2.83297682f + p * w;
    }
    return p * x;
}
}  // namespace

float sample_truncated_gaussian(float u, float sigma, float radius) {
    return sample_truncated_gaussian(u, sigma, radius, std::erf(radius / (sigma * std::sqrt(2.f))));
}
float sample_truncated_gaussian(float u, float sigma, float radius, float e) {
    // Map u into the CDF range of [-radius, radius] and invert Φ(x) = (1 + erf(x/(σ√2)))/2.
    float v = clamp((2.f * u - 1.f) * e, -0.9999999f, 0.9999999f);
    return clamp(sigma * std::sqrt(2.f) * erfinv(v), -radius, radius);
}
float truncated_gaussian_pdf(float x, float sigma, float radius) {
    if (std::fabs(x) > radius) return 0.f;
    float e = std::erf(radius / (sigma * std::sqrt(2.f)));
    return std::exp(-x * x / (2.f * sigma * sigma)) / (sigma * std::sqrt(2.f * kPi) * e);
}
}  // namespace pellucid
