// Affine transforms with a cached inverse; points, vectors and normals transform differently.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <string>

#include "pellucid/math/vec.h"

namespace pellucid {

class Transform {
public:
    Transform() = default;
    explicit Transform(const Mat4f& m);
    Transform(const Mat4f& m, const Mat4f& inv) : m_m(m), m_inv(inv) {}

    static Transform translate(const Vec3f& t);
    static Transform scale(const Vec3f& s);
    /// Rotation by angle_deg degrees about axis (right-handed).
    static Transform rotate(const Vec3f& axis, float angle_deg);
    /// Camera-to-world transform: the camera looks down +z, y is up (Mitsuba's convention).
    static Transform look_at(const Vec3f& origin, const Vec3f& target, const Vec3f& up);

    Transform operator*(const Transform& o) const { return {m_m * o.m_m, o.m_inv * m_inv}; }
    Transform inverse() const { return {m_inv, m_m}; }
    const Mat4f& matrix() const { return m_m; }
    const Mat4f& inverse_matrix() const { return m_inv; }

    Vec3f point(const Vec3f& p) const { return Vec3f(m_m * Vec4f(p, 1.f)); }
    Vec3f vector(const Vec3f& v) const { return Vec3f(m_m * Vec4f(v, 0.f)); }
    /// Normals transform with the inverse transpose.
    Vec3f normal(const Vec3f& n) const { return Vec3f(glm::transpose(m_inv) * Vec4f(n, 0.f)); }
    /// True if the transform flips handedness (negative determinant of the linear part).
    bool swaps_handedness() const { return glm::determinant(Mat3f(m_m)) < 0.f; }
    /// If the linear part is a similarity, s·Q with Q orthogonal (a rotation, possibly with a
    /// mirror) and s > 0, return s; else return 0 and, if `why` is given, say what fails. All three
    /// column lengths must agree and all three pairs of columns be perpendicular, to `rel_tol`
    /// relative to the lengths.
    float similarity_scale(std::string* why = nullptr, float rel_tol = 1e-4f) const;
    std::string to_string() const;

private:
    Mat4f m_m{1.f}, m_inv{1.f};
};
}  // namespace pellucid
