// Affine transforms.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/math/transform.h"

#include <cmath>
#include <sstream>

#include "pellucid/math/constants.h"

namespace pellucid {

Transform::Transform(const Mat4f& m) : m_m(m), m_inv(glm::inverse(m)) {}

Transform Transform::translate(const Vec3f& t) {
    Mat4f m(1.f), inv(1.f);
    m[3] = Vec4f(t, 1.f);
    inv[3] = Vec4f(-t, 1.f);
    return {m, inv};
}

Transform Transform::scale(const Vec3f& s) {
    Mat4f m(1.f), inv(1.f);
    for (int i = 0; i < 3; ++i) {
        m[i][i] = s[i];
        inv[i][i] = 1.f / s[i];
    }
    return {m, inv};
}

Transform Transform::rotate(const Vec3f& axis, float angle_deg) {
    // Rodrigues' rotation formula, in double so that 90° turns are exact to float precision.
    glm::dvec3 a = glm::normalize(glm::dvec3(axis));
    double th = double(angle_deg) * 3.14159265358979323846 / 180.0;
    double c = std::cos(th), s = std::sin(th), C = 1.0 - c;
    glm::dmat3 r;
    r[0] = {a.x * a.x * C + c, a.y * a.x * C + a.z * s, a.z * a.x * C - a.y * s};
    r[1] = {a.x * a.y * C - a.z * s, a.y * a.y * C + c, a.z * a.y * C + a.x * s};
    r[2] = {a.x * a.z * C + a.y * s, a.y * a.z * C - a.x * s, a.z * a.z * C + c};
    Mat4f m{Mat3f(r)}, inv{Mat3f(glm::transpose(r))};
    return {m, inv};
}

Transform Transform::look_at(const Vec3f& origin, const Vec3f& target, const Vec3f& up) {
    Vec3f dir = normalize(target - origin);
    Vec3f left = normalize(cross(normalize(up), dir));
    Vec3f new_up = cross(dir, left);
    Mat4f m(1.f);
    m[0] = Vec4f(left, 0.f);
    m[1] = Vec4f(new_up, 0.f);
    m[2] = Vec4f(dir, 0.f);
    m[3] = Vec4f(origin, 1.f);
    return Transform(m);
}

float Transform::similarity_scale(std::string* why, float rel_tol) const {
    const Mat3f m(m_m);
    const float len[3] = {length(m[0]), length(m[1]), length(m[2])};
    auto fail = [&](const std::string& msg) {
        if (why) *why = msg;
        return 0.f;
    };
    auto scales = [&] {
        return "scales " + std::to_string(len[0]) + ", " + std::to_string(len[1]) + ", " + std::to_string(len[2]);
    };
    if (!(len[0] > 0.f && len[1] > 0.f && len[2] > 0.f) || !std::isfinite(len[0] + len[1] + len[2]))
        return fail("it is degenerate (" + scales() + ")");
    for (int k = 1; k < 3; ++k)
        if (std::fabs(len[k] - len[0]) > rel_tol * len[0])
            return fail("it does not scale uniformly (" + scales() + ")");
    static const char* const kAxis[3] = {"x", "y", "z"};
    for (int a = 0; a < 3; ++a)
        for (int b = a + 1; b < 3; ++b) {
            const float c = dot(m[a], m[b]) / (len[a] * len[b]);  // cosine of the angle between the mapped axes
            if (std::fabs(c) > rel_tol)
                return fail(std::string("it shears: the images of the ") + kAxis[a] + " and " + kAxis[b] +
                            " axes are not perpendicular (cosine " + std::to_string(c) + ")");
        }
    return len[0];
}

std::string Transform::to_string() const {
    std::ostringstream os;
    os << "[";
    for (int r = 0; r < 4; ++r) {
        os << (r ? ", [" : "[");
        for (int c = 0; c < 4; ++c) os << (c ? ", " : "") << m_m[c][r];
        os << "]";
    }
    os << "]";
    return os.str();
}
}  // namespace pellucid
