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

std::string PerspectiveCamera::to_string() const {
    return "PerspectiveCamera[fov_x=" + std::to_string(m_fov_x) + ", origin=" + pellucid::to_string(m_origin) + "]";
}
}  // namespace pellucid
