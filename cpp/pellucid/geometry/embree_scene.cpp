// Embree 3 wrapper: every rtc* call of pellucid lives here.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/geometry/embree_scene.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <limits>
#include <string>
#include <vector>

#include "pellucid/geometry/direct_trace.h"
#include "pellucid/util/error.h"

namespace pellucid {

namespace {
using direct_trace::SphereData;
using direct_trace::TriangleData;
using direct_trace::sphere_first_root;
/// The direct trace is allowed unless PELLUCID_TRACE is `embree` (for comparisons of the two).
bool direct_tracing_default() {
    const char* env = std::getenv("PELLUCID_TRACE");
    return !(env && std::string(env) == "embree");
}
struct TraceCalls;  // the packet traces of one instruction-set variant (below)
const TraceCalls& trace_calls(EmbreeScene::PacketVariant v);
}  // namespace

struct EmbreeScene::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    uint32_t next_id = 0;
    std::string error;  // set by the device's error callback, raised after each build call
    // The analytic spheres, each a one-primitive user geometry whose callbacks read its entry here
    // (a deque: the entries never move while geometries point at them).
    std::deque<SphereData> spheres;
    std::vector<uint32_t> sphere_ids;  // the geometry id of each entry of spheres
    uint32_t meshes = 0;
    // A small scene is traced without Embree (commit(), direct_trace.h): every ray against every
    // triangle (each mesh's, recorded while there are few) and sphere.
    bool direct = false;
    bool allow_direct = direct_tracing_default();  // set_direct_tracing
    bool committed = false;
    void decide_direct() {
        direct = committed && allow_direct && triangle_count <= 2 * direct_trace::kMaxPrimitives &&
                 direct_trace::worth_tracing_directly(triangles.size(), spheres.size());
    }
    // Every mesh's triangles as the direct trace's primitives, quads first (commit()), while there
    // are at most 2 kMaxPrimitives triangles.
    std::vector<TriangleData> triangles;
    int quads = 0;
    size_t triangle_count = 0;
    // The spheres in the direct trace's cluster order, their ids alike, and the clusters.
    std::vector<const SphereData*> sphere_ptrs;
    std::vector<uint32_t> sphere_ptr_ids;
    std::vector<direct_trace::SphereCluster> clusters;
    direct_trace::Scene direct_scene() const {
        return {triangles.data(), int(triangles.size()), quads, sphere_ptrs.data(), sphere_ptr_ids.data(),
                int(sphere_ptrs.size()), clusters.data(), int(clusters.size())};
    }
    const TraceCalls* trace = &trace_calls(EmbreeScene::packet_variants().back());
    void check() {
        if (!error.empty()) {
            std::string e = error;
            error.clear();
            throw Error(e);
        }
    }
};

namespace {
// Exceptions must not cross Embree's C frames, so the callback only records the message.
void error_callback(void* user, RTCError code, const char* str) {
    static_cast<std::string*>(user)->assign("Embree error " + std::to_string(int(code)) + ": " +
                                            (str ? str : ""));
}
}  // namespace

EmbreeScene::EmbreeScene() : m_impl(std::make_unique<Impl>()) {
    m_impl->device = rtcNewDevice(nullptr);
    if (!m_impl->device) throw Error("could not create an Embree device");
    rtcSetDeviceErrorFunction(m_impl->device, error_callback, &m_impl->error);
    m_impl->scene = rtcNewScene(m_impl->device);
    // LOW makes Embree build two levels: a BVH per geometry (at the geometry's default MEDIUM
    // quality) under a top-level BVH over the geometries. Measured on our scenes (2 threads, same
    // image bit for bit): the Cornell box traces 1.35x faster than with one HIGH-quality BVH over all
    // triangles (32 spp: 4.1 against 3.0 M samples/s), the box with a 360k-triangle sphere added
    // 1.15x; the sphere and textured scenes, which spend their time shading, are unchanged.
    rtcSetSceneBuildQuality(m_impl->scene, RTC_BUILD_QUALITY_LOW);
    rtcSetSceneFlags(m_impl->scene, RTC_SCENE_FLAG_NONE);
}

EmbreeScene::~EmbreeScene() {
    if (m_impl->scene) rtcReleaseScene(m_impl->scene);
    if (m_impl->device) rtcReleaseDevice(m_impl->device);
}

uint32_t EmbreeScene::add_mesh(const TriangleMesh& mesh) {
    RTCGeometry g = rtcNewGeometry(m_impl->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), mesh.positions.size()));
    for (size_t i = 0; i < mesh.positions.size(); ++i)
        for (int k = 0; k < 3; ++k) v[3 * i + k] = mesh.positions[i][k];
    auto* idx = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(uint32_t), mesh.triangle_count()));
    for (size_t i = 0; i < mesh.indices.size(); ++i) idx[i] = mesh.indices[i];
    rtcCommitGeometry(g);
    uint32_t id = m_impl->next_id++;
    m_impl->triangle_count += mesh.triangle_count();
    if (m_impl->triangle_count <= 2 * direct_trace::kMaxPrimitives)  // (more: never traced directly)
        direct_trace::append_mesh(m_impl->triangles, v, idx, mesh.triangle_count(), id);
    rtcAttachGeometryByID(m_impl->scene, g, id);
    rtcReleaseGeometry(g);
    m_impl->check();
    ++m_impl->meshes;
    return id;
}

namespace {

// The sphere tests below compute every lane and select the results, which GCC vectorises only
// when it may evaluate floating-point operations whose results a lane does not use (their
// exceptions are never read here); the values are the same either way.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC push_options
#pragma GCC optimize("no-trapping-math")
#endif
/// The callbacks for a packet of N rays, every lane computed and only valid hits written (called
/// with N a constant for Embree's widths 1, 4, 8 and 16, so that the loops vectorise).
[[gnu::always_inline]] inline void sphere_intersect_n(const RTCIntersectFunctionNArguments* args, const unsigned N) {
    const SphereData& s = *static_cast<const SphereData*>(args->geometryUserPtr);
    const float* r = reinterpret_cast<const float*>(args->rayhit);  // RTCRayN's layout (rtcore_ray.h)
    float* tfar = reinterpret_cast<float*>(args->rayhit) + 8 * N;
    float* h = reinterpret_cast<float*>(args->rayhit) + 12 * N;  // RTCHitN follows the 12 ray fields
    unsigned* hu = reinterpret_cast<unsigned*>(h);
    const unsigned inst = args->context->instID[0], prim = args->primID, geom = args->geomID;
    for (unsigned i = 0; i < N; ++i) {
        bool hit;
        const float ox = r[i], oy = r[N + i], oz = r[2 * N + i], dx = r[4 * N + i], dy = r[5 * N + i], dz = r[6 * N + i];
        const float t = sphere_first_root(s, ox, oy, oz, dx, dy, dz, r[3 * N + i], tfar[i], &hit);
        const bool take = hit & (args->valid[i] != 0);
        // Ng = p − c (unnormalised, as Embree's own geometries report it); the renderer recomputes
        // the hit's point and frame from t (geometry/hit_lanes.h).
        const float nx = float(double(ox) + double(t) * dx - s.cx);
        const float ny = float(double(oy) + double(t) * dy - s.cy);
        const float nz = float(double(oz) + double(t) * dz - s.cz);
        tfar[i] = take ? t : tfar[i];
        h[i] = take ? nx : h[i];
        h[N + i] = take ? ny : h[N + i];
        h[2 * N + i] = take ? nz : h[2 * N + i];
        h[3 * N + i] = take ? 0.f : h[3 * N + i];            // u
        h[4 * N + i] = take ? 0.f : h[4 * N + i];            // v
        hu[5 * N + i] = take ? prim : hu[5 * N + i];         // primID
        hu[6 * N + i] = take ? geom : hu[6 * N + i];         // geomID
        hu[7 * N + i] = take ? inst : hu[7 * N + i];         // instID[0]
    }
}
[[gnu::always_inline]] inline void sphere_occluded_n(const RTCOccludedFunctionNArguments* args, const unsigned N) {
    const SphereData& s = *static_cast<const SphereData*>(args->geometryUserPtr);
    float* r = reinterpret_cast<float*>(args->ray);
    for (unsigned i = 0; i < N; ++i) {
        bool hit;
        sphere_first_root(s, r[i], r[N + i], r[2 * N + i], r[4 * N + i], r[5 * N + i], r[6 * N + i], r[3 * N + i],
                          r[8 * N + i], &hit);
        r[8 * N + i] = hit & (args->valid[i] != 0) ? -std::numeric_limits<float>::infinity() : r[8 * N + i];
    }
}
static_assert(sizeof(float) == sizeof(unsigned), "RTCHitN mixes float and unsigned fields of one size");


#define PELLUCID_SPHERE_CALLBACKS(SUFFIX, ATTR)                                                        \
    ATTR void sphere_intersect_##SUFFIX(const RTCIntersectFunctionNArguments* args) {                  \
        switch (args->N) {                                                                            \
        case 16: return sphere_intersect_n(args, 16);                                                 \
        case 8: return sphere_intersect_n(args, 8);                                                   \
        case 4: return sphere_intersect_n(args, 4);                                                   \
        case 1: return sphere_intersect_n(args, 1);                                                   \
        default: return sphere_intersect_n(args, args->N);                                                \
        }                                                                                             \
    }                                                                                                 \
    ATTR void sphere_occluded_##SUFFIX(const RTCOccludedFunctionNArguments* args) {                    \
        switch (args->N) {                                                                            \
        case 16: return sphere_occluded_n(args, 16);                                                  \
        case 8: return sphere_occluded_n(args, 8);                                                    \
        case 4: return sphere_occluded_n(args, 4);                                                    \
        case 1: return sphere_occluded_n(args, 1);                                                    \
        default: return sphere_occluded_n(args, args->N);                                              \
        }                                                                                             \
    }
// The callbacks, compiled for the baseline and, on x86-64 with GCC, for AVX2
// (four doubles a vector, no FMA) and AVX-512 (eight), the widest the CPU runs chosen once
// (sphere_calls); the same bits every way (sphere_first_root: IEEE operations in double, never
// contracted).
PELLUCID_SPHERE_CALLBACKS(baseline, )
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define PELLUCID_SPHERE_X86_VARIANTS 1
PELLUCID_SPHERE_CALLBACKS(avx2, __attribute__((target("avx2"))))
PELLUCID_SPHERE_CALLBACKS(avx512, __attribute__((target("avx512f,avx512dq,avx512vl,avx512bw"))))
#endif
#undef PELLUCID_SPHERE_CALLBACKS
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC pop_options
#endif

void sphere_bounds(const RTCBoundsFunctionArguments* args) {
    const auto& s = *static_cast<const SphereData*>(args->geometryUserPtr);
    RTCBounds* b = args->bounds_o;
    b->lower_x = s.lower[0], b->lower_y = s.lower[1], b->lower_z = s.lower[2];
    b->upper_x = s.upper[0], b->upper_y = s.upper[1], b->upper_z = s.upper[2];
}

/// The callbacks of the widest variant this CPU runs.
struct SphereCallbacks {
    RTCIntersectFunctionN intersect;
    RTCOccludedFunctionN occluded;
};
SphereCallbacks sphere_variant() {
#ifdef PELLUCID_SPHERE_X86_VARIANTS
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
        __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512bw"))
        return {sphere_intersect_avx512, sphere_occluded_avx512};
    if (__builtin_cpu_supports("avx2"))
        return {sphere_intersect_avx2, sphere_occluded_avx2};
#endif
    return {sphere_intersect_baseline, sphere_occluded_baseline};
}
const SphereCallbacks& sphere_calls() {
    static const SphereCallbacks v = sphere_variant();
    return v;
}
}  // namespace

// A sphere is a user geometry with the callbacks above, not Embree's RTC_GEOMETRY_TYPE_SPHERE_POINT:
// measured on one unit sphere and 16-ray packets of camera rays (rtcIntersect16, on our 2-core Zen 5
// machine), the point geometry costs about 33 ns a ray and a scalar callback about 3.5 ns.
uint32_t EmbreeScene::add_sphere(const Point3f& c, float r) {
    SphereData& s = m_impl->spheres.emplace_back();
    s.cx = c.x, s.cy = c.y, s.cz = c.z, s.r2 = double(r) * double(r);
    direct_trace::set_float_view(s);
    for (int k = 0; k < 3; ++k) {
        // Padded by a relative 1e-6 and by an ulp-scale absolute term, so that float rounding of
        // the bounds never cuts off the surface.
        const float pad = 1e-6f * (std::fabs(c[k]) + r) + 1e-30f;
        s.lower[k] = c[k] - r - pad;
        s.upper[k] = c[k] + r + pad;
    }
    RTCGeometry g = rtcNewGeometry(m_impl->device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(g, 1);
    rtcSetGeometryUserData(g, &s);
    rtcSetGeometryBoundsFunction(g, sphere_bounds, nullptr);
    rtcSetGeometryIntersectFunction(g, sphere_calls().intersect);
    rtcSetGeometryOccludedFunction(g, sphere_calls().occluded);
    rtcCommitGeometry(g);
    uint32_t id = m_impl->next_id++;
    rtcAttachGeometryByID(m_impl->scene, g, id);
    rtcReleaseGeometry(g);
    m_impl->check();
    m_impl->sphere_ids.push_back(id);
    return id;
}


void EmbreeScene::commit() {
    rtcCommitScene(m_impl->scene);
    m_impl->check();
    m_impl->sphere_ptrs.clear();
    for (const SphereData& sd : m_impl->spheres) m_impl->sphere_ptrs.push_back(&sd);
    m_impl->sphere_ptr_ids = m_impl->sphere_ids;
    m_impl->clusters = direct_trace::build_clusters(m_impl->sphere_ptrs, m_impl->sphere_ptr_ids);
    auto& tris = m_impl->triangles;
    m_impl->quads = int(std::stable_partition(tris.begin(), tris.end(), [](const TriangleData& d) { return d.quad; }) -
                        tris.begin());
    m_impl->committed = true;
    m_impl->decide_direct();
}

void EmbreeScene::set_direct_tracing(bool allow) {
    m_impl->allow_direct = allow;
    m_impl->decide_direct();
}

bool EmbreeScene::traced_directly() const { return m_impl->direct; }

bool EmbreeScene::intersect(const Ray& ray, RayHit& hit) const {
    if (m_impl->direct) return direct_trace::intersect(m_impl->direct_scene(), ray, hit);
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    rh.ray.org_x = ray.o.x;
    rh.ray.org_y = ray.o.y;
    rh.ray.org_z = ray.o.z;
    rh.ray.dir_x = ray.d.x;
    rh.ray.dir_y = ray.d.y;
    rh.ray.dir_z = ray.d.z;
    rh.ray.tnear = 0.f;
    rh.ray.tfar = ray.tmax;
    rh.ray.mask = ~0u;
    rh.ray.flags = 0;
    rh.ray.time = 0.f;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(m_impl->scene, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
        hit.geom_id = ~0u;
        return false;
    }
    hit.t = rh.ray.tfar;
    hit.geom_id = rh.hit.geomID;
    hit.prim_id = rh.hit.primID;
    hit.u = rh.hit.u;
    hit.v = rh.hit.v;
    hit.ng = Vec3f(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
    return true;
}

bool EmbreeScene::occluded(const Ray& ray) const {
    if (m_impl->direct) return direct_trace::occluded(m_impl->direct_scene(), ray);
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRay r;
    r.org_x = ray.o.x;
    r.org_y = ray.o.y;
    r.org_z = ray.o.z;
    r.dir_x = ray.d.x;
    r.dir_y = ray.d.y;
    r.dir_z = ray.d.z;
    r.tnear = 0.f;
    r.tfar = ray.tmax;
    r.mask = ~0u;
    r.flags = 0;
    r.time = 0.f;
    rtcOccluded1(m_impl->scene, &ctx, &r);
    return r.tfar < 0.f;
}

namespace {
/// Lanes [0, n) of an Embree ray packet from arrays (soa: origin, direction, tmax) where valid[i];
/// the others, and lanes past n, hold a well-formed empty ray whatever the caller left there (NaN
/// included: Embree's 16-wide call on an AVX2 build, done as two 8-wide halves, asserts that every
/// ray it carries is valid). mask[i] = −1 for a lane to trace, else 0.
///
/// A full packet (n = K, every kernel's packets but the 4-lane one) is filled Vn lanes at a time in
/// vectors (GCC/Clang vector extensions: Vn = 4 in the baseline instruction set, SSE2 or NEON, and 8
/// in the AVX2 variant, trace_calls): each field a select between the caller's value and the empty
/// ray's by the lane's mask, with no branch and no copy of run-time length; the mask from the Vn
/// bools read as bytes and widened. (Scalar loops over the lanes, which the compiler left
/// unvectorised, cost more than the copies and fix-ups below.)
template <int Vn>
struct FillVectors;  // Vn int32 lanes (V) and as many bytes (B)
template <>
struct FillVectors<4> {
    typedef int32_t V __attribute__((vector_size(16)));
    typedef uint8_t B __attribute__((vector_size(4)));
};
template <>
struct FillVectors<8> {
    typedef int32_t V __attribute__((vector_size(32)));
    typedef uint8_t B __attribute__((vector_size(8)));
};
template <int K, int Vn, class RayK>
[[gnu::always_inline]] inline void fill_lanes(RayK& r, int* mask, int n, const float* const soa[7], const bool* valid) {
    float* dst[7] = {r.org_x, r.org_y, r.org_z, r.dir_x, r.dir_y, r.dir_z, r.tfar};
    if (n == K) {
        using V = typename FillVectors<Vn>::V;
        using B = typename FillVectors<Vn>::B;
        static_assert(K % Vn == 0, "packets of whole vectors");
        static_assert(sizeof(bool) == 1, "one byte a bool");
        const V neg_inf = V{} + int32_t(0xff800000u);  // −∞: the empty ray's tfar
        for (int j = 0; j < K; j += Vn) {
            B bytes;
            std::memcpy(&bytes, valid + j, sizeof bytes);
            const V m = -__builtin_convertvector(bytes, V);  // (bools are 0 or 1)
            std::memcpy(mask + j, &m, sizeof m);
            for (int k = 0; k < 7; ++k) {
                V v;
                std::memcpy(&v, soa[k] + j, sizeof v);
                v = (v & m) | (k == 6 ? neg_inf & ~m : V{});
                std::memcpy(dst[k] + j, &v, sizeof v);
            }
            const V zero{}, ones = ~V{};
            std::memcpy(r.tnear + j, &zero, sizeof zero);
            std::memcpy(r.mask + j, &ones, sizeof ones);
            std::memcpy(r.flags + j, &zero, sizeof zero);
            std::memcpy(r.time + j, &zero, sizeof zero);
        }
        return;
    }
    for (int k = 0; k < 7; ++k) std::memcpy(dst[k], soa[k], sizeof(float) * size_t(n));
    for (int i = 0; i < K; ++i) {
        mask[i] = i < n && valid[i] ? -1 : 0;
        r.tnear[i] = 0.f;
        r.mask[i] = ~0u;
        r.flags[i] = 0;
        r.time[i] = 0.f;
    }
    for (int i = 0; i < K; ++i) {
        if (mask[i]) continue;
        for (int k = 0; k < 6; ++k) dst[k][i] = 0.f;
        dst[6][i] = -std::numeric_limits<float>::infinity();
    }
}
/// The first n lanes of a packet's field into out (a copy of fixed length for a full packet).
template <int K, class T>
[[gnu::always_inline]] inline void copy_lanes(T* out, const T* field, int n) {
    if (n == K) std::memcpy(out, field, sizeof(T) * size_t(K));
    else std::memcpy(out, field, sizeof(T) * size_t(n));
}
/// intersect_lanes on a K-wide packet (n ≤ K).
template <int K, int Vn, class RayHitK>
[[gnu::always_inline]] inline void intersect_k(RTCScene scene, int n, const float* const soa[7], const bool* valid,
                                               HitLanes& out) {
    alignas(64) RayHitK rh;
    alignas(64) int mask[K];
    fill_lanes<K, Vn>(rh.ray, mask, n, soa, valid);
    static_assert(RTC_INVALID_GEOMETRY_ID == ~0u, "a miss is geom_id ~0u: every byte 0xff");
    std::memset(rh.hit.geomID, 0xff, sizeof rh.hit.geomID);
    std::memset(rh.hit.instID[0], 0xff, sizeof rh.hit.instID[0]);
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    if constexpr (K == 16) rtcIntersect16(mask, scene, &ctx, &rh);
    else rtcIntersect8(mask, scene, &ctx, &rh);
    copy_lanes<K>(out.t, rh.ray.tfar, n);
    copy_lanes<K>(out.geom_id, rh.hit.geomID, n);
    copy_lanes<K>(out.prim_id, rh.hit.primID, n);
    copy_lanes<K>(out.u, rh.hit.u, n);
    copy_lanes<K>(out.v, rh.hit.v, n);
}
/// occluded_lanes on a K-wide packet (n ≤ K).
template <int K, int Vn, class RayK>
[[gnu::always_inline]] inline void occluded_k(RTCScene scene, int n, const float* const soa[7], const bool* valid,
                                              bool* occluded) {
    alignas(64) RayK r;
    alignas(64) int mask[K];
    fill_lanes<K, Vn>(r, mask, n, soa, valid);
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    if constexpr (K == 16) rtcOccluded16(mask, scene, &ctx, &r);
    else rtcOccluded8(mask, scene, &ctx, &r);
    if (n == K) {  // (a loop of fixed length without branches, which the compiler vectorises)
        for (int i = 0; i < K; ++i) occluded[i] = (mask[i] != 0) & (r.tfar[i] < 0.f);
        return;
    }
    for (int i = 0; i < n; ++i) occluded[i] = mask[i] != 0 && r.tfar[i] < 0.f;
}

/// The packet traces, compiled for the baseline and, on x86-64 with GCC, for AVX2 (their filling and
/// copying of the packets eight lanes a vector), the widest the CPU runs by default
/// (EmbreeScene::set_packet_variant chooses another): Embree's calls are the same either way.
struct TraceCalls {
    void (*intersect8)(RTCScene, int, const float* const*, const bool*, HitLanes&);
    void (*intersect16)(RTCScene, int, const float* const*, const bool*, HitLanes&);
    void (*occluded8)(RTCScene, int, const float* const*, const bool*, bool*);
    void (*occluded16)(RTCScene, int, const float* const*, const bool*, bool*);
};
#define PELLUCID_TRACE_CALLS(SUFFIX, ATTR, VN)                                                                   \
    ATTR void intersect8_##SUFFIX(RTCScene s, int n, const float* const* soa, const bool* valid, HitLanes& h) {   \
        intersect_k<8, VN, RTCRayHit8>(s, n, soa, valid, h);                                                      \
    }                                                                                                             \
    ATTR void intersect16_##SUFFIX(RTCScene s, int n, const float* const* soa, const bool* valid, HitLanes& h) {  \
        intersect_k<16, VN, RTCRayHit16>(s, n, soa, valid, h);                                                    \
    }                                                                                                             \
    ATTR void occluded8_##SUFFIX(RTCScene s, int n, const float* const* soa, const bool* valid, bool* blocked) {  \
        occluded_k<8, VN, RTCRay8>(s, n, soa, valid, blocked);                                                    \
    }                                                                                                             \
    ATTR void occluded16_##SUFFIX(RTCScene s, int n, const float* const* soa, const bool* valid, bool* blocked) { \
        occluded_k<16, VN, RTCRay16>(s, n, soa, valid, blocked);                                                  \
    }
PELLUCID_TRACE_CALLS(baseline, , 4)
#ifdef PELLUCID_SPHERE_X86_VARIANTS
PELLUCID_TRACE_CALLS(avx2, __attribute__((target("avx2"))), 8)
#endif
#undef PELLUCID_TRACE_CALLS
const TraceCalls& trace_calls(EmbreeScene::PacketVariant v) {
    static const TraceCalls baseline{intersect8_baseline, intersect16_baseline, occluded8_baseline, occluded16_baseline};
#ifdef PELLUCID_SPHERE_X86_VARIANTS
    static const TraceCalls avx2{intersect8_avx2, intersect16_avx2, occluded8_avx2, occluded16_avx2};
    if (v == EmbreeScene::PacketVariant::AVX2) return avx2;
#endif
    (void)v;
    return baseline;
}
}  // namespace

std::vector<EmbreeScene::PacketVariant> EmbreeScene::packet_variants() {
    std::vector<PacketVariant> v{PacketVariant::Baseline};
#ifdef PELLUCID_SPHERE_X86_VARIANTS
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx2")) v.push_back(PacketVariant::AVX2);
#endif
    return v;
}

void EmbreeScene::set_packet_variant(PacketVariant v) {
    const std::vector<PacketVariant> ok = packet_variants();
    if (std::find(ok.begin(), ok.end(), v) == ok.end())
        throw Error("EmbreeScene::set_packet_variant: variant " + std::to_string(int(v)) + " is not available on this CPU");
    m_impl->trace = &trace_calls(v);
}

void EmbreeScene::intersect_lanes(int n, const float* const soa[7], const bool* valid, HitLanes& hits) const {
    static_assert(kPacketSize == 16, "the packet calls below are at most 16 wide");
    if (n <= 0) return;
    if (m_impl->direct) return direct_trace::intersect(m_impl->direct_scene(), n, soa, valid, hits);
    // Up to 8 rays go as Embree's 8-wide packet (the 8-lane kernels' packets; an AVX2 build of
    // Embree would split a 16-wide call into two 8-wide ones), more as a 16-wide one.
    if (n <= 8) m_impl->trace->intersect8(m_impl->scene, n, soa, valid, hits);
    else m_impl->trace->intersect16(m_impl->scene, n, soa, valid, hits);
}

void EmbreeScene::occluded_lanes(int n, const float* const soa[7], const bool* valid, bool* occluded) const {
    if (n <= 0) return;
    if (m_impl->direct) return direct_trace::occluded(m_impl->direct_scene(), n, soa, valid, occluded);
    if (n <= 8) m_impl->trace->occluded8(m_impl->scene, n, soa, valid, occluded);
    else m_impl->trace->occluded16(m_impl->scene, n, soa, valid, occluded);
}

}  // namespace pellucid
