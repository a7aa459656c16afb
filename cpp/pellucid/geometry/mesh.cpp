// Triangle mesh utilities and built-in shapes.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/geometry/mesh.h"

#include <cmath>

#include "pellucid/util/error.h"

namespace pellucid {

float TriangleMesh::triangle_area(size_t tri) const {
    const Point3f& a = positions[indices[3 * tri]];
    const Point3f& b = positions[indices[3 * tri + 1]];
    const Point3f& c = positions[indices[3 * tri + 2]];
    return 0.5f * length(cross(b - a, c - a));
}

void TriangleMesh::transform(const Transform& t) {
    for (auto& p : positions) p = t.point(p);
    for (auto& n : normals) n = normalize(t.normal(n));
    if (t.swaps_handedness())  // keep the winding consistent with the transformed normals
        for (size_t i = 0; i + 2 < indices.size(); i += 3) std::swap(indices[i + 1], indices[i + 2]);
}

size_t TriangleMesh::remove_degenerate() {
    std::vector<uint32_t> kept;
    kept.reserve(indices.size());
    size_t removed = 0;
    for (size_t t = 0; t < triangle_count(); ++t) {
        float a = triangle_area(t);
        if (a > 0.f && std::isfinite(a))
            kept.insert(kept.end(), indices.begin() + 3 * t, indices.begin() + 3 * t + 3);
        else
            ++removed;
    }
    indices.swap(kept);
    return removed;
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
    for (size_t i = 0; i < normals.size(); ++i)
        if (!is_finite(normals[i]) || length2(normals[i]) == 0.f)
            throw Error(where + "normals: normal " + std::to_string(i) + " is zero or not finite");
}

void TriangleMesh::compute_smooth_normals() {
    normals.assign(positions.size(), Normal3f(0.f));
    for (size_t t = 0; t < triangle_count(); ++t) {
        uint32_t i0 = indices[3 * t], i1 = indices[3 * t + 1], i2 = indices[3 * t + 2];
        Vec3f n = cross(positions[i1] - positions[i0], positions[i2] - positions[i0]);  // |n| = 2·area
        normals[i0] += n;
        normals[i1] += n;
        normals[i2] += n;
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
    TriangleMesh m;
    // Six faces, four vertices each, so that every face has its own flat normal and uvs.
    const Vec3f axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int a = 0; a < 3; ++a)
        for (int s = -1; s <= 1; s += 2) {
            Vec3f n = axes[a] * float(s);
            Vec3f u = axes[(a + 1) % 3], v = axes[(a + 2) % 3];
            if (s < 0) std::swap(u, v);  // keep (u, v, n) right-handed so triangles face outward
            uint32_t base = uint32_t(m.positions.size());
            const float c[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
            for (auto& k : c) {
                m.positions.push_back(n + u * k[0] + v * k[1]);
                m.normals.push_back(n);
                m.uvs.push_back(Vec2f(0.5f * (k[0] + 1), 0.5f * (k[1] + 1)));
            }
            m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base + 2, base + 3, base});
        }
    return m;
}
}  // namespace pellucid
