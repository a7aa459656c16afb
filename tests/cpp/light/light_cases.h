// Shared fixtures for the light tests: test lights, a small asymmetric environment map, and the
// geometric queries the tests use to evaluate pdf_li independently of the light's own sampling.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cmath>
#include <optional>
#include <utility>
#include <vector>

#include "pellucid/geometry/mesh.h"
#include "pellucid/image/image.h"
#include "pellucid/light/light.h"
#include "pellucid/math/transform.h"

namespace pellucid::test {

/// An 8×5 map with a bright spot, a ramp, distinct channels and two black columns (so some cells
/// have zero density), asymmetric under every flip of u or v.
inline Image asymmetric_envmap_image(int w = 8, int h = 5) {
    Image img(w, h, 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float* p = img.pixel(x, y);
            bool black = x == w - 2 || x == w - 1;
            float base = black ? 0.f : 0.2f + 0.15f * float(x) + 0.4f * float(y);
            float spot = (x == 2 && y == 1) ? 12.f : 0.f;
            p[0] = base + spot;
            p[1] = black ? 0.f : 0.5f * base + 0.3f * spot;
            p[2] = black ? 0.f : 1.f + 0.1f * float(y * y);
        }
    return img;
}

/// Linear part of a rotation about a tilted axis (non-trivial to_world for the tests).
inline Mat3f test_rotation() { return Mat3f(Transform::rotate(Vec3f(0.3f, 1.f, -0.4f), 37.f).matrix()); }

/// Triangles (three corners each) of a planar emitter in the plane y = 2: a quad split in two and a
/// smaller, separate triangle, so area sampling must pick triangles by area.
inline std::vector<Point3f> planar_light_triangles() {
    return {{-1, 2, -0.5f}, {1, 2, -0.5f}, {1, 2, 0.5f},  //
            {-1, 2, -0.5f}, {1, 2, 0.5f},  {-1, 2, 0.5f}, //
            {1.5f, 2, 0},   {2.5f, 2, 0},  {1.5f, 2, 1.2f}};
}
inline TriangleMesh mesh_of(const std::vector<Point3f>& tris) {
    TriangleMesh m;
    for (size_t i = 0; i < tris.size(); ++i) {
        m.positions.push_back(tris[i]);
        m.indices.push_back(uint32_t(i));
    }
    return m;
}

/// Closest hit of the ray (o, d) with a triangle list (Möller–Trumbore in double): point and unit
/// geometric normal.
inline std::optional<std::pair<Point3f, Normal3f>> hit_triangles(const std::vector<Point3f>& tris,
                                                                  const Point3f& o, const Vec3f& d) {
    double best = 1e30;
    std::optional<std::pair<Point3f, Normal3f>> out;
    for (size_t t = 0; t + 2 < tris.size(); t += 3) {
        Vec3d a(tris[t]), b(tris[t + 1]), c(tris[t + 2]), od(o), dd(d);
        Vec3d e1 = b - a, e2 = c - a, pv = glm::cross(dd, e2);
        double det = glm::dot(e1, pv);
        if (std::fabs(det) < 1e-14) continue;
        Vec3d tv = od - a;
        double u = glm::dot(tv, pv) / det;
        if (u < 0 || u > 1) continue;
        Vec3d qv = glm::cross(tv, e1);
        double v = glm::dot(dd, qv) / det;
        if (v < 0 || u + v > 1) continue;
        double dist = glm::dot(e2, qv) / det;
        if (dist > 0 && dist < best) {
            best = dist;
            out = std::make_pair(Point3f(od + dist * dd), Normal3f(glm::normalize(glm::cross(e1, e2))));
        }
    }
    return out;
}

/// Nearest hit (t > 0) of the ray (o, d) with a sphere, in double.
inline std::optional<std::pair<Point3f, Normal3f>> hit_sphere(const Point3f& c, float r, const Point3f& o,
                                                               const Vec3f& d) {
    Vec3d oc = Vec3d(o) - Vec3d(c), dd(d);
    double b = glm::dot(oc, dd), q = glm::dot(oc, oc) - double(r) * r, disc = b * b - q;
    if (disc < 0) return std::nullopt;
    double s = std::sqrt(disc), t = -b - s;
    if (t <= 0) t = -b + s;
    if (t <= 0) return std::nullopt;
    Vec3d p = Vec3d(o) + t * dd;
    return std::make_pair(Point3f(p), Normal3f(glm::normalize(p - Vec3d(c))));
}
}  // namespace pellucid::test
