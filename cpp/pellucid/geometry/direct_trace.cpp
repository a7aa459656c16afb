// The direct trace of small scenes (direct_trace.h).
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/geometry/direct_trace.h"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>

#include "pellucid/util/error.h"

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#include <immintrin.h>
#endif

namespace pellucid::direct_trace {

namespace {
// Every lane is computed and the results selected (see sphere_first_root). The helpers that take
// or return 32-byte vectors are always inlined, so no call passes one across the baseline
// variant's ABI (which GCC's -Wpsabi note, silenced for this file, is about).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC push_options
#pragma GCC optimize("no-trapping-math")
#pragma GCC diagnostic ignored "-Wpsabi"
#endif
/// A call: the scene and rays [0, n) as arrays (soa) where valid.
struct Args {
    const Scene& s;
    int n;
    const float* const* soa;
    const bool* valid;
};
// The packet code, compiled for the baseline and, on x86-64 with GCC, for AVX2 and AVX-512, the
// widest the CPU runs chosen at start-up (set_variant chooses another); the same IEEE operations
// every way (no contraction), so the same bits.
#define PELLUCID_DIRECT_AVX2 0
namespace baseline {
constexpr int kTriangleLanes = 8;  // the lanes of one triangle test (16: one AVX-512 register)
#include "pellucid/geometry/direct_trace_kernels.inc"
}  // namespace baseline
#undef PELLUCID_DIRECT_AVX2
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define PELLUCID_DIRECT_X86_VARIANTS 1
#define PELLUCID_DIRECT_AVX2 1
#pragma GCC push_options
#pragma GCC target("avx2")
namespace avx2 {
constexpr int kTriangleLanes = 8;
#include "pellucid/geometry/direct_trace_kernels.inc"
}  // namespace avx2
#pragma GCC pop_options
#pragma GCC push_options
#pragma GCC target("avx512f,avx512dq,avx512vl,avx512bw")
namespace avx512 {
constexpr int kTriangleLanes = 16;
#include "pellucid/geometry/direct_trace_kernels.inc"
}  // namespace avx512
#pragma GCC pop_options
#undef PELLUCID_DIRECT_AVX2
#endif

/// One ray (r: origin, direction) with the lanes' tests, so the same bits: the closest hit in
/// (0, tmax] and the index of its primitive (spheres after triangles), or −1.
int closest1(const Scene& s, const float* r, float tmax, float* t_out, float* u_out, float* v_out) {
    int best = -1;
    float tb = tmax, ub = 0.f, vb = 0.f;
    for (int k = 0; k < s.n_tris; ++k) {
        float t, u, v;
        const bool h = k < s.n_quads ? baseline::primitive_hit<true, float>(s.tris[k], r, tb, &t, &u, &v)
                                     : baseline::primitive_hit<false, float>(s.tris[k], r, tb, &t, &u, &v);
        if (h) tb = t, ub = u, vb = v, best = k;
    }
    for (int k = 0; k < s.n_spheres; ++k) {
        bool h;
        const float t = sphere_first_root(*s.spheres[k], r[0], r[1], r[2], r[3], r[4], r[5], 0.f, tb, &h);
        if (h) tb = t, ub = 0.f, vb = 0.f, best = s.n_tris + k;
    }
    *t_out = tb, *u_out = ub, *v_out = vb;
    return best;
}
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC pop_options
#endif

struct Calls {
    void (*intersect)(const Args&, HitLanes&);
    void (*occluded)(const Args&, bool*);
};
const Calls kBaseline{baseline::intersect_packet, baseline::occluded_packet};
#ifdef PELLUCID_DIRECT_X86_VARIANTS
const Calls kAVX2{avx2::intersect_packet, avx2::occluded_packet};
const Calls kAVX512{avx512::intersect_packet, avx512::occluded_packet};
#endif
const Calls& calls_of(Variant v) {
#ifdef PELLUCID_DIRECT_X86_VARIANTS
    if (v == Variant::AVX512) return kAVX512;
    if (v == Variant::AVX2) return kAVX2;
#endif
    (void)v;
    return kBaseline;
}
/// The calls in use: the widest variant's unless set_variant chose another.
std::atomic<const Calls*>& current() {
    static std::atomic<const Calls*> c{&calls_of(available_variants().back())};
    return c;
}
const Calls& calls() { return *current().load(std::memory_order_relaxed); }
}  // namespace

std::vector<Variant> available_variants() {
    std::vector<Variant> v{Variant::Baseline};
#ifdef PELLUCID_DIRECT_X86_VARIANTS
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx2")) v.push_back(Variant::AVX2);
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
        __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512bw"))
        v.push_back(Variant::AVX512);
#endif
    return v;
}

void set_variant(Variant v) {
    const std::vector<Variant> ok = available_variants();
    if (std::find(ok.begin(), ok.end(), v) == ok.end())
        throw Error("direct_trace::set_variant: variant " + std::to_string(int(v)) + " is not available on this CPU");
    current().store(&calls_of(v), std::memory_order_relaxed);
}

void intersect(const Scene& s, int n, const float* const soa[7], const bool* valid, HitLanes& hits) {
    if (n > 0) calls().intersect(Args{s, n, soa, valid}, hits);
}
void occluded(const Scene& s, int n, const float* const soa[7], const bool* valid, bool* blocked) {
    if (n > 0) calls().occluded(Args{s, n, soa, valid}, blocked);
}

bool intersect(const Scene& s, const Ray& ray, RayHit& hit) {
    const float r[6] = {ray.o.x, ray.o.y, ray.o.z, ray.d.x, ray.d.y, ray.d.z};
    float t, u, v;
    const int k = closest1(s, r, ray.tmax, &t, &u, &v);
    if (k < 0) {
        hit.geom_id = ~0u;
        return false;
    }
    hit.t = t, hit.u = u, hit.v = v;
    if (k < s.n_tris) {  // Ng as Embree reports it: (p1 − p0) × (p2 − p0), unnormalised
        const TriangleData& d = s.tris[k];
        hit.geom_id = d.geom;
        baseline::decode_hit<float, uint32_t>(d.packed, u, v, &hit.prim_id, &hit.u, &hit.v);
        const float* ng = hit.prim_id == d.prim ? d.ng_a : d.ng_b;
        hit.ng = Vec3f(ng[0], ng[1], ng[2]);
        return true;
    }
    // A sphere's p − c in double, unnormalised (as Embree's callbacks report it).
    const SphereData& sd = *s.spheres[k - s.n_tris];
    hit.geom_id = s.sphere_ids[k - s.n_tris], hit.prim_id = 0;
    hit.ng = Vec3f(float(double(r[0]) + double(t) * r[3] - sd.cx), float(double(r[1]) + double(t) * r[4] - sd.cy),
                   float(double(r[2]) + double(t) * r[5] - sd.cz));
    return true;
}

bool occluded(const Scene& s, const Ray& ray) {
    const float r[6] = {ray.o.x, ray.o.y, ray.o.z, ray.d.x, ray.d.y, ray.d.z};
    for (int k = 0; k < s.n_tris; ++k) {
        float t, u, v;
        if (k < s.n_quads ? baseline::primitive_hit<true, float>(s.tris[k], r, ray.tmax, &t, &u, &v)
                          : baseline::primitive_hit<false, float>(s.tris[k], r, ray.tmax, &t, &u, &v))
            return true;
    }
    for (int k = 0; k < s.n_spheres; ++k) {
        bool h;
        sphere_first_root(*s.spheres[k], r[0], r[1], r[2], r[3], r[4], r[5], 0.f, ray.tmax, &h);
        if (h) return true;
    }
    return false;
}

namespace {
/// Corners p0, p1, p2 of triangle t as pointers into v.
void corners(const float* v, const uint32_t* idx, size_t t, const float* p[3]) {
    for (int j = 0; j < 3; ++j) p[j] = v + 3 * size_t(idx[3 * t + size_t(j)]);
}
bool same_point(const float* a, const float* b) { return a[0] == b[0] && a[1] == b[1] && a[2] == b[2]; }
/// Triangle (p0, p1, p2) as a primitive alone.
TriangleData triangle(const float* const p[3], uint32_t geom, uint32_t prim) {
    TriangleData d;
    for (int k = 0; k < 3; ++k) d.v0[k] = p[0][k], d.e1[k] = p[1][k] - p[0][k], d.e2[k] = p[2][k] - p[0][k];
    d.geom = geom, d.prim = prim;
    set_derived(d);
    d.ng_a[0] = d.e1[1] * d.e2[2] - d.e1[2] * d.e2[1];
    d.ng_a[1] = d.e1[2] * d.e2[0] - d.e1[0] * d.e2[2];
    d.ng_a[2] = d.e1[0] * d.e2[1] - d.e1[1] * d.e2[0];
    return d;
}
/// Triangles a and b as one quad, if they make one (append_mesh).
bool make_quad(const float* const a[3], const float* const b[3], TriangleData* out) {
    // The corners of a that b shares: exactly two, and a's third corner (the quad's corner 0).
    int shared[3], n_shared = 0, third = -1;
    for (int i = 0; i < 3; ++i) {
        int j = 0;
        while (j < 3 && !same_point(a[i], b[j])) ++j;
        if (j < 3) shared[n_shared++] = i;
        else third = i;
    }
    if (n_shared != 2) return false;
    int b_third = -1;
    for (int j = 0; j < 3; ++j)
        if (!same_point(b[j], a[shared[0]]) && !same_point(b[j], a[shared[1]])) b_third = j;
    if (b_third < 0) return false;
    const float *c0 = a[third], *c1 = a[shared[0]], *c2 = a[shared[1]], *c3 = b[b_third];
    float scale = 0.f;
    for (const float* c : {c0, c1, c2, c3})
        for (int k = 0; k < 3; ++k) scale = std::max(scale, std::fabs(c[k]));
    for (int k = 0; k < 3; ++k)  // corner 3 = corners 1 + 2 − 0, to rounding
        if (!(std::fabs((c1[k] + c2[k]) - (c0[k] + c3[k])) <= 1e-6f * scale)) return false;
    TriangleData d;
    for (int k = 0; k < 3; ++k) d.v0[k] = c0[k], d.e1[k] = c1[k] - c0[k], d.e2[k] = c2[k] - c0[k];
    set_derived(d);
    d.quad = true;
    auto corner = [&](const float* p) -> uint8_t {
        return same_point(p, c0) ? 0 : same_point(p, c1) ? 1 : same_point(p, c2) ? 2 : 3;
    };
    d.a1 = corner(a[1]), d.a2 = corner(a[2]), d.b1 = corner(b[1]), d.b2 = corner(b[2]);
    return *out = d, true;
}
}  // namespace

void append_mesh(std::vector<TriangleData>& out, const float* v, const uint32_t* idx, size_t triangles, uint32_t geom) {
    for (size_t t = 0; t < triangles; ++t) {
        const float *a[3], *b[3];
        corners(v, idx, t, a);
        const TriangleData ta = triangle(a, geom, uint32_t(t));
        TriangleData q;
        if (t + 1 < triangles) {
            corners(v, idx, t + 1, b);
            if (make_quad(a, b, &q)) {
                const TriangleData tb = triangle(b, geom, uint32_t(t + 1));
                q.geom = geom, q.prim = uint32_t(t), q.packed = pack_hit(q);
                std::copy(ta.ng_a, ta.ng_a + 3, q.ng_a), std::copy(tb.ng_a, tb.ng_a + 3, q.ng_b);
                out.push_back(q);
                ++t;
                continue;
            }
        }
        out.push_back(ta);
    }
}

namespace {
/// The bound of spheres [first, first + count): the middle of their centres' box, and the farthest
/// member surface from it (in double), then in float rounded outward (float_sphere).
FloatSphere bound_of(const std::vector<const SphereData*>& s, int first, int count, double* lo, double* hi) {
    for (int a = 0; a < 3; ++a) lo[a] = INFINITY, hi[a] = -INFINITY;
    for (int k = first; k < first + count; ++k) {
        const double c[3] = {s[size_t(k)]->cx, s[size_t(k)]->cy, s[size_t(k)]->cz};
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], c[a]), hi[a] = std::max(hi[a], c[a]);
    }
    const double m[3] = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
    double r = 0.0;
    for (int k = first; k < first + count; ++k) {
        const SphereData& d = *s[size_t(k)];
        const double dx = d.cx - m[0], dy = d.cy - m[1], dz = d.cz - m[2];
        r = std::max(r, std::sqrt(dx * dx + dy * dy + dz * dz) + std::sqrt(d.r2));
    }
    return float_sphere(m[0], m[1], m[2], r * (1.0 + 1e-12));
}
void split(std::vector<const SphereData*>& s, std::vector<uint32_t>& ids, int first, int count,
           std::vector<SphereCluster>& out) {
    double lo[3], hi[3];
    const FloatSphere bound = bound_of(s, first, count, lo, hi);
    if (count <= kClusterSpheres) {
        out.push_back({bound, first, count});
        return;
    }
    int axis = 0;
    for (int a = 1; a < 3; ++a)
        if (hi[a] - lo[a] > hi[axis] - lo[axis]) axis = a;
    auto key = [axis](const SphereData* d) { return axis == 0 ? d->cx : axis == 1 ? d->cy : d->cz; };
    // The range sorted by the axis (ties in their order), the ids alike.
    std::vector<int> order(static_cast<size_t>(count));
    for (int k = 0; k < count; ++k) order[size_t(k)] = first + k;
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return key(s[size_t(a)]) < key(s[size_t(b)]); });
    std::vector<const SphereData*> s2;
    std::vector<uint32_t> i2;
    for (int k : order) s2.push_back(s[size_t(k)]), i2.push_back(ids[size_t(k)]);
    std::copy(s2.begin(), s2.end(), s.begin() + first);
    std::copy(i2.begin(), i2.end(), ids.begin() + first);
    const int half = count / 2;
    split(s, ids, first, half, out);
    split(s, ids, first + half, count - half, out);
}
}  // namespace

std::vector<SphereCluster> build_clusters(std::vector<const SphereData*>& spheres, std::vector<uint32_t>& ids) {
    std::vector<SphereCluster> out;
    if (!spheres.empty()) split(spheres, ids, 0, int(spheres.size()), out);
    return out;
}

}  // namespace pellucid::direct_trace
