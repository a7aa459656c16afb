// Rays, and spawning rays off surfaces without self-intersection.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include "pellucid/math/constants.h"
#include "pellucid/math/lane_types.h"
#include "pellucid/math/vec.h"

namespace pellucid {

struct Ray {
    Point3f o{0.f};
    Vec3f d{0.f};
    float tmax = kInfinity;
};

/// A ray with the two neighbouring rays of the next pixel in x and in y (Igehy 1999, "Tracing Ray
/// Differentials"): they start at the camera and are carried through specular bounces only.
struct RayDifferential : Ray {
    bool has_differentials = false;
    Point3f rx_o{0.f}, ry_o{0.f};
    Vec3f rx_d{0.f}, ry_d{0.f};
    RayDifferential() = default;
    RayDifferential(const Ray& r) : Ray(r) {}  // NOLINT: a plain ray has no differentials
    /// Become the plain ray (o, d, tmax) in place. The differentials' fields keep stale values,
    /// which nothing reads without has_differentials. (Assigning a new RayDifferential builds all
    /// 80 bytes on the stack and copies them, a store-forwarding stall per 16 bytes.)
    [[gnu::always_inline]] void set(const Point3f& origin, const Vec3f& dir, float t_max) {
        o = origin;
        d = dir;
        tmax = t_max;
        has_differentials = false;
    }
};

/// Offset a surface point along its geometric normal n, far enough that a ray leaving in direction w
/// cannot re-hit the surface: the offset is the projection of the point's conservative error box
/// p_error onto n, rounded away from p (pbrt-v4 §6.8.6, "Robust Spawned Ray Origins").
inline Point3f offset_ray_origin(const Point3f& p, const Vec3f& p_error, const Normal3f& n,
                                 const Vec3f& w) {
    float d = dot(abs(n), p_error);
    Vec3f offset = d * n;
    if (dot(w, n) < 0.f) offset = -offset;
    Point3f po = p + offset;
    for (int i = 0; i < 3; ++i) {
        if (offset[i] > 0.f) po[i] = next_float_up(po[i]);
        else if (offset[i] < 0.f) po[i] = next_float_down(po[i]);
    }
    return po;
}

/// offset_ray_origin over a lane type F (simd/lane.h): p + offset, then one ulp further in the
/// offset's direction, as next_float_up / next_float_down do for finite values, by integer steps
/// on the bits.
template <class F>
inline F offset_coordinate(const F& p, const F& off) {
    using I = IntT<F>;
    const F po = p + off;
    const I b = lane::as_int(po);
    const auto zero = lane::int_mask(po == F(0.f));
    // Up: ±0 goes to the smallest positive number; positives gain an ulp, negatives lose one.
    const I up = lane::select(zero, I(0), b) + lane::select(lane::int_mask(po >= F(0.f)), I(1), I(-1));
    const I down = lane::select(zero, I(int32_t(0x80000000u)), b) + lane::select(lane::int_mask(po > F(0.f)), I(-1), I(1));
    return lane::as_float(lane::select(lane::int_mask(off > F(0.f)), up, lane::select(lane::int_mask(off < F(0.f)), down, b)));
}
template <class F>
inline V3<F> offset_ray_origin(const V3<F>& p, const V3<F>& p_error, const V3<F>& n, const V3<F>& w) {
    const F d = dot(abs(n), p_error);
    const F s = lane::select(dot(w, n) < F(0.f), lane::neg(d), d);
    return V3<F>(offset_coordinate<F>(p.x, s * n.x), offset_coordinate<F>(p.y, s * n.y), offset_coordinate<F>(p.z, s * n.z));
}
}  // namespace pellucid
