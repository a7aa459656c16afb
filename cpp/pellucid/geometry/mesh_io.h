// Triangle mesh files: Wavefront OBJ (through tinyobjloader, used only in mesh_io.cpp) and PLY (our
// own strict reader). See docs/meshes.md.
//
// Memory: a loaded TriangleMesh holds 12 B per vertex position, 12 B per vertex normal (if any),
// 8 B per vertex uv (if any) and 12 B of indices per triangle. A closed mesh has about half as many
// vertices as triangles, so that is ~18 B/triangle (positions only) to ~28 B/triangle (normals
// and uvs), plus 4 B/triangle for ObjMesh::face_material. The loaders size the vectors exactly
// (MeshIO.LargeBinaryPly measures it on a 1M-triangle mesh).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "pellucid/geometry/mesh.h"

namespace pellucid {

struct MeshLoadOptions {
    /// Ignore the file's vertex normals (flat shading), Mitsuba's `face_normals`.
    bool face_normals = false;
    /// Compute angle-weighted vertex normals when the file has none (and face_normals is off).
    bool smooth_normals = false;
    /// v -> 1 - v on load (Mitsuba's OBJ `flip_tex_coords`).
    bool flip_tex_coords = false;
};

/// An OBJ mesh with its per-face material names (`usemtl`), for "per-face materials mapped by name".
struct ObjMesh {
    static constexpr uint32_t kNoMaterial = 0xffffffffu;  ///< faces before any `usemtl`
    TriangleMesh mesh;
    std::vector<std::string> material_names;  ///< distinct `usemtl` names in order of appearance
    std::vector<uint32_t> face_material;      ///< per triangle: index into material_names or kNoMaterial;
                                              ///< empty when the file has no `usemtl`
};

/// Load a Wavefront OBJ: polygons are fan-triangulated, negative (relative) indices are resolved,
/// vertices are shared where position/uv/normal indices all agree. Throws pellucid::Error naming
/// the file (and the face) for a missing file, bad or out-of-range indices.
ObjMesh load_obj(const std::string& path, const MeshLoadOptions& options = {});

/// Load a PLY file (ascii, binary_little_endian or binary_big_endian): vertex x, y, z (+ optional
/// nx, ny, nz and u, v / s, t / texture_u, texture_v / texture_s, texture_t); faces as a
/// `vertex_indices` (or `vertex_index`) list, polygons fan-triangulated. Other elements and
/// properties are skipped. Throws pellucid::Error naming the file and the line or element for
/// bad headers, unsupported types, truncated data and out-of-range indices.
TriangleMesh load_ply(const std::string& path, const MeshLoadOptions& options = {});

/// By extension (.obj / .ply, case-insensitive); OBJ material names are dropped.
TriangleMesh load_mesh(const std::string& path, const MeshLoadOptions& options = {});

/// Bytes held by the mesh vectors (capacity, not size).
size_t mesh_memory_bytes(const TriangleMesh& mesh);
}  // namespace pellucid
