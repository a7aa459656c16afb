// EmbreeScene: the ray-tracing kernel. The only file that includes <embree3/rtcore.h> is the .cpp,
// so an Embree 4 migration touches one file.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "pellucid/geometry/mesh.h"
#include "pellucid/math/ray.h"

namespace pellucid {

/// Raw hit record as the kernel reports it.
struct RayHit {
    float t = kInfinity;
    uint32_t geom_id = ~0u;  ///< = the index returned by add_mesh/add_sphere
    uint32_t prim_id = 0;
    float u = 0.f, v = 0.f;  ///< triangle barycentrics of vertices 1 and 2
    Vec3f ng{0.f};           ///< unnormalised geometric normal
    bool hit() const { return geom_id != ~0u; }
};

/// The hits of a packet of up to EmbreeScene::kPacketSize rays, as arrays (lane i of each): the
/// path kernel reads them as packets. geom_id[i] = ~0u where ray i hit nothing or was not traced.
struct alignas(64) HitLanes {
    float t[16];
    uint32_t geom_id[16];
    uint32_t prim_id[16];
    float u[16], v[16];  ///< triangle barycentrics of vertices 1 and 2
    /// Lane i as a RayHit (without the geometric normal, which the scene computes itself).
    RayHit lane(int i) const {
        RayHit h;
        h.t = t[i], h.geom_id = geom_id[i], h.prim_id = prim_id[i], h.u = u[i], h.v = v[i];
        return h;
    }
    bool hit(int i) const { return geom_id[i] != ~0u; }
};

class EmbreeScene {
public:
    EmbreeScene();
    ~EmbreeScene();
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;
    /// Exchange the built scenes (a parameter update that moved geometry, scene/scene_update.cpp).
    void swap(EmbreeScene& other) noexcept { m_impl.swap(other.m_impl); }

    /// Add a mesh (its buffers are copied into Embree). Returns the geometry id, dense from 0.
    uint32_t add_mesh(const TriangleMesh& mesh);
    /// Add an analytic sphere. Returns the geometry id.
    uint32_t add_sphere(const Point3f& center, float radius);
    void commit();
    /// Whether the committed scene is traced without Embree: a small scene (a few triangles and
    /// spheres; direct_trace::worth_tracing_directly), every ray tested against every primitive,
    /// spheres by the same test as Embree's callback, triangles by direct_trace's own.
    bool traced_directly() const;
    /// Allow the direct trace of small scenes (the default, unless the environment variable
    /// PELLUCID_TRACE is `embree`) or not: Embree then traces every scene. Takes effect at once.
    void set_direct_tracing(bool allow);

    /// Closest hit in (0, ray.tmax]. Thread-safe after commit().
    bool intersect(const Ray& ray, RayHit& hit) const;
    /// Any hit in (0, ray.tmax].
    bool occluded(const Ray& ray) const;

    /// The most rays per packet of intersect_packet/occluded_lanes (Embree's widest, rtcIntersect16).
    /// Up to 8 rays are traced with Embree's 8-wide calls: the packets of the 8- and 4-lane kernels
    /// (AVX2, SSE4.2), for which an AVX2 build of Embree would otherwise convert a 16-wide packet
    /// into two 8-wide ones (bench/README.md measures it).
    static constexpr int kPacketSize = 16;
    /// intersect() for n ≤ kPacketSize rays at once, traced as one packet: Embree tests a BVH node
    /// against all of them in SIMD, which amortises the traversal of incoherent rays too. The rays
    /// are arrays of n floats, soa = origin x, y, z, direction x, y, z, tmax (occluded_lanes'
    /// layout); rays where valid[i] is false are not traced. Lane i of hits gets what intersect()
    /// gives ray i (t, ids, barycentrics; geom_id ~0u: no hit).
    void intersect_lanes(int n, const float* const soa[7], const bool* valid, HitLanes& hits) const;
    /// occluded() for n ≤ kPacketSize rays at once, given as arrays of n floats, soa = origin x, y,
    /// z, direction x, y, z, tmax; rays where valid[i] is false are not traced (occluded[i] false).
    void occluded_lanes(int n, const float* const soa[7], const bool* valid, bool* occluded) const;
    /// The instruction-set variants of the code around intersect_lanes' and occluded_lanes' Embree
    /// calls (the packets' filling and the results' copying; the same results either way): the
    /// baseline, and AVX2 on x86-64 CPUs that have it. A scene uses the last this CPU runs; tests
    /// choose each (an unavailable one is an Error).
    enum class PacketVariant { Baseline, AVX2 };
    static std::vector<PacketVariant> packet_variants();
    void set_packet_variant(PacketVariant v);


private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};
}  // namespace pellucid
