// GLM aliases and small vector helpers used everywhere.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <glm/glm.hpp>

#include <cmath>
#include <string>

namespace pellucid {
using Vec2f = glm::vec2;
using Vec3f = glm::vec3;
using Vec4f = glm::vec4;
using Vec2i = glm::ivec2;
using Vec3d = glm::dvec3;
using Point3f = glm::vec3;
using Normal3f = glm::vec3;
using Mat3f = glm::mat3;
using Mat4f = glm::mat4;

inline float dot(const Vec3f& a, const Vec3f& b) { return glm::dot(a, b); }
inline float absdot(const Vec3f& a, const Vec3f& b) { return std::fabs(glm::dot(a, b)); }
inline Vec3f cross(const Vec3f& a, const Vec3f& b) { return glm::cross(a, b); }
inline float length(const Vec3f& a) { return glm::length(a); }
inline float length2(const Vec3f& a) { return glm::dot(a, a); }
inline Vec3f normalize(const Vec3f& a) { return glm::normalize(a); }
/// |a| per component by clearing the sign bit (glm::abs compiles to a branch per component, which
/// hit records take with unpredictable signs).
inline Vec3f abs(const Vec3f& a) { return Vec3f(std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)); }
/// Flip v so that it lies in the same hemisphere as n.
inline Vec3f face_forward(const Vec3f& v, const Vec3f& n) { return dot(v, n) < 0.f ? -v : v; }
inline bool is_finite(const Vec3f& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
inline std::string to_string(const Vec3f& v) {
    return "[" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) + "]";
}
}  // namespace pellucid
