// Footprints at surface hits from ray differentials.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/geometry/interaction.h"

#include <cmath>

namespace pellucid {

bool SurfaceInteraction::differentials_from_ray(const RayDifferential& ray) {
    if (!ray.has_differentials) return false;
    // Plane through p with normal ng: the offset ray o + t·d meets it at t = (n·p − n·o)/(n·d).
    float d = dot(ng, p);
    float ddx = dot(ng, ray.rx_d), ddy = dot(ng, ray.ry_d);
    if (ddx == 0.f || ddy == 0.f) return false;
    float tx = (d - dot(ng, ray.rx_o)) / ddx, ty = (d - dot(ng, ray.ry_o)) / ddy;
    if (!std::isfinite(tx) || !std::isfinite(ty)) return false;
    dpdx = ray.rx_o + tx * ray.rx_d - p;
    dpdy = ray.ry_o + ty * ray.ry_d - p;
    uv_differentials_from_dp();
    return true;
}

void SurfaceInteraction::uv_differentials_from_dp() {
    // Least squares for [∂p/∂u ∂p/∂v]·(du, dv)ᵀ = dp: the 2×2 normal equations AᵀA x = Aᵀ dp.
    float a = dot(dpdu, dpdu), b = dot(dpdu, dpdv), c = dot(dpdv, dpdv);
    float det = a * c - b * b;
    auto solve = [&](const Vec3f& dp, float& du, float& dv) {
        float r0 = dot(dpdu, dp), r1 = dot(dpdv, dp);
        du = (c * r0 - b * r1) / det;
        dv = (a * r1 - b * r0) / det;
        // Clamp absurd values from near-singular parameterisations (a huge footprint would pick
        // the coarsest MIP level everywhere).
        if (!std::isfinite(du) || std::fabs(du) > 1e8f) du = 0.f;
        if (!std::isfinite(dv) || std::fabs(dv) > 1e8f) dv = 0.f;
    };
    if (!(std::fabs(det) > 1e-20f)) {
        dudx = dvdx = dudy = dvdy = 0.f;
        return;
    }
    solve(dpdx, dudx, dvdx);
    solve(dpdy, dudy, dvdy);
}
}  // namespace pellucid
