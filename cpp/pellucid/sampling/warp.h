// Warps from the unit square to common domains, each with its density. All pdfs are with respect to
// the natural measure of the target domain (solid angle for directions, area for disks/triangles).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <algorithm>
#include <cmath>

#include "pellucid/math/constants.h"
#include "pellucid/math/vec.h"

namespace pellucid {
namespace detail {
/// sin and cos of |x| ≤ π/4 by their Taylor series to x⁹ and x¹⁰: the truncation error is below
/// (π/4)¹¹/11! ≈ 2e-9, under float rounding, with no range reduction and no libm call.
inline void sincos_quarter_pi(float x, float* s, float* c) {
    const float x2 = x * x;
    *s = x * (1.f + x2 * (-1.f / 6.f + x2 * (1.f / 120.f + x2 * (-1.f / 5040.f + x2 * (1.f / 362880.f)))));
    *c = 1.f + x2 * (-0.5f + x2 * (1.f / 24.f + x2 * (-1.f / 720.f + x2 * (1.f / 40320.f - x2 * (1.f / 3628800.f)))));
}
}  // namespace detail

/// Shirley & Chiu 1997 concentric map from the square to the unit disk. Its angle is θ' = π/4 · b/a
/// in the wedges where |a| > |b|, and π/2 − θ' (with a and b swapped) in the others, so sin and cos
/// are needed on [−π/4, π/4] only. Inline: it is on every diffuse bounce.
inline Vec2f square_to_uniform_disk_concentric(Vec2f u) {
    const float a = 2.f * u.x - 1.f, b = 2.f * u.y - 1.f;
    if (a == 0.f && b == 0.f) return Vec2f(0.f);
    float s, c;
    if (std::fabs(a) > std::fabs(b)) {
        detail::sincos_quarter_pi(kPiOver4 * (b / a), &s, &c);
        return Vec2f(a * c, a * s);
    }
    detail::sincos_quarter_pi(kPiOver4 * (a / b), &s, &c);  // cos(π/2 − θ') = sin θ'
    return Vec2f(b * s, b * c);
}
inline float square_to_uniform_disk_concentric_pdf(Vec2f p) { return (p.x * p.x + p.y * p.y <= 1.f) ? kInvPi : 0.f; }

/// Cosine-weighted hemisphere about +z (Malley's method); pdf = cos θ / π.
inline Vec3f square_to_cosine_hemisphere(Vec2f u) {
    const Vec2f d = square_to_uniform_disk_concentric(u);
    return Vec3f(d.x, d.y, std::sqrt(std::max(0.f, 1.f - d.x * d.x - d.y * d.y)));
}
inline float square_to_cosine_hemisphere_pdf(const Vec3f& w) { return w.z > 0.f ? w.z * kInvPi : 0.f; }

Vec3f square_to_uniform_hemisphere(Vec2f u);
float square_to_uniform_hemisphere_pdf(const Vec3f& w);

Vec3f square_to_uniform_sphere(Vec2f u);
float square_to_uniform_sphere_pdf(const Vec3f& w);

/// Uniform over the spherical cap {w : w.z ≥ cos_theta_max}.
Vec3f square_to_uniform_cone(Vec2f u, float cos_theta_max);
float square_to_uniform_cone_pdf(const Vec3f& w, float cos_theta_max);

/// Uniform barycentrics (b0, b1) over a triangle (Heitz 2019, "A Low-Distortion Map Between
/// Triangle and Square"); the area pdf is 1/area of the triangle.
inline Vec2f square_to_uniform_triangle(Vec2f u) {
    if (u.x < u.y) {
        const float b0 = u.x / 2.f;
        return Vec2f(b0, u.y - b0);
    }
    const float b1 = u.y / 2.f;
    return Vec2f(u.x - b1, b1);
}

/// Tent on [-r, r] (1D): pdf = (r - |x|)/r².
float sample_tent(float u, float r);
float tent_pdf(float x, float r);
/// Standard normal through the inverse CDF (Giles 2010 erfinv approximation), scaled by sigma and
/// truncated to [-radius, radius].
float sample_truncated_gaussian(float u, float sigma, float radius);
/// The same with erf(radius/(σ√2)) precomputed by the caller.
float sample_truncated_gaussian(float u, float sigma, float radius, float erf_radius);
float truncated_gaussian_pdf(float x, float sigma, float radius);
}  // namespace pellucid
