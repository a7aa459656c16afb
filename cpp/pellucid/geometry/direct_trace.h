// Rays traced without Embree: a small scene's rays tested against every one of its triangles and
// spheres (EmbreeScene::traced_directly), and the sphere test that Embree's sphere callbacks share.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "pellucid/geometry/embree_scene.h"

namespace pellucid::direct_trace {

/// A sphere in float for the direct trace's conservative pre-test: centre, a radius at least the
/// true one, and the centre's L1 norm.
struct FloatSphere {
    float c[3], r, c_l1;
};
/// An analytic sphere: centre and squared radius in double precision, its padded bounds (for
/// Embree's user geometry) and its float view (FloatSphere, set by set_float_view).
struct SphereData {
    double cx, cy, cz, r2;
    float lower[3], upper[3];
    FloatSphere view;
};
/// A sphere of centre (x, y, z) and radius r, all in double, in float: the radius rounded up and
/// widened by 10⁻⁶ of the centre's L1 norm, more than the rounding of the centre moves it.
inline FloatSphere float_sphere(double x, double y, double z, double r) {
    FloatSphere f;
    f.c[0] = float(x), f.c[1] = float(y), f.c[2] = float(z);
    f.r = std::nextafter(float(r + 1e-6 * (std::fabs(x) + std::fabs(y) + std::fabs(z))), INFINITY);
    f.c_l1 = std::fabs(f.c[0]) + std::fabs(f.c[1]) + std::fabs(f.c[2]);
    return f;
}
inline void set_float_view(SphereData& s) { s.view = float_sphere(s.cx, s.cy, s.cz, std::sqrt(s.r2)); }
/// Spheres [first, first + count) of a direct-trace scene, and a sphere around them all: a ray
/// whose line misses it misses each of them (build_clusters).
struct SphereCluster {
    FloatSphere bound;
    int first, count;
};
/// A primitive of the direct trace's mesh part: a triangle, or a quad, the parallelogram that two
/// triangles of a mesh sharing a diagonal make (append_mesh). Either is v0 + s·e1 + t·e2, over
/// s, t ≥ 0 and s + t ≤ 1 for a triangle, s, t ≤ 1 for a quad; for a triangle v0, e1 and e2 are its
/// first corner and the edges to the other two (the float vertices Embree gets). What the test
/// precomputes (set_derived), the ids a hit reports and, for a quad, which of its triangles a hit
/// lies in and their barycentrics (decode_hit, in direct_trace_kernels.inc).
struct TriangleData {
    float v0[3], e1[3], e2[3];
    float ne1[3];  ///< −e1
    float n[3];    ///< e2 × e1 (the negated normal e1 × e2)
    uint32_t geom, prim;
    bool quad = false;
    /// A quad: triangle A (prim) covers s + t ≤ 1, triangle B (prim + 1) the rest. Its corners are
    /// numbered 0: v0, 1: v0 + e1, 2: v0 + e2, 3: v0 + e1 + e2; a1, a2 (b1, b2) are those of A's
    /// (B's) vertices 1 and 2 (a triangle's: corners 1 and 2).
    uint8_t a1 = 1, a2 = 2, b1 = 0, b2 = 0;
    /// Each triangle's unnormalised geometric normal as Embree reports it, (p1 − p0) × (p2 − p0).
    float ng_a[3], ng_b[3];
    /// prim, with quad and the corners of a1, a2, b1, b2 above it (pack_hit).
    uint32_t packed;
};
/// A primitive's prim (below 2²³), quad and corners as one word: prim in bits 0–22, quad in bit 23,
/// a1, a2, b1, b2 in two bits each from bit 24 (decode_hit, direct_trace_kernels.inc).
inline uint32_t pack_hit(const TriangleData& d) {
    return d.prim | uint32_t(d.quad) << 23 | uint32_t(d.a1) << 24 | uint32_t(d.a2) << 26 | uint32_t(d.b1) << 28 |
           uint32_t(d.b2) << 30;
}
/// The word of a hit whose (s, t) are already its barycentrics (a triangle's, or a sphere's 0, 0).
constexpr uint32_t kPlainHit = 1u << 24 | 2u << 26;
/// Sets a primitive's ne1, n and packed from its other fields.
inline void set_derived(TriangleData& d) {
    for (int k = 0; k < 3; ++k) d.ne1[k] = -d.e1[k];
    d.n[0] = d.e2[1] * d.e1[2] - d.e2[2] * d.e1[1];
    d.n[1] = d.e2[2] * d.e1[0] - d.e2[0] * d.e1[2];
    d.n[2] = d.e2[0] * d.e1[1] - d.e2[1] * d.e1[0];
    d.packed = pack_hit(d);
}
/// Appends a mesh's triangles (positions v, three indices each in idx) to out as primitives:
/// triangles t and t + 1 as one quad where they share two corners (equal positions) and their
/// other corners complete a parallelogram (to float rounding: within 10⁻⁶ of the corners' largest
/// coordinate), else each alone.
void append_mesh(std::vector<TriangleData>& out, const float* v, const uint32_t* idx, size_t triangles, uint32_t geom);

// The sphere test computes every lane and selects the results, which GCC vectorises only when it
// may evaluate floating-point operations whose results a lane does not use (their exceptions are
// never read here); the values are the same either way.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC push_options
#pragma GCC optimize("no-trapping-math")
#endif
/// One lane of a sphere test: the first root of |o + t·d − c|² = r² in (tnear, tfar], computed in
/// double precision without cancellation (Numerical Recipes, 3rd ed., §5.6: with the half
/// coefficient b, q = −(b + sign(b)√disc), the roots are q/a and c/q), rounded to float; `hit`
/// tells whether there is one. Branch-free, so that loops over lanes vectorise; every operation is
/// one IEEE operation in double, so scalar and vector code give the same bits.
[[gnu::always_inline]] inline float sphere_first_root(const SphereData& s, float fox, float foy, float foz, float fdx,
                                                      float fdy, float fdz, float tnear, float tfar, bool* hit) {
    const double ox = double(fox) - s.cx, oy = double(foy) - s.cy, oz = double(foz) - s.cz;
    const double dx = fdx, dy = fdy, dz = fdz;
    const double a = dx * dx + dy * dy + dz * dz, b = ox * dx + oy * dy + oz * dz;
    const double c = ox * ox + oy * oy + oz * oz - s.r2, disc = b * b - a * c;
    const bool real = (disc >= 0.0) & (a > 0.0);
    const double sq = std::sqrt(real ? disc : 0.0);
    const double q = -(b + (b < 0.0 ? -sq : sq));  // −(b + sign(b)√disc), sign(±0) = +
    // (Both divisions always run, on a safe divisor where their result is not used: no branch.)
    const double r0 = q / (real ? a : 1.0), rc = c / (q != 0.0 ? q : 1.0), r1 = q != 0.0 ? rc : r0;
    const float f0 = float(r0 < r1 ? r0 : r1), f1 = float(r0 < r1 ? r1 : r0);
    const bool h0 = (f0 > tnear) & (f0 <= tfar), h1 = (f1 > tnear) & (f1 <= tfar);
    *hit = real & (h0 | h1);
    return h0 ? f0 : f1;
}
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC pop_options
#endif

/// A small scene's primitives: every ray is tested against each triangle, and against each
/// sphere of each cluster its line comes near.
struct Scene {
    const TriangleData* tris = nullptr;  ///< the quads first
    int n_tris = 0;
    int n_quads = 0;
    const SphereData* const* spheres = nullptr;  ///< in cluster order
    const uint32_t* sphere_ids = nullptr;        ///< the geometry id of each sphere
    int n_spheres = 0;
    const SphereCluster* clusters = nullptr;  ///< spheres [0, n_spheres) in order (build_clusters)
    int n_clusters = 0;
};

/// The most spheres a cluster holds.
constexpr int kClusterSpheres = 6;
/// Orders spheres (and their ids alike) into clusters of nearby ones, at most kClusterSpheres each:
/// halves the largest extent of their centres at its median, recursively, and returns the clusters.
std::vector<SphereCluster> build_clusters(std::vector<const SphereData*>& spheres, std::vector<uint32_t>& ids);

/// The most primitives (quads and triangles) a scene traced directly has, less a fifth of its
/// spheres (below). The direct trace's cost grows with every primitive, Embree's hardly. Render
/// time traced directly over Embree's (bench/README.md, "Small scenes without Embree"): 0.79 for
/// the Cornell box (18 quads), 0.90 for the fog box (19 quads), 0.85 to 0.93 for the suite's scenes
/// of 1 to 7 quads with up to 5 spheres, and 0.91 for 2 quads with 36 spheres
/// (bench/suite/many_materials.json), where a cluster's pre-test culls most spheres.
constexpr size_t kMaxPrimitives = 20;
/// Whether a scene of this many primitives (quads and triangles) and spheres is traced directly
/// rather than by Embree: where testing every ray against every primitive costs less than Embree's
/// packet call, a sphere counted as a fifth of a primitive (so at most 100 spheres). A scene of
/// spheres alone goes to Embree, whose packet call on its spheres' callbacks took 0.82 to 0.89 of
/// the direct trace's render time (one sphere: bench/suite/env_diffuse.json, env_rough_metal.json;
/// 4, 9 and 64 spheres: 0.88, 0.87, 0.74); with a mesh too, Embree traverses two kinds of geometry.
inline bool worth_tracing_directly(size_t primitives, size_t spheres) {
    return primitives > 0 && 5 * primitives + spheres <= 5 * kMaxPrimitives;
}

/// The instruction-set variants of the packet code (the same bits every way): the baseline
/// (eight lanes a primitive test), AVX2 (eight) and AVX-512 (sixteen).
enum class Variant { Baseline, AVX2, AVX512 };
/// The variants this CPU runs, narrowest first; the calls use the last.
std::vector<Variant> available_variants();
/// Has the calls use variant v from now on, in every thread (tests compare the variants); throws
/// pellucid::Error if this CPU cannot run it.
void set_variant(Variant v);

/// Rays [0, n ≤ 16) as arrays (soa: origin, direction, tmax) where valid[i]: the closest hit in
/// (0, tmax] (t, geometry and primitive ids, a triangle's barycentrics u, v of vertices 1 and 2, 0
/// on a sphere); lanes without one (and lanes not valid) report geom_id ~0u.
void intersect(const Scene& s, int n, const float* const soa[7], const bool* valid, HitLanes& hits);
/// Whether each ray has a hit in (0, tmax] (false where not valid).
void occluded(const Scene& s, int n, const float* const soa[7], const bool* valid, bool* blocked);
/// One ray, with the same tests (so the same hits as a lane of a packet), and the hit's
/// unnormalised geometric normal as Embree reports it (a triangle's e1 × e2, a sphere's p − c).
bool intersect(const Scene& s, const Ray& ray, RayHit& hit);
bool occluded(const Scene& s, const Ray& ray);

}  // namespace pellucid::direct_trace
