// Pinhole perspective camera.
// SPDX-License-Identifier: Apache-2.0
//
// | parameter | type      | default | meaning                                                        |
// |-----------|-----------|---------|----------------------------------------------------------------|
// | fov       | float     | 45      | field of view in degrees, along fov_axis                       |
// | fov_axis  | string    | "x"     | x, y, smaller or larger (as Mitsuba 3)                         |
// | to_world  | transform | identity| camera-to-world; the camera looks down +z with +y up (look_at) |
// JSON: {"type": "perspective", "fov": 40, "to_world": [{"look_at": {"origin": [0,0,4],
//        "target": [0,0,0], "up": [0,1,0]}}]}
#pragma once
#include <string>

#include "pellucid/math/lane_types.h"
#include "pellucid/math/ray.h"
#include "pellucid/math/transform.h"

namespace pellucid {

class PerspectiveCamera {
public:
    PerspectiveCamera() = default;
    /// fov_x_deg is the horizontal field of view after resolving fov_axis.
    PerspectiveCamera(const Transform& to_world, float fov_x_deg, int width, int height);

    /// Ray through film position (x, y) in pixels, (0, 0) = top-left corner of the image.
    Ray generate_ray(float x, float y) const { return Ray{m_origin, direction<float>(x, y), kInfinity}; }
    /// The unit direction of generate_ray(x, y), over a lane type F (math/lane_types.h): the path
    /// kernel starts a packet's camera rays at once.
    template <class F>
    V3<F> direction(const F& x, const F& y) const {
        const F cx = F(m_tan_x) * (F(1.f) - F(2.f) * x * F(m_inv_w)), cy = F(m_tan_y) * (F(1.f) - F(2.f) * y * F(m_inv_h));
        // to_world · (cx, cy, 1, 0), summed as GLM's mat4 · vec4 sums: (m₀x + m₁y) + (m₂z + m₃w).
        const Mat4f& m = m_to_world.matrix();
        auto row = [&](int r) {
            return (F(m[0][r]) * cx + F(m[1][r]) * cy) + (F(m[2][r]) * F(1.f) + F(m[3][r]) * F(0.f));
        };
        return normalize(V3<F>(row(0), row(1), row(2)));
    }
    /// The same ray with its differentials toward the neighbouring pixels (x+1, y) and (x, y+1).
    RayDifferential generate_ray_differential(float x, float y) const {
        RayDifferential r(generate_ray(x, y));
        r.has_differentials = true;
        r.rx_o = r.ry_o = m_origin;
        r.rx_d = normalize(m_to_world.vector(Vec3f(m_tan_x * (1.f - 2.f * (x + 1.f) * m_inv_w),
                                                   m_tan_y * (1.f - 2.f * y * m_inv_h), 1.f)));
        r.ry_d = normalize(m_to_world.vector(Vec3f(m_tan_x * (1.f - 2.f * x * m_inv_w),
                                                   m_tan_y * (1.f - 2.f * (y + 1.f) * m_inv_h), 1.f)));
        return r;
    }
    /// Approximate footprint of one pixel at a point seen along an arbitrary path (after a diffuse
    /// or glossy bounce, where ray differentials are not tracked): the footprint the camera would
    /// have there if it looked at p directly — the angle of one pixel at the image centre, at p's
    /// distance from the camera, projected onto the tangent plane of normal n (the idea of pbrt-v4's
    /// Approximate_dp_dxy). Stretching at grazing angles is capped at 64 pixel widths.
    void approximate_dp_dxy(const Point3f& p, const Normal3f& n, Vec3f* dpdx, Vec3f* dpdy) const;
    std::string to_string() const;
    /// The camera's position, and the angle one pixel spans at the image centre (radians).
    Point3f origin() const { return m_origin; }
    float pixel_angle() const { return 2.f * m_tan_x * m_inv_w; }

private:
    Transform m_to_world;
    Point3f m_origin{0.f};
    float m_tan_x = 1.f, m_tan_y = 1.f, m_inv_w = 1.f, m_inv_h = 1.f, m_fov_x = 45.f;
};
}  // namespace pellucid
