// SurfaceInteraction: everything shading needs to know about a ray–surface hit.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>

#include "pellucid/math/frame.h"
#include "pellucid/math/ray.h"

namespace pellucid {

struct SurfaceInteraction {
    Point3f p;             ///< hit position (world)
    Vec3f p_error{0.f};    ///< conservative absolute error bound of p, per axis
    Normal3f ng;           ///< geometric normal (unit; faces the side the primitive defines)
    Frame shading;         ///< shading frame, shading.n = shading normal (same side as ng)
    Vec2f uv{0.f};
    Vec3f dpdu{0.f}, dpdv{0.f};
    Vec3f dndu{0.f}, dndv{0.f};  ///< derivatives of the shading normal (0 for flat triangles)
    /// Footprint of one pixel at the hit (zero until compute_differentials): screen-space
    /// derivatives of the position and of uv.
    Vec3f dpdx{0.f}, dpdy{0.f};
    float dudx = 0.f, dvdx = 0.f, dudy = 0.f, dvdy = 0.f;
    Vec3f wo{0.f};         ///< direction back toward the ray origin (unit)
    float t = 0.f;
    uint32_t shape_id = 0, prim_id = 0, material_id = 0;
    int32_t light_id = -1; ///< area light bound to this shape, or -1

    /// Fill dpdx/dpdy from the ray's differentials, by intersecting the two offset rays with the
    /// tangent plane (Igehy 1999; pbrt-v3 §10.1.1), then du/dx … by least squares on
    /// dp/dx = ∂p/∂u·du/dx + ∂p/∂v·dv/dx. Returns false (nothing set) without differentials.
    bool differentials_from_ray(const RayDifferential& ray);
    /// du/dx … from dpdx/dpdy already set (normal equations of the 3×2 system).
    void uv_differentials_from_dp();

    /// A ray leaving the surface in direction d, offset so it cannot re-hit this surface.
    Ray spawn_ray(const Vec3f& d) const { return Ray{offset_ray_origin(p, p_error, ng, d), d, kInfinity}; }
    /// A shadow ray toward the surface point p2 (normal n2, error bound e2): both ends are offset
    /// off their surfaces by their error bounds, so neither end can hit its own surface
    /// (pbrt-v4 §6.8.6, SpawnRayTo between two interactions). tmax = 1 − ε spans the segment.
    Ray spawn_ray_to(const Point3f& p2, const Normal3f& n2, const Vec3f& e2) const {
        Point3f o = offset_ray_origin(p, p_error, ng, p2 - p);
        Point3f e = offset_ray_origin(p2, e2, n2, o - p2);
        return Ray{o, e - o, 1.f - 1e-4f};
    }
};
}  // namespace pellucid
