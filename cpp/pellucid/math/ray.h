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
