// Warps from the unit square to common domains, each with its density. All pdfs are with respect to
// the natural measure of the target domain (solid angle for directions, area for disks/triangles).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <algorithm>
#include <cmath>

#include "pellucid/math/constants.h"
#include "pellucid/math/lane_types.h"
#include "pellucid/math/vec.h"

namespace pellucid {
namespace detail {
/// sin and cos of |x| ≤ π/4 by their Taylor series to x⁹ and x¹⁰: the truncation error is below
/// (π/4)¹¹/11! ≈ 2e-9, under float rounding, with no range reduction and no libm call.
template <class F>
inline void sincos_quarter_pi(const F& x, F* s, F* c) {
    const F x2 = x * x;
    *s = x * (F(1.f) + x2 * (F(-1.f / 6.f) + x2 * (F(1.f / 120.f) + x2 * (F(-1.f / 5040.f) + x2 * F(1.f / 362880.f)))));
    *c = F(1.f) + x2 * (F(-0.5f) + x2 * (F(1.f / 24.f) + x2 * (F(-1.f / 720.f) + x2 * (F(1.f / 40320.f) - x2 * F(1.f / 3628800.f)))));
}
/// cos and sin of φ = 2π u for u ∈ [0, 1), without libm: φ's octant k = ⌊8u⌋ is chosen per lane,
/// and within it sincos_quarter_pi gives the angle to the nearer axis (f = 8u − k: fπ/4 past an
/// even octant's axis, (1 − f)π/4 before an odd one's), rotated by the quadrant ⌊k/2⌋.
template <class F>
inline void sincos_two_pi(const F& u, F* c_out, F* s_out) {
    using I = IntT<F>;
    const F t = F(8.f) * u;
    const F k = lane::floor(t);
    const F f = t - k;
    const I ki = lane::as_int(k + F(8388608.f)) - lane::as_int(F(8388608.f));  // k as an integer, k < 2²³
    const auto odd = lane::float_mask((ki & I(1)) != I(0));
    F s, c;
    sincos_quarter_pi<F>(lane::select(odd, F(1.f) - f, f) * F(kPiOver4), &s, &c);
    const F cp = lane::select(odd, s, c), sp = lane::select(odd, c, s);  // cos, sin of φ within its quadrant
    const I q = (ki >> 1) & I(3);
    const auto q1 = lane::float_mask(q == I(1)), q2 = lane::float_mask(q == I(2)), q3 = lane::float_mask(q == I(3));
    *c_out = lane::select(q1, lane::neg(sp), lane::select(q2, lane::neg(cp), lane::select(q3, sp, cp)));
    *s_out = lane::select(q1, cp, lane::select(q2, lane::neg(sp), lane::select(q3, lane::neg(cp), sp)));
}
}  // namespace detail

// The warps on every path vertex are templates over the lane type F (math/lane_types.h), called
// as name<F>(u); the float overloads below keep the scalar spelling.

/// Shirley & Chiu 1997 concentric map from the square to the unit disk. Its angle is θ' = π/4 · b/a
/// in the wedges where |a| > |b|, and π/2 − θ' (with a and b swapped) in the others, so sin and cos
/// are needed on [−π/4, π/4] only; the wedge is chosen per lane, without a branch.
template <class F>
inline V2<F> square_to_uniform_disk_concentric(const V2<F>& u) {
    const F a = F(2.f) * u.x - F(1.f), b = F(2.f) * u.y - F(1.f);
    const auto wide = lane::abs(a) > lane::abs(b);
    const F major = lane::select(wide, a, b), minor = lane::select(wide, b, a);
    const auto zero = major == F(0.f);  // then a = b = 0: the centre
    const F ang = lane::select(zero, F(0.f), F(kPiOver4) * (minor / lane::select(zero, F(1.f), major)));
    F s, c;
    detail::sincos_quarter_pi<F>(ang, &s, &c);  // cos(π/2 − θ') = sin θ'
    return V2<F>{major * lane::select(wide, c, s), major * lane::select(wide, s, c)};
}
inline Vec2f square_to_uniform_disk_concentric(Vec2f u) { return square_to_uniform_disk_concentric<float>(u); }
inline float square_to_uniform_disk_concentric_pdf(Vec2f p) { return (p.x * p.x + p.y * p.y <= 1.f) ? kInvPi : 0.f; }

/// Cosine-weighted hemisphere about +z (Malley's method); pdf = cos θ / π.
template <class F>
inline V3<F> square_to_cosine_hemisphere(const V2<F>& u) {
    const V2<F> d = square_to_uniform_disk_concentric<F>(u);
    return V3<F>(d.x, d.y, lane::sqrt(lane::max(F(0.f), F(1.f) - d.x * d.x - d.y * d.y)));
}
inline Vec3f square_to_cosine_hemisphere(Vec2f u) { return square_to_cosine_hemisphere<float>(u); }
template <class F>
inline F square_to_cosine_hemisphere_pdf(const V3<F>& w) {
    return lane::select(w.z > F(0.f), w.z * F(kInvPi), F(0.f));
}
inline float square_to_cosine_hemisphere_pdf(const Vec3f& w) { return square_to_cosine_hemisphere_pdf<float>(w); }

Vec3f square_to_uniform_hemisphere(Vec2f u);
float square_to_uniform_hemisphere_pdf(const Vec3f& w);

Vec3f square_to_uniform_sphere(Vec2f u);
float square_to_uniform_sphere_pdf(const Vec3f& w);
/// Uniform over the unit sphere, over a lane type F (pdf 1/4π): z = 1 − 2u.x and φ = 2π u.y, its
/// sine and cosine from detail::sincos_two_pi, so every lane type gives the same bits (the float
/// function above calls libm and may differ in the last bits).
template <class F>
inline V3<F> square_to_uniform_sphere_lanes(const V2<F>& u) {
    const F z = F(1.f) - F(2.f) * u.x;
    const F r = lane::sqrt(lane::max(F(0.f), F(1.f) - z * z));
    F c, s;
    detail::sincos_two_pi<F>(u.y, &c, &s);
    return V3<F>(r * c, r * s, z);
}

/// Uniform over the spherical cap {w : w.z ≥ cos_theta_max}.
Vec3f square_to_uniform_cone(Vec2f u, float cos_theta_max);
float square_to_uniform_cone_pdf(const Vec3f& w, float cos_theta_max);

/// Uniform barycentrics (b0, b1) over a triangle (Heitz 2019, "A Low-Distortion Map Between
/// Triangle and Square"); the area pdf is 1/area of the triangle.
template <class F>
inline V2<F> square_to_uniform_triangle(const V2<F>& u) {
    const auto lower = u.x < u.y;
    const F h = lane::select(lower, u.x, u.y) * F(0.5f);
    return V2<F>{lane::select(lower, h, u.x - h), lane::select(lower, u.y - h, h)};
}
inline Vec2f square_to_uniform_triangle(Vec2f u) { return square_to_uniform_triangle<float>(u); }

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
