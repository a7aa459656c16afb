// The direct trace of small scenes (direct_trace.h).
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/geometry/direct_trace.h"

#include <algorithm>
#include <cstring>

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
/// Eight lanes of floats and their masks (GCC/Clang vector extensions: one AVX2 register, or two
/// SSE2 ones in the baseline variant; the same IEEE operation per element either way).
typedef float VF8 __attribute__((vector_size(32)));
typedef int32_t VI8 __attribute__((vector_size(32)));
/// Triangle d against rays r (origin, direction) with tmax, on eight lanes (V = VF8) or one
/// (V = float), the same IEEE operations either way: where it is hit in (0, tmax] (a lane mask, or
/// a bool), with t and the barycentrics (u, v) of vertices 1 and 2. Möller and Trumbore 1997, "Fast,
/// Minimum Storage Ray/Triangle Intersection", J. Graphics Tools 2(1), §2: with p = d × e2, s = o − v0
/// and q = s × e1, det = e1·p, u = s·p/det, v = d·q/det, t = e2·q/det; the hit needs det ≠ 0, u, v ≥ 0
/// and u + v ≤ 1 (edges and corners count, so a ray through a shared edge hits one of its triangles
/// unless rounding puts it just outside both).
template <class V>
[[gnu::always_inline]] inline auto triangle_hit(const TriangleData& d, const V* r, V tmax, V* t_out, V* u_out, V* v_out) {
    const V px = r[4] * d.e2[2] - r[5] * d.e2[1], py = r[5] * d.e2[0] - r[3] * d.e2[2], pz = r[3] * d.e2[1] - r[4] * d.e2[0];
    const V det = d.e1[0] * px + d.e1[1] * py + d.e1[2] * pz;
    const V tx = r[0] - d.v0[0], ty = r[1] - d.v0[1], tz = r[2] - d.v0[2];
    const V qx = ty * d.e1[2] - tz * d.e1[1], qy = tz * d.e1[0] - tx * d.e1[2], qz = tx * d.e1[1] - ty * d.e1[0];
    const auto nz = det != 0.f;
    const V one = V{} + 1.f;
    const V inv = one / (nz ? det : one);
    const V u = (tx * px + ty * py + tz * pz) * inv;
    const V v = (r[3] * qx + r[4] * qy + r[5] * qz) * inv;
    const V t = (d.e2[0] * qx + d.e2[1] * qy + d.e2[2] * qz) * inv;
    *t_out = t, *u_out = u, *v_out = v;
    return nz & (u >= 0.f) & (v >= 0.f) & (u + v <= 1.f) & (t > 0.f) & (t <= tmax);
}
template <class T>
[[gnu::always_inline]] inline T load8(const void* p) {
    T v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
template <class T>
[[gnu::always_inline]] inline void store8(void* p, T v) {
    std::memcpy(p, &v, sizeof v);
}
/// Rays [0, n) into N-lane arrays, tmax −1 (no hit possible) in lanes not valid or past n.
template <int N>
[[gnu::always_inline]] inline void load_rays(const Args& A, float (*r)[N], float* tmax) {
    if (A.n == N) {
        for (int k = 0; k < 6; ++k) std::memcpy(r[k], A.soa[k], sizeof(float) * N);
        for (int i = 0; i < N; ++i) tmax[i] = A.valid[i] ? A.soa[6][i] : -1.f;
        return;
    }
    for (int k = 0; k < 6; ++k) {
        std::memcpy(r[k], A.soa[k], sizeof(float) * size_t(A.n));
        for (int i = A.n; i < N; ++i) r[k][i] = 0.f;
    }
    for (int i = 0; i < N; ++i) tmax[i] = i < A.n && A.valid[i] ? A.soa[6][i] : -1.f;
}
[[gnu::always_inline]] inline VF8 fabs8(VF8 v) { return v < 0.f ? -v : v; }
/// Whether any lane of a mask is set.
[[gnu::always_inline]] inline bool any8(VI8 m) {
    uint64_t w[4];
    std::memcpy(w, &m, sizeof w);
    return ((w[0] | w[1]) | (w[2] | w[3])) != 0;
}
/// Eight rays as the float pre-test reads them: origin × direction, |d|²·(1 + 10⁻⁵), the origin's
/// L1 norm, and the lanes whose tmax is positive (or NaN).
struct PreRays {
    VF8 d[3], oxd[3], d2k, o_l1;
    VI8 live;
};
[[gnu::always_inline]] inline PreRays pre_rays(const VF8* r, VF8 tmax) {
    PreRays p;
    for (int k = 0; k < 3; ++k) p.d[k] = r[3 + k];
    p.oxd[0] = r[1] * r[5] - r[2] * r[4], p.oxd[1] = r[2] * r[3] - r[0] * r[5], p.oxd[2] = r[0] * r[4] - r[1] * r[3];
    p.d2k = (r[3] * r[3] + r[4] * r[4] + r[5] * r[5]) * (1.f + 1e-5f);
    p.o_l1 = fabs8(r[0]) + fabs8(r[1]) + fabs8(r[2]);
    p.live = ~(tmax <= 0.f);
    return p;
}
/// A conservative float pre-test of sphere s against eight rays: clear in a lane only where
/// sphere_first_root cannot find a hit there (on s, or on any sphere inside it). A lane passes
/// where it is live and the ray's line comes within s.r of the centre: |(c − o) × d|² ≤ r²|d|²,
/// with (c − o) × d computed as c × d − o × d. The float operations round each term by a few ulps
/// of |c||d| and |o||d|; the radius is widened by 10⁻⁵ of |c| + |o| (L1 norms), some hundred ulps
/// of them, and the bound by a factor 1 + 10⁻⁵, far more than those errors and than
/// sphere_first_root's rounding in double. The comparison is written as !(a > b), so that a NaN or
/// an overflow passes the lane.
[[gnu::always_inline]] inline VI8 sphere_may_hit(const FloatSphere& s, const PreRays& p) {
    const VF8 cx = (s.c[1] * p.d[2] - s.c[2] * p.d[1]) - p.oxd[0];
    const VF8 cy = (s.c[2] * p.d[0] - s.c[0] * p.d[2]) - p.oxd[1];
    const VF8 cz = (s.c[0] * p.d[1] - s.c[1] * p.d[0]) - p.oxd[2];
    const VF8 cross2 = cx * cx + cy * cy + cz * cz;
    const VF8 rr = s.r + 1e-5f * (p.o_l1 + s.c_l1);
    return ~(cross2 > (rr * rr) * p.d2k) & p.live;
}
/// Sphere s against the eight rays at lanes [c, c + 8) of r (origin, direction; local arrays, so
/// that the loop vectorises) in (0, tmax]: t and the hit mask (−1 or 0) per lane.
template <int N>
[[gnu::always_inline]] inline void sphere_roots8(const SphereData& s, const float (*r)[N], int c, const float* tmax,
                                                 float* t, int32_t* hit) {
    for (int i = 0; i < 8; ++i) {
        bool h;
        const int l = c + i;
        t[i] = sphere_first_root(s, r[0][l], r[1][l], r[2][l], r[3][l], r[4][l], r[5][l], 0.f, tmax[l], &h);
        hit[i] = h ? -1 : 0;
    }
}
/// Calls f(k), in the scene's order, for each sphere k whose float pre-tests (its cluster's where
/// that holds others, then its own) pass in some lane of the eight-lane block at c, whose rays are
/// r8 (origin, direction) and whose tmax the block's lanes of tmax hold. f may set a
/// lane's tmax to −1 where Blocks (occlusion: the lane is blocked), which drops it from the later
/// pre-tests.
/// (f passes no vector by value: a lambda does not take the target attribute of the function it is
/// written in, so a call to it that is not inlined would pass one under another ABI.)
template <bool Blocks, class Fn>
[[gnu::always_inline]] inline void for_spheres_near(const Args& A, const VF8* r8, int c, const float* tmax, Fn&& f) {
    PreRays p = pre_rays(r8, load8<VF8>(tmax + c));
    for (int g = 0; g < A.s.n_clusters && any8(p.live); ++g) {
        const SphereCluster& cl = A.s.clusters[g];
        if (cl.count > 1 && !any8(sphere_may_hit(cl.bound, p))) continue;
        for (int k = cl.first; k < cl.first + cl.count; ++k)
            if (any8(sphere_may_hit(A.s.spheres[k]->view, p))) {
                f(k);
                if (Blocks) p.live &= ~(load8<VF8>(tmax + c) <= 0.f);
            }
    }
}
template <int N>
[[gnu::always_inline]] inline void intersect_n(const Args& A, HitLanes& out) {
    alignas(32) float r[6][N], tb[N], ub[N], vb[N];
    uint32_t gb[N], pb[N];
    load_rays<N>(A, r, tb);
    for (int i = 0; i < N; ++i) gb[i] = ~0u, pb[i] = 0, ub[i] = 0.f, vb[i] = 0.f;
    for (int c = 0; c < N; c += 8) {
        VF8 r8[6];
        for (int k = 0; k < 6; ++k) r8[k] = load8<VF8>(r[k] + c);
        VF8 tt = load8<VF8>(tb + c), uu = load8<VF8>(ub + c), vv = load8<VF8>(vb + c);
        VI8 gg = load8<VI8>(gb + c), pp = load8<VI8>(pb + c);
        for (int k = 0; k < A.s.n_tris; ++k) {
            const TriangleData& d = A.s.tris[k];
            VF8 t, u, v;
            const VI8 h = triangle_hit<VF8>(d, r8, tt, &t, &u, &v);
            tt = h ? t : tt, uu = h ? u : uu, vv = h ? v : vv;
            gg = h ? VI8{} + int32_t(d.geom) : gg, pp = h ? VI8{} + int32_t(d.prim) : pp;
        }
        store8(tb + c, tt), store8(ub + c, uu), store8(vb + c, vv), store8(gb + c, gg), store8(pb + c, pp);
        // The spheres in double, in the scene's order, on the blocks their pre-tests pass (which
        // never fail a lane the double test hits: the same hits as testing every sphere).
        for_spheres_near<false>(A, r8, c, tb, [&](int k) {
            alignas(32) float t[8];
            alignas(32) int32_t h[8];
            sphere_roots8<N>(*A.s.spheres[k], r, c, tb, t, h);
            const VI8 m = load8<VI8>(h), id = VI8{} + int32_t(A.s.sphere_ids[k]);
            store8(tb + c, m ? load8<VF8>(t) : load8<VF8>(tb + c));
            store8(ub + c, m ? VF8{} : load8<VF8>(ub + c));
            store8(vb + c, m ? VF8{} : load8<VF8>(vb + c));
            store8(gb + c, m ? id : load8<VI8>(gb + c));
            store8(pb + c, m ? VI8{} : load8<VI8>(pb + c));
        });
    }
    for (int i = 0; i < A.n; ++i) {
        out.t[i] = A.valid[i] ? tb[i] : A.soa[6][i];
        out.geom_id[i] = gb[i], out.prim_id[i] = pb[i], out.u[i] = ub[i], out.v[i] = vb[i];
    }
}
template <int N>
[[gnu::always_inline]] inline void occluded_n(const Args& A, bool* blocked) {
    alignas(32) float r[6][N], tm[N];
    bool b[N];
    load_rays<N>(A, r, tm);
    for (int c = 0; c < N; c += 8) {
        VF8 r8[6];
        for (int k = 0; k < 6; ++k) r8[k] = load8<VF8>(r[k] + c);
        const VF8 tt = load8<VF8>(tm + c);
        VI8 hit{};
        for (int k = 0; k < A.s.n_tris; ++k) {
            VF8 t, u, v;
            hit |= triangle_hit<VF8>(A.s.tris[k], r8, tt, &t, &u, &v);
        }
        // A lane found blocked is not tested again: its tmax becomes −1, which no hit passes.
        store8(tm + c, hit ? VF8{} - 1.f : tt);
        for (int i = 0; i < 8; ++i) b[c + i] = hit[i] != 0;
        for_spheres_near<true>(A, r8, c, tm, [&](int k) {
            alignas(32) float t[8];
            alignas(32) int32_t h[8];
            sphere_roots8<N>(*A.s.spheres[k], r, c, tm, t, h);
            for (int i = 0; i < 8; ++i) b[c + i] |= h[i] != 0;
            store8(tm + c, load8<VI8>(h) ? VF8{} - 1.f : load8<VF8>(tm + c));
        });
    }
    for (int i = 0; i < A.n; ++i) blocked[i] = b[i];
}

/// One ray (r: origin, direction) with the lanes' tests, so the same bits: the closest hit in
/// (0, tmax] and the index of its primitive (spheres after triangles), or −1.
int closest1(const Scene& s, const float* r, float tmax, float* t_out, float* u_out, float* v_out) {
    int best = -1;
    float tb = tmax, ub = 0.f, vb = 0.f;
    for (int k = 0; k < s.n_tris; ++k) {
        float t, u, v;
        if (triangle_hit<float>(s.tris[k], r, tb, &t, &u, &v)) tb = t, ub = u, vb = v, best = k;
    }
    for (int k = 0; k < s.n_spheres; ++k) {
        bool h;
        const float t = sphere_first_root(*s.spheres[k], r[0], r[1], r[2], r[3], r[4], r[5], 0.f, tb, &h);
        if (h) tb = t, ub = 0.f, vb = 0.f, best = s.n_tris + k;
    }
    *t_out = tb, *u_out = ub, *v_out = vb;
    return best;
}

/// The calls of one instruction-set variant: up to 8 rays as one 8-lane block, more as two.
#define PELLUCID_DIRECT_CALLS(SUFFIX, ATTR)                                                            \
    ATTR void intersect_##SUFFIX(const Args& a, HitLanes& h) {                                        \
        if (a.n <= 8) return intersect_n<8>(a, h);                                                    \
        intersect_n<16>(a, h);                                                                        \
    }                                                                                                 \
    ATTR void occluded_##SUFFIX(const Args& a, bool* blocked) {                                       \
        if (a.n <= 8) return occluded_n<8>(a, blocked);                                               \
        occluded_n<16>(a, blocked);                                                                   \
    }
// Compiled for the baseline and, on x86-64 with GCC, for AVX2 and AVX-512, the widest the CPU runs
// chosen once; the same IEEE operations every way (no contraction), so the same bits.
PELLUCID_DIRECT_CALLS(baseline, )
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define PELLUCID_DIRECT_X86_VARIANTS 1
PELLUCID_DIRECT_CALLS(avx2, __attribute__((target("avx2"))))
PELLUCID_DIRECT_CALLS(avx512, __attribute__((target("avx512f,avx512dq,avx512vl,avx512bw"))))
#endif
#undef PELLUCID_DIRECT_CALLS
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC pop_options
#endif

struct Calls {
    void (*intersect)(const Args&, HitLanes&);
    void (*occluded)(const Args&, bool*);
};
Calls widest() {
#ifdef PELLUCID_DIRECT_X86_VARIANTS
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
        __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512bw"))
        return {intersect_avx512, occluded_avx512};
    if (__builtin_cpu_supports("avx2")) return {intersect_avx2, occluded_avx2};
#endif
    return {intersect_baseline, occluded_baseline};
}
const Calls& calls() {
    static const Calls c = widest();
    return c;
}
}  // namespace

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
    if (k < s.n_tris) {  // Ng as Embree reports it: e1 × e2, unnormalised
        const TriangleData& d = s.tris[k];
        hit.geom_id = d.geom, hit.prim_id = d.prim;
        hit.ng = cross(Vec3f(d.e1[0], d.e1[1], d.e1[2]), Vec3f(d.e2[0], d.e2[1], d.e2[2]));
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
        if (triangle_hit<float>(s.tris[k], r, ray.tmax, &t, &u, &v)) return true;
    }
    for (int k = 0; k < s.n_spheres; ++k) {
        bool h;
        sphere_first_root(*s.spheres[k], r[0], r[1], r[2], r[3], r[4], r[5], 0.f, ray.tmax, &h);
        if (h) return true;
    }
    return false;
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
