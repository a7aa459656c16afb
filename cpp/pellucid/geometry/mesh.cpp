// Triangle mesh utilities and built-in shapes.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/geometry/mesh.h"

#include "pellucid/geometry/hit_lanes.h"

#include <cmath>

#include "pellucid/util/error.h"
#include "pellucid/util/limits.h"

namespace pellucid {

float TriangleMesh::triangle_area(size_t tri) const {
    const Point3f& a = positions[indices[3 * tri]];
    const Point3f& b = positions[indices[3 * tri + 1]];
    const Point3f& c = positions[indices[3 * tri + 2]];
    return 0.5f * length(cross(b - a, c - a));
}

FlatTriangle TriangleMesh::flat_triangle(size_t tri) const {
    const uint32_t i0 = indices[3 * tri], i1 = indices[3 * tri + 1], i2 = indices[3 * tri + 2];
    // Without uvs the triangle's own (0,0), (1,0), (1,1) parameterise it.
    const TriangleTangentsT<float> t = triangle_tangents<float>(
        positions[i0], positions[i1], positions[i2], uvs.empty() ? Vec2f(0, 0) : uvs[i0],
        uvs.empty() ? Vec2f(1, 0) : uvs[i1], uvs.empty() ? Vec2f(1, 1) : uvs[i2]);
    FlatTriangle f;
    f.ng = t.ng;
    f.dpdu = t.dpdu;
    f.dpdv = t.dpdv;
    f.shading = Frame::from_xz(f.dpdu, f.ng);
    return f;
}

void TriangleMesh::precompute_flat() {
    flat.clear();
    const size_t n = triangle_count();
    for (size_t i = 0; i < n && !normals.empty(); ++i) {
        const Normal3f& n0 = normals[indices[3 * i]];
        if (!(n0 == normals[indices[3 * i + 1]] && n0 == normals[indices[3 * i + 2]]) || !(length2(n0) > 0.f)) return;
    }
    flat.resize(n);
    for (size_t i = 0; i < n; ++i) {
        FlatTriangle f = flat_triangle(i);
        if (!normals.empty()) {
            // As a hit on a smooth triangle would compute them (Scene::intersect): the shading normal
            // is the (constant) vertex normal and the geometric normal turns to its side.
            const Normal3f ns = normalize(normals[indices[3 * i]]);
            if (dot(ns, f.ng) < 0.f) f.ng = -f.ng;
            f.shading = Frame::from_xz(f.dpdu, ns);
        }
        flat[i] = f;
    }
}

void TriangleMesh::transform(const Transform& t) {
    for (auto& p : positions) p = t.point(p);
    for (auto& n : normals) n = normalize(t.normal(n));
    if (t.swaps_handedness())  // keep the winding consistent with the transformed normals
        for (size_t i = 0; i + 2 < indices.size(); i += 3) std::swap(indices[i + 1], indices[i + 2]);
}

size_t TriangleMesh::remove_degenerate(std::vector<uint32_t>* per_face) {
    const bool compact_faces = per_face && !per_face->empty();
    PELLUCID_CHECK(!compact_faces || per_face->size() == triangle_count(), "one value per triangle");
    std::vector<uint32_t> kept;
    kept.reserve(indices.size());
    size_t removed = 0;
    for (size_t t = 0; t < triangle_count(); ++t) {
        float a = triangle_area(t);
        if (a > 0.f && std::isfinite(a)) {
            if (compact_faces) (*per_face)[kept.size() / 3] = (*per_face)[t];
            kept.insert(kept.end(), indices.begin() + 3 * t, indices.begin() + 3 * t + 3);
        } else {
            ++removed;
        }
    }
    indices.swap(kept);
    if (compact_faces) per_face->resize(triangle_count());
    return removed;
}

void TriangleMesh::flip_normals() {
    for (size_t i = 0; i + 2 < indices.size(); i += 3) std::swap(indices[i + 1], indices[i + 2]);
    for (auto& n : normals) n = -n;
}

void TriangleMesh::validate(const std::string& where) const {
    if (indices.size() % 3 != 0)
        throw Error(where + "indices: length " + std::to_string(indices.size()) + " is not a multiple of 3");
    for (size_t i = 0; i < indices.size(); ++i)
        if (indices[i] >= positions.size())
            throw Error(where + "indices[" + std::to_string(i) + "]: index " + std::to_string(indices[i]) +
                        " out of range (mesh has " + std::to_string(positions.size()) + " vertices)");
    if (!normals.empty() && normals.size() != positions.size())
        throw Error(where + "normals: " + std::to_string(normals.size()) + " normals for " +
                    std::to_string(positions.size()) + " vertices");
    if (!uvs.empty() && uvs.size() != positions.size())
        throw Error(where + "uvs: " + std::to_string(uvs.size()) + " uvs for " +
                    std::to_string(positions.size()) + " vertices");
    for (size_t i = 0; i < positions.size(); ++i)
        if (!is_finite(positions[i]))
            throw Error(where + "positions: vertex " + std::to_string(i) + " is not finite");
        else if (!within_coordinate_limit(positions[i].x, positions[i].y, positions[i].z))
            throw Error(where + "positions: vertex " + std::to_string(i) + " at " + point_text(positions[i].x, positions[i].y, positions[i].z) +
                        " (after to_world) is beyond the coordinate limit of 1e18 scene units");
    for (size_t i = 0; i < normals.size(); ++i)
        if (!is_finite(normals[i]) || length2(normals[i]) == 0.f)
            throw Error(where + "normals: normal " + std::to_string(i) + " is zero or not finite");
    for (size_t i = 0; i < uvs.size(); ++i)
        if (!std::isfinite(uvs[i].x) || !std::isfinite(uvs[i].y))
            throw Error(where + "uvs: uv " + std::to_string(i) + " (" + std::to_string(uvs[i].x) + ", " +
                        std::to_string(uvs[i].y) + ") is not finite");
}

void TriangleMesh::compute_smooth_normals() {
    // Angle-weighted face normals (Thürmer & Wüthrich 1998, "Computing Vertex Normals from Polygonal
    // Facets", JGT 3(1)): each face adds its unit normal times its interior angle at the vertex, so
    // the result does not depend on how a surface is split into triangles (area weights do), and it
    // is the rule Mitsuba 3 uses for meshes without normals.
    normals.assign(positions.size(), Normal3f(0.f));
    for (size_t t = 0; t < triangle_count(); ++t) {
        const uint32_t v[3] = {indices[3 * t], indices[3 * t + 1], indices[3 * t + 2]};
        Vec3f n = cross(positions[v[1]] - positions[v[0]], positions[v[2]] - positions[v[0]]);
        if (!(length2(n) > 0.f)) continue;
        n = normalize(n);
        for (int k = 0; k < 3; ++k) {
            Vec3f a = positions[v[(k + 1) % 3]] - positions[v[k]], b = positions[v[(k + 2) % 3]] - positions[v[k]];
            float la = length(a), lb = length(b);
            if (!(la > 0.f && lb > 0.f)) continue;
            // The angle between a and b, by atan2 (accurate for small and obtuse angles alike).
            float angle = std::atan2(length(cross(a, b)), dot(a, b));
            normals[v[k]] += angle * n;
        }
    }
    for (auto& n : normals) n = length2(n) > 0.f ? normalize(n) : Normal3f(0, 0, 1);
}

TriangleMesh TriangleMesh::rectangle() {
    TriangleMesh m;
    m.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    m.indices = {0, 1, 2, 2, 3, 0};
    return m;
}

TriangleMesh TriangleMesh::cube() {
    // Mitsuba 3's cube (src/shapes/cube.cpp) maps every face onto [0,1]² in its own orientation. We
    // describe it by the face normal n and the direction U in which u grows; v grows along
    // V = U × n (so (U, V) is a mirrored frame seen from outside, on every face), and uv = (0, 0)
    // sits at the corner n − U − V. tests/data/mitsuba/cube_uv.xml checks the layout against
    // Mitsuba with an asymmetric texture on all six faces.
    const Vec3f X(1, 0, 0), Y(0, 1, 0), Z(0, 0, 1);
    const Vec3f faces[6][2] = {{-Y, Z}, {Y, -X}, {X, Y}, {Z, Y}, {-X, Y}, {-Z, -Y}};  // (n, U)
    TriangleMesh m;
    for (const auto& f : faces) {
        const Vec3f n = f[0], U = f[1], V = cross(U, n);
        const Point3f o = n - U - V;
        const uint32_t base = uint32_t(m.positions.size());
        const float corners[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};  // (u, v)
        for (const auto& c : corners) {
            m.positions.push_back(o + 2.f * c[0] * U + 2.f * c[1] * V);
            m.normals.push_back(n);
            m.uvs.emplace_back(c[0], c[1]);
        }
        // U × V = −n, so the uv-counter-clockwise order faces inward: wind the other way.
        m.indices.insert(m.indices.end(), {base, base + 2, base + 1, base, base + 3, base + 2});
    }
    return m;
}
}  // namespace pellucid
