// Pinhole perspective camera.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/camera/perspective.h"

#include <cmath>

#include "pellucid/math/constants.h"

namespace pellucid {

PerspectiveCamera::PerspectiveCamera(const Transform& to_world, float fov_x_deg, int width, int height)
    : m_to_world(to_world), m_fov_x(fov_x_deg) {
    m_origin = to_world.point(Point3f(0.f));
    m_tan_x = std::tan(radians(fov_x_deg) * 0.5f);
    m_tan_y = m_tan_x * float(height) / float(width);
    m_inv_w = 1.f / float(width);
    m_inv_h = 1.f / float(height);
}

void PerspectiveCamera::approximate_dp_dxy(const Point3f& p, const Normal3f& n, Vec3f* dpdx, Vec3f* dpdy) const {
    *dpdx = *dpdy = Vec3f(0.f);
    Vec3f to_p = p - m_origin;
    float dist = length(to_p);
    if (!(dist > 0.f)) return;
    Vec3f w = to_p / dist;
    // Camera x and y axes, made orthogonal to the viewing direction w.
    Vec3f cx = m_to_world.vector(Vec3f(1, 0, 0)), cy = m_to_world.vector(Vec3f(0, 1, 0));
    cx = normalize(cx - w * dot(w, cx));
    cy = cross(w, cx);
    if (dot(cy, m_to_world.vector(Vec3f(0, 1, 0))) < 0.f) cy = -cy;
    const float angle_x = 2.f * m_tan_x * m_inv_w, angle_y = 2.f * m_tan_y * m_inv_h;  // radians per pixel
    float cos_n = std::fabs(dot(n, w));
    float stretch = 1.f / std::max(cos_n, 1.f / 64.f);
    // A footprint of dist·angle perpendicular to w, moved along the tangent plane: project the
    // screen-parallel offset along w onto the plane (t = −n·v / n·w).
    auto onto_plane = [&](const Vec3f& v) {
        float nw = dot(n, w);
        Vec3f q = std::fabs(nw) > 1e-6f ? v - w * (dot(n, v) / nw) : v;
        float l = length(q), cap = length(v) * stretch;
        return l > cap && l > 0.f ? q * (cap / l) : q;
    };
    *dpdx = onto_plane(cx * (dist * angle_x));
    *dpdy = onto_plane(cy * (dist * angle_y));
}

std::string PerspectiveCamera::to_string() const {
    return "PerspectiveCamera[fov_x=" + std::to_string(m_fov_x) + ", origin=" + pellucid::to_string(m_origin) + "]";
}
}  // namespace pellucid
