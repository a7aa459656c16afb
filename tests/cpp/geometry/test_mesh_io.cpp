// OBJ and PLY loading (geometry/mesh_io.h).
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <functional>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "pellucid/geometry/mesh_io.h"
#include "pellucid/util/error.h"
#include "support/temp_dir.h"

using namespace pellucid;
namespace fs = std::filesystem;

namespace {

fs::path write_text(const test::TempDir& tmp, const std::string& name, const std::string& text) {
    fs::path p = tmp.file(name);
    std::ofstream(p, std::ios::binary) << text;
    return p;
}

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

/// A small PLY writer for the round trips: float xyz (+ normals, uvs), uchar/int face lists.
struct PlyMesh {
    std::vector<Vec3f> p, n;
    std::vector<Vec2f> uv;
    std::vector<std::vector<uint32_t>> faces;
};

enum class Fmt { Ascii, LE, BE };

template <class T>
void put(std::string& out, T v, bool big_endian) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (big_endian) std::reverse(b, b + sizeof(T));
    out.append(b, sizeof(T));
}

std::string ply_text(const PlyMesh& m, Fmt fmt, const std::string& extra_vertex_prop = "") {
    std::string h = "ply\n";
    h += fmt == Fmt::Ascii ? "format ascii 1.0\n" : fmt == Fmt::LE ? "format binary_little_endian 1.0\n"
                                                                  : "format binary_big_endian 1.0\n";
    h += "comment written by test_mesh_io\n";
    h += "element vertex " + std::to_string(m.p.size()) + "\nproperty float x\nproperty float y\nproperty float z\n";
    if (!m.n.empty()) h += "property float nx\nproperty float ny\nproperty float nz\n";
    if (!m.uv.empty()) h += "property float u\nproperty float v\n";
    if (!extra_vertex_prop.empty()) h += "property uchar " + extra_vertex_prop + "\n";
    h += "element face " + std::to_string(m.faces.size()) + "\nproperty list uchar int vertex_indices\n";
    h += "element edge 1\nproperty int vertex1\nproperty int vertex2\n";  // skipped by the reader
    h += "end_header\n";
    std::string d;
    bool be = fmt == Fmt::BE;
    auto num = [&](float v) {
        if (fmt == Fmt::Ascii) d += std::to_string(v) + " ";
        else put(d, v, be);
    };
    for (size_t i = 0; i < m.p.size(); ++i) {
        for (int k = 0; k < 3; ++k) num(m.p[i][k]);
        if (!m.n.empty())
            for (int k = 0; k < 3; ++k) num(m.n[i][k]);
        if (!m.uv.empty())
            for (int k = 0; k < 2; ++k) num(m.uv[i][k]);
        if (!extra_vertex_prop.empty()) {
            if (fmt == Fmt::Ascii) d += "7";
            else d += char(7);
        }
        if (fmt == Fmt::Ascii) d += "\n";
    }
    for (const auto& f : m.faces) {
        if (fmt == Fmt::Ascii) {
            d += std::to_string(f.size());
            for (uint32_t i : f) d += " " + std::to_string(i);
            d += "\n";
        } else {
            put(d, uint8_t(f.size()), be);
            for (uint32_t i : f) put(d, int32_t(i), be);
        }
    }
    if (fmt == Fmt::Ascii) d += "0 1\n";
    else {
        put(d, int32_t(0), be);
        put(d, int32_t(1), be);
    }
    return h + d;
}

PlyMesh small_mesh() {
    PlyMesh m;
    m.p = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5f, 2, 0.25f}};
    m.n = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 1, 0}};
    m.uv = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.5f, 0.75f}};
    m.faces = {{0, 1, 2, 3}, {3, 2, 4}};  // a quad and a triangle
    return m;
}
}  // namespace

TEST(MeshIO, ObjQuadsMaterialsUvsNormals) {
    const test::TempDir tmp("pellucid_mesh_io_");
    fs::path p = write_text(tmp, "quads.obj", R"(# two materials, a quad, a triangle and a pentagon
mtllib missing.mtl
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0.5 2 0
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vn 0 0 2
o thing
f 1/1/1 2/2/1 3/3/1 4/4/1
usemtl red
f -2/3/1 -3/3/1 -1/4/1
usemtl blue
f 1/1/1 2/2/1 3/3/1 5/4/1 4/4/1
usemtl red
f 1/1/1 3/3/1 4/4/1
)");
    ObjMesh o = load_obj(p.string());
    const TriangleMesh& m = o.mesh;
    ASSERT_EQ(m.triangle_count(), 2u + 1u + 3u + 1u);
    EXPECT_EQ(o.material_names, (std::vector<std::string>{"red", "blue"}));
    const uint32_t N = ObjMesh::kNoMaterial;
    EXPECT_EQ(o.face_material, (std::vector<uint32_t>{N, N, 0, 1, 1, 1, 0}));
    // Corners shared where (v, vt, vn) agree: 4 from the quad, then only (4,3,1) and (5,4,1) are new.
    EXPECT_EQ(m.positions.size(), 6u);
    ASSERT_EQ(m.normals.size(), m.positions.size());
    ASSERT_EQ(m.uvs.size(), m.positions.size());
    EXPECT_EQ(m.normals[0], Vec3f(0, 0, 1));  // normalised
    // The quad is fanned (0,1,2), (0,2,3).
    EXPECT_EQ(std::vector<uint32_t>(m.indices.begin(), m.indices.begin() + 6),
              (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
    EXPECT_EQ(m.positions[m.indices[6]], Vec3f(0, 1, 0));  // -2 with 5 defined so far = v4
    EXPECT_EQ(m.uvs[m.indices[6]], Vec2f(1, 1));
    m.validate("quads.obj");

    // face_normals drops the file's normals; flip_tex_coords flips v.
    MeshLoadOptions opt;
    opt.face_normals = true;
    opt.flip_tex_coords = true;
    ObjMesh f = load_obj(p.string(), opt);
    EXPECT_TRUE(f.mesh.normals.empty());
    EXPECT_EQ(f.mesh.uvs[3], Vec2f(0, 0));
}

TEST(MeshIO, ObjWithoutAttributesAndSmoothNormals) {
    const test::TempDir tmp("pellucid_mesh_io_");
    fs::path p = write_text(tmp, "plain.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
    ObjMesh o = load_obj(p.string());
    EXPECT_EQ(o.mesh.triangle_count(), 4u);
    EXPECT_EQ(o.mesh.positions.size(), 4u);
    EXPECT_TRUE(o.mesh.normals.empty());
    EXPECT_TRUE(o.mesh.uvs.empty());
    EXPECT_TRUE(o.face_material.empty());
    MeshLoadOptions opt;
    opt.smooth_normals = true;
    TriangleMesh s = load_mesh(p.string(), opt);
    ASSERT_EQ(s.normals.size(), 4u);
    EXPECT_NEAR(length(s.normals[0]), 1.f, 1e-6f);
}

TEST(MeshIO, ObjErrorsNameTheFile) {
    const test::TempDir tmp("pellucid_mesh_io_");
    fs::path p = write_text(tmp, "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n");
    EXPECT_EQ(error_of([&] { load_obj(p.string()); }),
              p.string() + ": face 2: vertex index 9 is out of range (3 defined so far)");
    p = write_text(tmp, "bad2.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n");
    EXPECT_EQ(error_of([&] { load_obj(p.string()); }), p.string() + ": face 1 has 2 vertices (need >= 3)");
    p = write_text(tmp, "bad3.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n");
    EXPECT_EQ(error_of([&] { load_obj(p.string()); }),
              p.string() + ": face 1: texture coordinate index 2 is out of range (1 defined so far)");
    p = write_text(tmp, "empty.obj", "v 0 0 0\n");
    EXPECT_EQ(error_of([&] { load_obj(p.string()); }), p.string() + ": OBJ file has no faces");
    EXPECT_EQ(error_of([] { load_obj("/nonexistent/x.obj"); }),
              "/nonexistent/x.obj: cannot open OBJ file (does it exist?)");
}

TEST(MeshIO, PlyRoundTripsAsciiAndBinary) {
    const test::TempDir tmp("pellucid_mesh_io_");
    PlyMesh src = small_mesh();
    for (Fmt fmt : {Fmt::Ascii, Fmt::LE, Fmt::BE}) {
        SCOPED_TRACE(int(fmt));
        fs::path p = tmp.file("round" + std::to_string(int(fmt)) + ".ply");
        std::ofstream(p, std::ios::binary) << ply_text(src, fmt, "red");
        TriangleMesh m = load_ply(p.string());
        ASSERT_EQ(m.positions.size(), 5u);
        ASSERT_EQ(m.triangle_count(), 3u);
        EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3, 3, 2, 4}));
        for (size_t i = 0; i < 5; ++i) {
            EXPECT_NEAR(length(m.positions[i] - src.p[i]), 0.f, 1e-6f);
            EXPECT_NEAR(length(m.normals[i] - src.n[i]), 0.f, 1e-6f);
            EXPECT_NEAR(length(m.uvs[i] - src.uv[i]), 0.f, 1e-6f);
        }
        m.validate(p.string());
        // A uv that is not finite is bad input, named by its file and index.
        TriangleMesh bad = m;
        bad.uvs[3].y = std::nanf("");
        try {
            bad.validate(p.string());
            ADD_FAILURE() << "a NaN uv was accepted";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(p.string()), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("uvs: uv 3"), std::string::npos) << e.what();
        }
    }
    // Positions only, smooth normals on request.
    PlyMesh bare = src;
    bare.n.clear();
    bare.uv.clear();
    fs::path p = tmp.file("bare.ply");
    std::ofstream(p, std::ios::binary) << ply_text(bare, Fmt::LE);
    TriangleMesh m = load_ply(p.string());
    EXPECT_TRUE(m.normals.empty());
    EXPECT_TRUE(m.uvs.empty());
    MeshLoadOptions opt;
    opt.smooth_normals = true;
    m = load_ply(p.string(), opt);
    ASSERT_EQ(m.normals.size(), 5u);
    EXPECT_NEAR(m.normals[0].z, 1.f, 1e-6f);
}

TEST(MeshIO, PlyCorruptFilesNameTheFile) {
    const test::TempDir tmp("pellucid_mesh_io_");
    PlyMesh src = small_mesh();
    std::string good = ply_text(src, Fmt::LE);
    auto load_text = [&tmp](const std::string& name, const std::string& text) {
        fs::path p = tmp.file(name);
        std::ofstream(p, std::ios::binary) << text;
        return std::make_pair(p.string(), error_of([&] { load_ply(p.string()); }));
    };
    auto [p1, e1] = load_text("trunc.ply", good.substr(0, good.size() - 20));
    EXPECT_EQ(e1, p1 + ": element 'face' 1: unexpected end of file (truncated)");
    auto [p2, e2] = load_text("magic.ply", "plx\n" + good.substr(4));
    EXPECT_EQ(e2, p2 + ":1: not a PLY file (the first line must be 'ply')");
    std::string bad_type = good;
    bad_type.replace(bad_type.find("property float y"), 16, "property half  y");
    auto [p3, e3] = load_text("type.ply", bad_type);
    EXPECT_EQ(e3, p3 + ":6: unsupported property type 'half'");
    auto [p4, e4] = load_text("noend.ply", "ply\nformat ascii 1.0\nelement vertex 3\n");
    EXPECT_EQ(e4, p4 + ":3: truncated header (no end_header)");
    PlyMesh oob = src;
    oob.faces[1][2] = 5;
    auto [p5, e5] = load_text("oob.ply", ply_text(oob, Fmt::BE));
    EXPECT_EQ(e5, p5 + ": element 'face' 1: vertex index 5 is out of range [0, 5)");
    std::string ascii = ply_text(src, Fmt::Ascii);
    ascii.replace(ascii.find("1.000000"), 8, "1.0x0000");
    auto [p6, e6] = load_text("token.ply", ascii);
    EXPECT_EQ(e6, p6 + ":19: element 'vertex' 0: expected a number, got '1.0x0000'");
    auto [p7, e7] = load_text("kw.ply", "ply\nformat ascii 1.0\nelemnt vertex 3\nend_header\n");
    EXPECT_EQ(e7, p7 + ":3: unknown header keyword 'elemnt'");
    auto [p8, e8] = load_text("noxyz.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                                           "element face 1\nproperty list uchar int vertex_indices\nend_header\n");
    EXPECT_EQ(e8, p8 + ":3: element 'vertex' needs properties x, y, z");
    EXPECT_EQ(error_of([] { load_ply("/nonexistent/x.ply"); }),
              "/nonexistent/x.ply: cannot open PLY file (does it exist?)");
}

TEST(MeshIO, LargeBinaryPlyMemoryPerTriangle) {
    const test::TempDir tmp("pellucid_mesh_io_");
    // A 708x708-quad grid: 502,681 vertices, 1,002,528 triangles (~19 MB binary PLY).
    const uint32_t n = 708;
    fs::path p = tmp.file("large.ply");
    {
        std::string h = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string((n + 1) * (n + 1)) +
                        "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                        std::to_string(2 * n * n) + "\nproperty list uchar int vertex_indices\nend_header\n";
        std::string d;
        d.reserve(size_t(n + 1) * (n + 1) * 12 + size_t(2) * n * n * 13);
        for (uint32_t j = 0; j <= n; ++j)
            for (uint32_t i = 0; i <= n; ++i) {
                put(d, float(i) / n, false);
                put(d, float(j) / n, false);
                put(d, 0.f, false);
            }
        for (uint32_t j = 0; j < n; ++j)
            for (uint32_t i = 0; i < n; ++i) {
                int32_t a = int32_t(j * (n + 1) + i), b = a + 1, c = a + int32_t(n) + 2, e = a + int32_t(n) + 1;
                put(d, uint8_t(3), false), put(d, a, false), put(d, b, false), put(d, c, false);
                put(d, uint8_t(3), false), put(d, a, false), put(d, c, false), put(d, e, false);
            }
        std::ofstream(p, std::ios::binary) << h << d;
    }
    auto t0 = std::chrono::steady_clock::now();
    TriangleMesh m = load_ply(p.string());
    double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ASSERT_EQ(m.triangle_count(), size_t(2) * n * n);
    ASSERT_GE(m.triangle_count(), 1000000u);
    EXPECT_EQ(m.positions.size(), size_t(n + 1) * (n + 1));
    EXPECT_EQ(m.indices[3 * 1000001 + 1], m.indices[3 * 1000000 + 2]);  // (a,b,c) then (a,c,e)
    double per_tri = double(mesh_memory_bytes(m)) / double(m.triangle_count());
    std::cout << "[ MeshIO   ] " << m.triangle_count() << " triangles, " << m.positions.size()
              << " vertices: " << mesh_memory_bytes(m) << " bytes = " << per_tri
              << " bytes/triangle (positions + indices), loaded in " << secs << " s\n";
    RecordProperty("bytes_per_triangle", std::to_string(per_tri));
    // 12 B of indices + 12 B per vertex * (V/T ~ 0.5) = ~18 B; the vectors are sized exactly.
    EXPECT_LT(per_tri, 18.1);
    EXPECT_GT(per_tri, 17.9);
    // With smooth normals: + 12 B per vertex (~6 B per triangle).
    MeshLoadOptions opt;
    opt.smooth_normals = true;
    m = load_ply(p.string(), opt);
    per_tri = double(mesh_memory_bytes(m)) / double(m.triangle_count());
    std::cout << "[ MeshIO   ] with smooth normals: " << per_tri << " bytes/triangle\n";
    EXPECT_LT(per_tri, 24.1);
    fs::remove(p);
}

TEST(MeshNormals, ComputedNormalsAreAngleWeighted) {
    // A vertex shared by a face with a 90° corner (normal +z) and a face with a 45° corner (normal +x):
    // angle weights give normalize(π/2·z + π/4·x); area weights would follow the larger face.
    TriangleMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0},  // face 0, 1, 2 in z = 0: right angle at the origin
                   {0, 0, -1}, {0, 4, -4}};           // face 0, 3, 4 in x = 0: 45° there, 4x the area
    m.indices = {0, 1, 2, 0, 3, 4};
    m.compute_smooth_normals();
    const Vec3f n0 = m.normals[0];
    EXPECT_NEAR(n0.z, 1.f / std::sqrt(5.f) * 2.f, 1e-5f) << to_string(n0);
    EXPECT_NEAR(std::fabs(n0.x), 1.f / std::sqrt(5.f), 1e-5f) << to_string(n0);
}
