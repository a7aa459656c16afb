// Rays, and spawning rays off surfaces without self-intersection.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include "pellucid/math/constants.h"
#include "pellucid/math/vec.h"

namespace pellucid {

struct Ray {
    Point3f o;
    Vec3f d;
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
}  // namespace pellucid
