// The vertices of a packet of kernel hits (geometry/hit_lanes.h) on a scene's spheres and triangle
// meshes: each lane's shape data is fetched one lane at a time (fetch_hit_vertex), then every
// lane's vertex is computed at once (hit_vertices). (Hits on the triangles of the path tracer's
// triangle table, PathSetup::tri_table, gather the same inputs by triangle instead.) The path kernel shades the hits whose material
// has a packet form with these; each lane carries the bits Scene::fill_hit gives the same hit
// (tests/cpp/scene/test_hit_lanes.cpp compares them on every SIMD target).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include "pellucid/geometry/hit_lanes.h"
#include "pellucid/scene/scene.h"

namespace pellucid {

/// What a packet's hit vertices are computed from, one entry per lane.
template <int W>
struct alignas(64) HitVertexInputs {
    float ox[W], oy[W], oz[W], dx[W], dy[W], dz[W], t[W];  // a sphere's: the ray, the refined t
    float cx[W], cy[W], cz[W], r[W], rot[9][W];            // centre, radius, rotation (columns)
    float p0[3][W], p1[3][W], p2[3][W], b1[W], b2[W];       // a triangle's corners, barycentrics
    float ng[3][W], fs[3][W], ft[3][W], fn[3][W];           // a flat one's normal and shading frame
    float uv[6][W], n0[3][W], n1[3][W], n2[3][W];           // a smooth one's uvs and vertex normals
    bool sphere[W], tri[W], smooth[W], flip[W];             // the lane's shape (none: not a vertex lane)
    bool any_sphere, any_tri, any_smooth;

    void clear() {
        for (int i = 0; i < W; ++i) sphere[i] = tri[i] = smooth[i] = false;
        any_sphere = any_tri = any_smooth = false;
    }
    bool any() const { return any_sphere || any_tri || any_smooth; }
};

/// Component c of a 3-vector, always inlined: the kernels are compiled once per instruction set, and
/// an out-of-line copy of glm's operator[] would be emitted in each under one name
/// (tests/cpp/integrator/check_kernel_symbols.py; GCC kept one such copy at -O1 in the sanitizer build).
template <class V>
[[gnu::always_inline]] inline float vec_component(const V& v, int c) {
    return c == 0 ? v.x : c == 1 ? v.y : v.z;
}

/// Lane i's inputs for the hit h of ray r (h.hit()), as Scene::fill_hit reads them.
template <int W>
[[gnu::always_inline]] inline void fetch_hit_vertex(const Scene& scene, const Ray& r, const RayHit& h, int i,
                                                    HitVertexInputs<W>& hv) {
    const ShapeRecord& s = scene.shapes[h.geom_id];
    if (s.kind == ShapeRecord::Kind::Sphere) {
        hv.ox[i] = r.o.x, hv.oy[i] = r.o.y, hv.oz[i] = r.o.z;
        hv.dx[i] = r.d.x, hv.dy[i] = r.d.y, hv.dz[i] = r.d.z;
        hv.t[i] = h.t;
        hv.cx[i] = s.center.x, hv.cy[i] = s.center.y, hv.cz[i] = s.center.z, hv.r[i] = s.radius;
        for (int c = 0; c < 9; ++c) hv.rot[c][i] = vec_component(s.rotation[c / 3], c % 3);
        hv.flip[i] = s.flip_normals;
        hv.sphere[i] = hv.any_sphere = true;
        return;
    }
    const TriangleMesh& mesh = scene.meshes[s.mesh_index];
    const uint32_t* idx = &mesh.indices[3 * size_t(h.prim_id)];
    for (int c = 0; c < 3; ++c) {
        hv.p0[c][i] = vec_component(mesh.positions[idx[0]], c);
        hv.p1[c][i] = vec_component(mesh.positions[idx[1]], c);
        hv.p2[c][i] = vec_component(mesh.positions[idx[2]], c);
    }
    hv.b1[i] = h.u, hv.b2[i] = h.v;
    if (!mesh.flat.empty()) {
        const FlatTriangle& f = mesh.flat[h.prim_id];
        for (int c = 0; c < 3; ++c)
            hv.ng[c][i] = vec_component(f.ng, c), hv.fs[c][i] = vec_component(f.shading.s, c),
            hv.ft[c][i] = vec_component(f.shading.t, c), hv.fn[c][i] = vec_component(f.shading.n, c);
        hv.tri[i] = hv.any_tri = true;
        return;
    }
    // Interpolated normals; without uvs the triangle's own (0,0), (1,0), (1,1) (Scene::fill_hit).
    const float kUV[6] = {0.f, 0.f, 1.f, 0.f, 1.f, 1.f};
    for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 2; ++c) hv.uv[2 * k + c][i] = mesh.uvs.empty() ? kUV[2 * k + c] : mesh.uvs[idx[k]][c];
    const bool has_n = !mesh.normals.empty();
    for (int c = 0; c < 3; ++c) {
        hv.n0[c][i] = has_n ? vec_component(mesh.normals[idx[0]], c) : 0.f;
        hv.n1[c][i] = has_n ? vec_component(mesh.normals[idx[1]], c) : 0.f;
        hv.n2[c][i] = has_n ? vec_component(mesh.normals[idx[2]], c) : 0.f;
    }
    hv.smooth[i] = hv.any_smooth = true;
}

/// Meshes of more than kPrefetchTriangles triangles do not fit the caches, and a hit's record
/// (fetch_hit_vertex, Scene::fill_hit) starts with a read of its triangle's index row that misses
/// them: prefetch_index_rows requests the rows of the lanes `take` that hit such a mesh as soon
/// as the packet's hits are known, so that their reads overlap the work before the records are made.
inline constexpr size_t kPrefetchTriangles = size_t(1) << 16;
/// The mesh of geometry g if it has more than kPrefetchTriangles triangles, else null.
[[gnu::always_inline]] inline const TriangleMesh* large_mesh(const Scene& scene, uint32_t g) {
    const ShapeRecord& s = scene.shapes[g];
    if (s.kind != ShapeRecord::Kind::Mesh) return nullptr;
    const TriangleMesh& m = scene.meshes[s.mesh_index];
    return m.triangle_count() > kPrefetchTriangles ? &m : nullptr;
}
template <int W>
[[gnu::always_inline]] inline void prefetch_index_rows(const Scene& scene, const uint32_t* geom_id, const uint32_t* prim_id, const bool* take) {
    for (int i = 0; i < W; ++i)
        if (const TriangleMesh* m = take[i] ? large_mesh(scene, geom_id[i]) : nullptr)
            __builtin_prefetch(&m->indices[3 * size_t(prim_id[i])]);
}
/// The corners, vertex normals and uvs of the same lanes' triangles, through their index rows
/// (requested just before the records are made, once the rows have had the time to arrive).
template <int W>
[[gnu::always_inline]] inline void prefetch_vertices(const Scene& scene, const uint32_t* geom_id, const uint32_t* prim_id, const bool* take) {
    for (int i = 0; i < W; ++i) {
        const TriangleMesh* m = take[i] ? large_mesh(scene, geom_id[i]) : nullptr;
        if (!m) continue;
        const uint32_t* idx = &m->indices[3 * size_t(prim_id[i])];
        for (int c = 0; c < 3; ++c) {
            __builtin_prefetch(&m->positions[idx[c]]);
            if (!m->normals.empty()) __builtin_prefetch(&m->normals[idx[c]]);
            if (!m->uvs.empty()) __builtin_prefetch(&m->uvs[idx[c]]);
        }
    }
}

/// The vertices of every lane fetched (lanes fetched as none hold unspecified values).
template <class F>
[[gnu::always_inline]] inline HitVertexT<F> hit_vertices(const HitVertexInputs<kLaneWidth<F>>& hv) {
    using M = MaskT<F>;
    auto LD = [](const float* p) { return lane::load_as<F>(p); };
    auto V = [&](const float* x, const float* y, const float* z) { return V3<F>(LD(x), LD(y), LD(z)); };
    auto V3A = [&](const float (&c)[3][kLaneWidth<F>]) { return V(c[0], c[1], c[2]); };
    auto merge = [](const M& where, const HitVertexT<F>& from, HitVertexT<F>& to) {
        to.p = lane::select(where, from.p, to.p);
        to.p_error = lane::select(where, from.p_error, to.p_error);
        to.ng = lane::select(where, from.ng, to.ng);
        to.shading = FrameT<F>(lane::select(where, from.shading.s, to.shading.s),
                               lane::select(where, from.shading.t, to.shading.t),
                               lane::select(where, from.shading.n, to.shading.n));
    };
    HitVertexT<F> v;
    bool have = false;
    if (hv.any_tri) {
        v = flat_triangle_vertex<F>(V3A(hv.p0), V3A(hv.p1), V3A(hv.p2), LD(hv.b1), LD(hv.b2), V3A(hv.ng),
                                    FrameT<F>(V3A(hv.fs), V3A(hv.ft), V3A(hv.fn)));
        have = true;
    }
    if (hv.any_smooth) {
        auto uv = [&](int k) { return V2<F>{LD(hv.uv[2 * k]), LD(hv.uv[2 * k + 1])}; };
        const TriangleTangentsT<F> tri = triangle_tangents<F>(V3A(hv.p0), V3A(hv.p1), V3A(hv.p2), uv(0), uv(1), uv(2));
        const HitVertexT<F> sv = smooth_triangle_vertex<F>(V3A(hv.p0), V3A(hv.p1), V3A(hv.p2), LD(hv.b1), LD(hv.b2), tri,
                                                           V3A(hv.n0), V3A(hv.n1), V3A(hv.n2));
        if (have) merge(lane::load_mask_as<M>(hv.smooth), sv, v);
        else v = sv;
        have = true;
    }
    if (hv.any_sphere) {
        auto col = [&](int k) { return V(hv.rot[3 * k], hv.rot[3 * k + 1], hv.rot[3 * k + 2]); };
        SphereTangentsT<F> tangents;
        const HitVertexT<F> sv = sphere_vertex<F>(V(hv.ox, hv.oy, hv.oz), V(hv.dx, hv.dy, hv.dz), LD(hv.t),
                                                  V(hv.cx, hv.cy, hv.cz), LD(hv.r), Mat3T<F>{col(0), col(1), col(2)},
                                                  lane::load_mask_as<M>(hv.flip), &tangents);
        if (have) merge(lane::load_mask_as<M>(hv.sphere), sv, v);
        else v = sv;
    }
    return v;
}
}  // namespace pellucid
