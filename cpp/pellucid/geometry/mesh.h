// Triangle meshes in world space, structure of arrays (positions, optional normals and uvs).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "pellucid/math/frame.h"
#include "pellucid/math/transform.h"
#include "pellucid/math/vec.h"

namespace pellucid {

/// What a hit on a flat-shaded triangle needs besides its position and uv, all constant over the
/// triangle: the unit geometric normal (on the side of the vertex normals, if any), dp/du and dp/dv,
/// and the shading frame.
struct FlatTriangle {
    Normal3f ng;
    Vec3f dpdu, dpdv;
    Frame shading;
};

struct TriangleMesh {
    std::vector<Point3f> positions;
    std::vector<Normal3f> normals;  ///< per vertex, optional (empty = flat shading)
    std::vector<Vec2f> uvs;         ///< per vertex, optional
    std::vector<uint32_t> indices;  ///< 3 per triangle
    /// Per-triangle constants of a flat-shaded mesh, filled by precompute_flat(): hits then read
    /// them instead of solving for dp/du and building a frame (72 bytes a triangle).
    std::vector<FlatTriangle> flat;

    size_t triangle_count() const { return indices.size() / 3; }
    float triangle_area(size_t tri) const;
    /// Apply a transform (normals with the inverse transpose).
    void transform(const Transform& t);
    /// Drop triangles of zero (or non-finite) area; returns how many were removed. `per_face`, if
    /// given and non-empty, holds one value per triangle and is compacted alongside.
    size_t remove_degenerate(std::vector<uint32_t>* per_face = nullptr);
    /// Turn the surface inside out (Mitsuba's `flip_normals`): reverse every triangle's winding, so
    /// the geometric normal flips, and negate the vertex normals; uvs (hence dp/du, dp/dv) stay.
    void flip_normals();
    /// Throws pellucid::Error (prefixed by `where`) for out-of-range indices, bad sizes or NaNs.
    void validate(const std::string& where) const;
    /// Fill `flat` if the mesh is flat-shaded: no vertex normals, or the three vertex normals of
    /// every triangle equal (rectangles, cubes, faceted OBJ/PLY files); else leave it empty. Call
    /// after the last change to the positions, normals, uvs or winding.
    void precompute_flat();
    /// Triangle `tri`'s unit geometric normal, dp/du and dp/dv (pbrt-v4 §6.5.3); the shading frame
    /// is set from the geometric normal only (flat shading, vertex normals ignored).
    FlatTriangle flat_triangle(size_t tri) const;
    /// Angle-weighted vertex normals (Thürmer & Wüthrich 1998), as Mitsuba 3 computes them.
    void compute_smooth_normals();

    static TriangleMesh rectangle();  ///< [-1,1]² in the z = 0 plane, normal +z (Mitsuba's)
    /// [-1,1]³, outward normals, flat faces, each face's uv over [0,1]² laid out as Mitsuba 3's cube.
    static TriangleMesh cube();
};
}  // namespace pellucid
