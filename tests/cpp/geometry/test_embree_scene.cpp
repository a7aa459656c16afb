// Embree hit distances, ids and normals on hand-built meshes and spheres.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "pellucid/geometry/direct_trace.h"
#include "pellucid/geometry/embree_scene.h"
#include "pellucid/scene/build.h"
#include "pellucid/scene/json_io.h"
#include "pellucid/util/error.h"

using namespace pellucid;

TEST(EmbreeScene, TriangleAndSphereHits) {
    EmbreeScene s;
    TriangleMesh quad = TriangleMesh::rectangle();  // z = 0, normal +z
    quad.transform(Transform::translate(Vec3f(0, 0, -2)));
    uint32_t q = s.add_mesh(quad);
    uint32_t sp = s.add_sphere(Point3f(3, 0, 0), 0.5f);
    s.commit();
    EXPECT_EQ(q, 0u);
    EXPECT_EQ(sp, 1u);

    RayHit h;
    ASSERT_TRUE(s.intersect(Ray{Point3f(0.2f, 0.1f, 5.f), Vec3f(0, 0, -1)}, h));
    EXPECT_EQ(h.geom_id, q);
    EXPECT_NEAR(h.t, 7.f, 1e-5f);
    EXPECT_GT(normalize(h.ng).z, 0.999f);

    RayHit h2;
    ASSERT_TRUE(s.intersect(Ray{Point3f(0, 0, 0), Vec3f(1, 0, 0)}, h2));
    EXPECT_EQ(h2.geom_id, sp);
    EXPECT_NEAR(h2.t, 2.5f, 1e-4f);
    EXPECT_LT(normalize(h2.ng).x, -0.999f);

    // From inside the sphere the far side is hit.
    RayHit h3;
    ASSERT_TRUE(s.intersect(Ray{Point3f(3, 0, 0), Vec3f(0, 1, 0)}, h3));
    EXPECT_EQ(h3.geom_id, sp);
    EXPECT_NEAR(h3.t, 0.5f, 1e-4f);

    // Misses, and tmax is respected; occluded agrees with intersect.
    RayHit h4;
    EXPECT_FALSE(s.intersect(Ray{Point3f(0, 0, 5), Vec3f(0, 1, 0)}, h4));
    EXPECT_FALSE(s.intersect(Ray{Point3f(0, 0, 5), Vec3f(0, 0, -1), 6.9f}, h4));
    EXPECT_TRUE(s.occluded(Ray{Point3f(0, 0, 5), Vec3f(0, 0, -1), 7.1f}));
    EXPECT_FALSE(s.occluded(Ray{Point3f(0, 0, 5), Vec3f(0, 0, -1), 6.9f}));
    EXPECT_FALSE(s.occluded(Ray{Point3f(0, 0, 5), Vec3f(0, 1, 0)}));
}

TEST(EmbreeScene, SurfaceInteractionAndSpawnedRays) {
    SceneDesc d;
    d.root = parse_json(R"({"shapes": [
        {"type": "sphere", "center": [0, 0, 0], "radius": 1000},
        {"type": "mesh", "positions": [1e4,-3000,-1e4, 1e4,-3000,1e4, -1e4,-3000,0], "indices": [0,1,2],
         "normals": [0,1,0, 0,1,0, 0,1,0], "uvs": [0,0, 1,0, 0,1]}]})", "t");
    auto scene = build_scene(d);
    // Hit the far-away sphere and the large triangle; a spawned ray must not re-hit its surface,
    // whatever the magnitude of the position.
    SurfaceInteraction si;
    ASSERT_TRUE(scene->intersect(Ray{Point3f(0, 0, 2000), normalize(Vec3f(0.3f, 0.1f, -1))}, si));
    EXPECT_EQ(si.shape_id, 0u);
    EXPECT_NEAR(length(si.p), 1000.f, 1e-2f);
    EXPECT_GT(dot(si.ng, normalize(si.p)), 0.9999f);
    EXPECT_NEAR(dot(si.shading.n, si.ng), 1.f, 1e-5f);
    EXPECT_NEAR(dot(si.dpdu, si.shading.n), 0.f, 1e-2f * length(si.dpdu));
    SurfaceInteraction si2;
    EXPECT_FALSE(scene->intersect(si.spawn_ray(si.ng), si2)) << "an outgoing ray re-hit its own sphere";

    ASSERT_TRUE(scene->intersect(Ray{Point3f(1234.5f, -2950.f, 17.25f), Vec3f(0, -1, 0)}, si));
    EXPECT_EQ(si.shape_id, 1u);
    EXPECT_NEAR(si.t, 50.f, 1e-3f);
    EXPECT_EQ(si.prim_id, 0u);
    for (int i = 0; i < 100; ++i) {
        Vec3f d2 = normalize(Vec3f(std::cos(i * 0.7f), 0.05f + 0.01f * i, std::sin(i * 0.7f)));
        Ray r = si.spawn_ray(d2);
        r.tmax = 100.f;  // only the neighbourhood of the surface matters here
        EXPECT_FALSE(scene->occluded(r)) << "self-intersection for direction " << i;
    }
}

// A sphere's t is the root of |o + t·d − c|² = r² rounded once from double precision, on single
// rays and packets alike; spawned rays on either side of its surface never re-hit it at the spawn
// point. 512 random rays aimed near a sphere far from the origin (where float rounding of the
// geometry is coarse).
TEST(EmbreeScene, SphereRootsAreExactAndAgreeAcrossPacketsAndSingleRays) {
    SceneDesc d;
    d.root = parse_json(R"({"shapes": [{"type": "sphere", "center": [300, -20, 7], "radius": 2.5}]})", "t");
    auto scene = build_scene(d);
    const EmbreeScene& accel = scene->accel;
    uint64_t state = 12345;
    auto next = [&] {  // a fixed LCG: the test's rays are the same on every run
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return float(state >> 40) / float(1 << 24);
    };
    // The first root in (0, ∞) of the ray's sphere equation in long double, or −1 for none.
    auto exact_root = [](const Ray& r) -> float {
        const long double ox = (long double)r.o.x - 300, oy = (long double)r.o.y + 20, oz = (long double)r.o.z - 7;
        const long double b = ox * r.d.x + oy * r.d.y + oz * r.d.z;
        const long double a = (long double)r.d.x * r.d.x + (long double)r.d.y * r.d.y + (long double)r.d.z * r.d.z;
        const long double c = ox * ox + oy * oy + oz * oz - 6.25L, disc = b * b - a * c;
        if (disc < 0) return -1.f;
        const long double t0 = (-b - std::sqrt(disc)) / a, t1 = (-b + std::sqrt(disc)) / a;
        return float(t0 > 0 ? t0 : t1 > 0 ? t1 : -1.L);
    };
    auto within_an_ulp = [](float t, float exact) { return std::fabs(t - exact) <= std::nextafter(exact, kInfinity) - exact; };
    constexpr int kRays = 512;
    std::vector<Ray> rays(kRays);
    for (Ray& r : rays) {
        r.o = Point3f(300.f + 20.f * (next() - 0.5f), -20.f + 20.f * (next() - 0.5f), 40.f);
        const Point3f target(300.f + 6.f * (next() - 0.5f), -20.f + 6.f * (next() - 0.5f), 7.f);
        r.d = normalize(target - r.o);
        r.tmax = kInfinity;
    }
    int hits = 0;
    for (int base = 0; base < kRays; base += EmbreeScene::kPacketSize) {
        float soa[7][EmbreeScene::kPacketSize];
        bool valid[EmbreeScene::kPacketSize];
        for (int i = 0; i < EmbreeScene::kPacketSize; ++i) {
            const Ray& r = rays[size_t(base + i)];
            const float v[7] = {r.o.x, r.o.y, r.o.z, r.d.x, r.d.y, r.d.z, r.tmax};
            for (int k = 0; k < 7; ++k) soa[k][i] = v[k];
            valid[i] = true;
        }
        const float* const p[7] = {soa[0], soa[1], soa[2], soa[3], soa[4], soa[5], soa[6]};
        HitLanes hl;
        accel.intersect_lanes(EmbreeScene::kPacketSize, p, valid, hl);
        RayHit packet[EmbreeScene::kPacketSize];
        for (int i = 0; i < EmbreeScene::kPacketSize; ++i) packet[i] = hl.lane(i);
        for (int i = 0; i < EmbreeScene::kPacketSize; ++i) {
            const Ray& r = rays[size_t(base + i)];
            RayHit single;
            const bool hit = accel.intersect(r, single);
            ASSERT_EQ(hit, packet[i].hit()) << "ray " << base + i;
            const float exact = exact_root(r);
            EXPECT_EQ(hit, exact > 0.f) << "ray " << base + i;
            if (!hit) continue;
            ++hits;
            EXPECT_EQ(single.t, packet[i].t) << "ray " << base + i;
            EXPECT_TRUE(within_an_ulp(single.t, exact)) << "ray " << base + i << ": " << single.t << " vs " << exact;
            // Spawned rays: reflected (outwards) misses; refracted straight on (inwards) hits the
            // far side at its own exact root.
            SurfaceInteraction si;
            ASSERT_TRUE(scene->intersect(r, si));
            const Vec3f out = normalize(r.d - 2.f * dot(r.d, si.ng) * si.ng);
            SurfaceInteraction si2;
            EXPECT_FALSE(scene->intersect(si.spawn_ray(out), si2)) << "reflected ray " << base + i << " re-hit";
            const Ray in = si.spawn_ray(r.d);
            ASSERT_TRUE(scene->intersect(in, si2)) << "ray " << base + i << " did not reach the far side";
            EXPECT_TRUE(within_an_ulp(si2.t, exact_root(in))) << "ray " << base + i;
            EXPECT_GT(si2.t, 1e-2f) << "ray " << base + i << " re-hit the near side";
        }
    }
    EXPECT_GT(hits, kRays / 4);  // the grid aims about half of the rays at the sphere
    EXPECT_LT(hits, kRays);
}

namespace {
/// 64 rectangles ([−1, 1]² each) in an 8 x 8 grid at z = −2, their centres 2.5 apart: enough
/// triangles for a BVH with inner nodes, and too many for the direct trace.
/// A small rectangle far from everything else, which no test ray reaches: a scene of spheres with
/// it is traced directly (one of spheres alone goes to Embree). Returns the mesh it adds.
TriangleMesh add_far_rectangle(EmbreeScene& s) {
    TriangleMesh m = TriangleMesh::rectangle();
    m.transform(Transform::translate(Vec3f(0, -1e5f, 0)) * Transform::scale(Vec3f(0.01f, 0.01f, 0.01f)));
    s.add_mesh(m);
    return m;
}
void add_quad_grid(EmbreeScene& s) {
    for (int k = 0; k < 64; ++k) {
        TriangleMesh quad = TriangleMesh::rectangle();
        quad.transform(Transform::translate(Vec3f(float(k % 8) * 2.5f, float(k / 8) * 2.5f, -2.f)));
        s.add_mesh(quad);
    }
}
}  // namespace

// Lanes left out of a shadow packet may hold anything, NaN included: they are ignored, and the others
// are answered, by the 16-wide and the 8-wide packet calls, with each instruction-set variant of the
// packets' filling (EmbreeScene::packet_variants).
TEST(EmbreeScene, OccludedLanesIgnoreGarbageInMaskedLanes) {
    EmbreeScene s;
    add_quad_grid(s);
    s.commit();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const int n = EmbreeScene::kPacketSize;
    float soa[7][16];
    bool valid[16], blocked[16];
    for (int i = 0; i < 16; ++i) {
        valid[i] = i % 3 == 2;
        const float x = float(i % 8) * 2.5f + 0.1f, y = float(i / 8) * 2.5f + 0.1f;
        const float v[7] = {x, y, 5.f, 0.f, 0.f, i % 2 ? -1.f : 1.f, std::numeric_limits<float>::infinity()};
        for (int k = 0; k < 7; ++k) soa[k][i] = valid[i] ? v[k] : (k == 6 ? 0.9f : nan);
    }
    const float* const p[7] = {soa[0], soa[1], soa[2], soa[3], soa[4], soa[5], soa[6]};
    for (const EmbreeScene::PacketVariant variant : EmbreeScene::packet_variants()) {
        s.set_packet_variant(variant);
        for (int m : {n, 8, 5}) {  // Embree's 16-wide call, and its 8-wide one (up to 8 rays)
            s.occluded_lanes(m, p, valid, blocked);
            for (int i = 0; i < m; ++i)
                EXPECT_EQ(blocked[i], valid[i] && i % 2 == 1) << m << " rays, lane " << i << ", variant " << int(variant);
        }
    }
    EXPECT_THROW(s.set_packet_variant(EmbreeScene::PacketVariant(99)), Error);
}

// intersect_lanes likewise: lanes left out (NaN included) report no hit, the others the hit a single
// ray finds (t, ids, barycentrics), by the 16-wide and the 8-wide packet calls and each variant.
TEST(EmbreeScene, IntersectLanesAgreeWithSingleRaysAndIgnoreMaskedLanes) {
    EmbreeScene s;
    add_quad_grid(s);
    s.commit();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    float soa[7][16];
    bool valid[16];
    for (int i = 0; i < 16; ++i) {
        valid[i] = i % 3 != 1;
        const float x = float(i % 8) * 2.5f + 0.1f + 0.03f * float(i), y = float(i / 8) * 2.5f + 0.2f;
        // Odd lanes point away from the quads (a miss), even lanes at them.
        const float v[7] = {x, y, 5.f, 0.f, 0.f, i % 2 ? 1.f : -1.f, std::numeric_limits<float>::infinity()};
        for (int k = 0; k < 7; ++k) soa[k][i] = valid[i] ? v[k] : nan;
    }
    const float* const p[7] = {soa[0], soa[1], soa[2], soa[3], soa[4], soa[5], soa[6]};
    for (const EmbreeScene::PacketVariant variant : EmbreeScene::packet_variants())
    for (int m : {16, 8, 5}) {
        s.set_packet_variant(variant);
        HitLanes hl;
        s.intersect_lanes(m, p, valid, hl);
        for (int i = 0; i < m; ++i) {
            if (!valid[i]) {
                EXPECT_FALSE(hl.hit(i)) << m << " rays, lane " << i << ", variant " << int(variant);
                continue;
            }
            RayHit single;
            const bool hit = s.intersect(Ray{Vec3f(soa[0][i], soa[1][i], soa[2][i]), Vec3f(soa[3][i], soa[4][i], soa[5][i]),
                                             soa[6][i]},
                                         single);
            EXPECT_EQ(hit, i % 2 == 0) << m << " rays, lane " << i;
            ASSERT_EQ(hl.hit(i), hit) << m << " rays, lane " << i;
            if (!hit) continue;
            EXPECT_EQ(hl.t[i], single.t);
            EXPECT_EQ(hl.geom_id[i], single.geom_id);
            EXPECT_EQ(hl.prim_id[i], single.prim_id);
            EXPECT_EQ(hl.u[i], single.u);
            EXPECT_EQ(hl.v[i], single.v);
        }
    }
}

// A small scene is traced without Embree (traced_directly), every ray against every triangle and
// sphere. It must give what Embree gives on the same scene (set_direct_tracing(false)): on spheres
// the same hits bit for bit (the same test: t, ids, the single ray's normal) and the same occlusion;
// on triangles, which direct_trace tests by its own formula, the same triangle, with t, u and v to
// float rounding. Rays from outside and inside the spheres, with finite tmax, and with masked lanes
// holding NaN; one, two and four spheres, alone and with two or four walls (rectangles, 2 triangles
// each) around them. Rays aimed at a wall aim at its inner part, so no ray passes within float
// rounding of a triangle's edge, where the two tests may differ.
// The direct trace's float pre-test never drops a hit that the double-precision sphere test finds:
// rays passing within a few ulps of tangent to spheres near and far from the origin (where float
// rounding of c − o is largest), in clusters of several, give the hits Embree's callbacks give.
TEST(EmbreeScene, DirectTracePreTestKeepsGrazingHits) {
    for (const float offset : {0.f, 100.f, 1e4f})
    for (const float radius : {1e-3f, 1.f, 50.f}) {
        const std::string what = "offset " + std::to_string(offset) + ", radius " + std::to_string(radius);
        EmbreeScene direct, embree;
        std::vector<Point3f> centres;
        for (int k = 0; k < 12; ++k) {  // a row of 12 spheres: two clusters
            centres.emplace_back(offset + 3.f * radius * float(k), offset * 0.5f, -offset);
            direct.add_sphere(centres.back(), radius), embree.add_sphere(centres.back(), radius);
        }
        add_far_rectangle(direct), add_far_rectangle(embree);
        embree.set_direct_tracing(false);
        direct.commit(), embree.commit();
        ASSERT_TRUE(direct.traced_directly()) << what;
        uint64_t state = 99;
        auto next = [&] {
            state = state * 6364136223846793005ull + 1442695040888963407ull;
            return float(state >> 40) / float(1 << 24);
        };
        int hits = 0, misses = 0;
        for (int packet = 0; packet < 256; ++packet) {
            float soa[7][8];
            bool valid[8];
            for (int i = 0; i < 8; ++i) {
                // Aim at a point on a sphere's silhouette as seen from the origin, the distance
                // from the centre 1 ± a few float ulps of the radius.
                const Point3f& c = centres[size_t(std::min(11, int(next() * 12.f)))];
                const Vec3f o = Vec3f(c) + Vec3f(20.f * radius * (next() - 0.5f), 20.f * radius * (next() - 0.5f),
                                                 10.f * radius + 5.f * radius * next());
                const Vec3f to_c = Vec3f(c) - o;
                Vec3f side = normalize(cross(to_c, Vec3f(next() - 0.5f, next() - 0.5f, next() - 0.5f)));
                // The line at distance R = r·scale from the centre: d at angle asin(R/|c − o|) from c − o.
                const double scale = 1.0 + double(int(next() * 9.f) - 4) * 1e-7, dist = double(length(to_c));
                const double sin_a = double(radius) * scale / dist, cos_a = std::sqrt(1.0 - sin_a * sin_a);
                const Vec3f d = normalize(to_c * float(cos_a) + side * float(dist * sin_a));
                const float v[7] = {o.x, o.y, o.z, d.x, d.y, d.z, kInfinity};
                for (int k = 0; k < 7; ++k) soa[k][i] = v[k];
                valid[i] = true;
            }
            const float* const p[7] = {soa[0], soa[1], soa[2], soa[3], soa[4], soa[5], soa[6]};
            HitLanes a, b;
            direct.intersect_lanes(8, p, valid, a);
            embree.intersect_lanes(8, p, valid, b);
            bool ba[8], bb[8];
            direct.occluded_lanes(8, p, valid, ba);
            embree.occluded_lanes(8, p, valid, bb);
            for (int i = 0; i < 8; ++i) {
                const std::string at = what + ", packet " + std::to_string(packet) + ", lane " + std::to_string(i);
                ASSERT_EQ(a.hit(i), b.hit(i)) << at;
                EXPECT_EQ(ba[i], bb[i]) << at;
                if (a.hit(i)) {
                    EXPECT_EQ(a.t[i], b.t[i]) << at;
                    EXPECT_EQ(a.geom_id[i], b.geom_id[i]) << at;
                }
                hits += a.hit(i), misses += !a.hit(i);
            }
        }
        // Both outcomes occur: the rays do straddle the silhouettes.
        EXPECT_GT(hits, 256) << what;
        EXPECT_GT(misses, 256) << what;
    }
}

TEST(EmbreeScene, DirectTraceGivesEmbreesHits) {
    // Up to four spheres of their own sizes, or a grid of many (which the direct trace sorts into
    // clusters, each culled as a whole by a float pre-test).
    const Point3f four[4] = {Point3f(0, 0, 0), Point3f(1.2f, 0.3f, -0.4f), Point3f(-2, 1, 0.5f), Point3f(0.4f, -1.5f, 1)};
    const float four_radii[4] = {1.f, 0.7f, 0.5f, 1.3f};
    // Walls: a rectangle of half-size 5 facing the origin at distance 6 along ±z, then ±x; then a
    // tilted cube above the spheres (its faces quads whose triangles are indexed unlike a
    // rectangle's) and, below them, a rectangle with one corner lifted off its plane (two triangles
    // that make no quad).
    const Transform walls[6] = {Transform::translate(Vec3f(0, 0, -6)) * Transform::scale(Vec3f(5, 5, 1)),
                                Transform::translate(Vec3f(0, 0, 6)) * Transform::scale(Vec3f(5, 5, 1)),
                                Transform::translate(Vec3f(-6, 0, 0)) * Transform::rotate(Vec3f(0, 1, 0), 90.f) *
                                    Transform::scale(Vec3f(5, 5, 1)),
                                Transform::translate(Vec3f(6, 0, 0)) * Transform::rotate(Vec3f(0, 1, 0), -90.f) *
                                    Transform::scale(Vec3f(5, 5, 1)),
                                Transform::translate(Vec3f(0, 4.5f, 0)) * Transform::rotate(normalize(Vec3f(1, 1, 0)), 30.f) *
                                    Transform::scale(Vec3f(1.2f, 1.2f, 1.2f)),
                                Transform::translate(Vec3f(0, -4.5f, 0)) * Transform::rotate(Vec3f(1, 0, 0), 90.f) *
                                    Transform::scale(Vec3f(3, 3, 1))};
    // Every instruction-set variant of the direct trace this CPU runs.
    for (const direct_trace::Variant variant : direct_trace::available_variants())
    for (const int spheres : {1, 2, 4, 36, 60})
    for (const int n_walls : {0, 2, 4, 6}) {
        if (spheres == 60 && n_walls == 6) continue;  // (more than the direct trace takes)
        direct_trace::set_variant(variant);
        const std::string what = std::to_string(spheres) + " spheres, " + std::to_string(n_walls) + " walls, variant " +
                                 std::to_string(int(variant));
        std::vector<Point3f> centres;
        std::vector<float> radii;
        for (int k = 0; k < spheres; ++k) {
            if (spheres <= 4) {
                centres.push_back(four[k]), radii.push_back(four_radii[k]);
                continue;
            }
            // A grid of n × n across [−3, 3]² in x and z, the heights and sizes varied.
            const int n = spheres == 36 ? 6 : 8;
            const float step = 6.f / float(n), x = -3.f + step * (float(k % n) + 0.5f), z = -3.f + step * (float(k / n) + 0.5f);
            centres.emplace_back(x, 0.3f * float(k % 3) - 0.3f, z);
            radii.push_back(step * (0.3f + 0.05f * float(k % 4)));
        }
        EmbreeScene direct, embree;
        std::vector<TriangleMesh> meshes;
        for (int k = 0; k < spheres; ++k) {
            EXPECT_EQ(direct.add_sphere(centres[size_t(k)], radii[size_t(k)]), uint32_t(k));
            EXPECT_EQ(embree.add_sphere(centres[size_t(k)], radii[size_t(k)]), uint32_t(k));
        }
        for (int w = 0; w < n_walls; ++w) {
            TriangleMesh m = w == 4 ? TriangleMesh::cube() : TriangleMesh::rectangle();
            if (w == 5) m.positions[3].z += 0.7f;
            m.transform(walls[w]);
            direct.add_mesh(m), embree.add_mesh(m);
            meshes.push_back(m);
        }
        if (n_walls == 0) add_far_rectangle(direct), meshes.push_back(add_far_rectangle(embree));
        embree.set_direct_tracing(false);
        direct.commit(), embree.commit();
        ASSERT_TRUE(direct.traced_directly()) << what;
        ASSERT_FALSE(embree.traced_directly()) << what;
        uint64_t state = 777 + uint64_t(spheres) * 31 + uint64_t(n_walls);
        auto next = [&] {  // a fixed LCG: the same rays on every run
            state = state * 6364136223846793005ull + 1442695040888963407ull;
            return float(state >> 40) / float(1 << 24);
        };
        const float nan = std::numeric_limits<float>::quiet_NaN();
        int hits = 0, wall_hits = 0, blocked_count = 0;
        for (int packet = 0; packet < 64; ++packet) {
            float soa[7][16];
            bool valid[16];
            for (int i = 0; i < 16; ++i) {
                // Origins in a box around the spheres (some inside one); each ray aimed at a point
                // near one of the spheres (about half of them hit) or, every third ray where there
                // are walls, at the inner part of a wall; every fourth ray a short one.
                const Vec3f o(6.f * next() - 3.f, 6.f * next() - 3.f, 6.f * next() - 3.f);
                Vec3f aim;
                if (n_walls > 0 && i % 3 == 0) {
                    const int w = std::min(n_walls - 1, int(next() * float(n_walls)));
                    aim = walls[w].point(Vec3f(1.8f * next() - 0.9f, 1.8f * next() - 0.9f, 0.f));
                } else {
                    const int k = std::min(spheres - 1, int(next() * float(spheres)));
                    aim = Vec3f(centres[size_t(k)]) +
                          1.5f * radii[size_t(k)] * Vec3f(2.f * next() - 1.f, 2.f * next() - 1.f, 2.f * next() - 1.f);
                }
                const Vec3f d = normalize(aim - o);
                const float tmax = i % 4 == 3 ? 2.f * next() : kInfinity;
                valid[i] = (packet + i) % 7 != 3;
                const float v[7] = {o.x, o.y, o.z, d.x, d.y, d.z, tmax};
                for (int k = 0; k < 7; ++k) soa[k][i] = valid[i] ? v[k] : nan;
            }
            const float* const p[7] = {soa[0], soa[1], soa[2], soa[3], soa[4], soa[5], soa[6]};
            for (int m : {16, 8, 5, 1}) {
                HitLanes a, b;
                direct.intersect_lanes(m, p, valid, a);
                embree.intersect_lanes(m, p, valid, b);
                bool ba[16], bb[16];
                direct.occluded_lanes(m, p, valid, ba);
                embree.occluded_lanes(m, p, valid, bb);
                for (int i = 0; i < m; ++i) {
                    const std::string at = what + ", packet " + std::to_string(packet) + " of " + std::to_string(m) +
                                           ", lane " + std::to_string(i);
                    ASSERT_EQ(a.hit(i), b.hit(i)) << at;
                    EXPECT_EQ(ba[i], bb[i]) << at;
                    if (!valid[i]) {
                        EXPECT_FALSE(a.hit(i)) << at;
                        EXPECT_FALSE(ba[i]) << at;
                        continue;
                    }
                    blocked_count += m == 16 && ba[i];
                    EXPECT_EQ(ba[i], a.hit(i)) << at;  // a hit in (0, tmax] blocks
                    if (!a.hit(i)) continue;
                    hits += m == 16;  // (each of the 1024 rays counted once)
                    EXPECT_EQ(a.geom_id[i], b.geom_id[i]) << at;
                    EXPECT_EQ(a.prim_id[i], b.prim_id[i]) << at;
                    const Ray r{Vec3f(soa[0][i], soa[1][i], soa[2][i]), Vec3f(soa[3][i], soa[4][i], soa[5][i]), soa[6][i]};
                    RayHit sa, sb;
                    ASSERT_TRUE(direct.intersect(r, sa)) << at;
                    ASSERT_TRUE(embree.intersect(r, sb)) << at;
                    EXPECT_EQ(sa.geom_id, sb.geom_id) << at;
                    EXPECT_EQ(sa.prim_id, sb.prim_id) << at;
                    EXPECT_EQ(sa.t, a.t[i]) << at;
                    EXPECT_EQ(direct.occluded(r), embree.occluded(r)) << at;
                    if (a.geom_id[i] < uint32_t(spheres)) {  // a sphere: bit for bit
                        EXPECT_EQ(a.t[i], b.t[i]) << at;
                        EXPECT_EQ(sa.t, sb.t) << at;
                        EXPECT_EQ(sa.ng.x, sb.ng.x) << at;
                        EXPECT_EQ(sa.ng.y, sb.ng.y) << at;
                        EXPECT_EQ(sa.ng.z, sb.ng.z) << at;
                        EXPECT_EQ(a.u[i], 0.f) << at;
                        EXPECT_EQ(a.v[i], 0.f) << at;
                        continue;
                    }
                    wall_hits += m == 16;
                    // A triangle: t to a few float ulps of the distance, (u, v) to a few of 1, the
                    // same normal direction.
                    EXPECT_NEAR(a.t[i], b.t[i], 4e-6f * b.t[i]) << at;
                    EXPECT_NEAR(a.u[i], b.u[i], 4e-6f) << at;
                    EXPECT_NEAR(a.v[i], b.v[i], 4e-6f) << at;
                    EXPECT_GT(dot(normalize(sa.ng), normalize(sb.ng)), 0.99999f) << at;
                    // The hit point from (u, v) is the hit point from t.
                    const TriangleMesh& mesh = meshes[size_t(a.geom_id[i]) - size_t(spheres)];
                    const uint32_t* tri = &mesh.indices[3 * size_t(a.prim_id[i])];
                    const Vec3f p0(mesh.positions[tri[0]]), p1(mesh.positions[tri[1]]), p2(mesh.positions[tri[2]]);
                    const Vec3f from_uv = (1.f - a.u[i] - a.v[i]) * p0 + a.u[i] * p1 + a.v[i] * p2;
                    EXPECT_LT(length(from_uv - (r.o + a.t[i] * r.d)), 1e-5f * (1.f + a.t[i])) << at;
                }
            }
        }
        EXPECT_GT(hits, 1024 / 4) << what;  // the rays do reach the primitives
        if (n_walls == 0) EXPECT_LT(hits, 1024 * 9 / 10) << what;  // and do miss them
        else EXPECT_GT(wall_hits, 1024 / 8) << what;
        EXPECT_GT(blocked_count, 1024 / 4) << what;
    }
    direct_trace::set_variant(direct_trace::available_variants().back());
    // A scene of many primitives goes to Embree, and direct tracing can be switched off and on.
    EmbreeScene big;
    add_quad_grid(big);
    big.commit();
    EXPECT_FALSE(big.traced_directly());
    EmbreeScene many_spheres;  // like bench/suite/many_materials.json: 36 spheres on 2 rectangles
    for (int k = 0; k < 2; ++k) many_spheres.add_mesh(TriangleMesh::rectangle());
    for (int k = 0; k < 36; ++k) many_spheres.add_sphere(Point3f(float(k), 0, 0), 0.4f);
    many_spheres.commit();
    EXPECT_TRUE(many_spheres.traced_directly());
    for (int k = 36; k < 91; ++k) many_spheres.add_sphere(Point3f(float(k), 0, 0), 0.4f);
    many_spheres.commit();  // 2 quads and 91 spheres: more than 20 primitives' worth
    EXPECT_FALSE(many_spheres.traced_directly());
    EXPECT_TRUE(direct_trace::worth_tracing_directly(6, 4));   // bench/suite/veach_mis.json: 6 quads, 4 spheres
    EXPECT_TRUE(direct_trace::worth_tracing_directly(18, 0));  // bench/suite/cornell_lambert.json: 18 quads
    EXPECT_TRUE(direct_trace::worth_tracing_directly(20, 0));
    EXPECT_FALSE(direct_trace::worth_tracing_directly(21, 0));
    EXPECT_TRUE(direct_trace::worth_tracing_directly(1, 95));
    EXPECT_FALSE(direct_trace::worth_tracing_directly(1, 96));
    EXPECT_FALSE(direct_trace::worth_tracing_directly(0, 1));  // spheres alone: Embree
    EXPECT_FALSE(direct_trace::worth_tracing_directly(0, 0));
    EXPECT_TRUE(direct_trace::worth_tracing_directly(16, 20));
    EXPECT_FALSE(direct_trace::worth_tracing_directly(16, 21));
    EmbreeScene one;
    one.add_sphere(Point3f(0, 0, 0), 1.f);
    one.commit();
    EXPECT_FALSE(one.traced_directly());  // a sphere alone
    add_far_rectangle(one);
    one.commit();
    EXPECT_TRUE(one.traced_directly());
    one.set_direct_tracing(false);
    EXPECT_FALSE(one.traced_directly());
    one.set_direct_tracing(true);
    EXPECT_TRUE(one.traced_directly());
}

// The direct trace tests two triangles of a mesh as one quad where they make a parallelogram: a
// rectangle's two, each face of a cube (indexed another way), but not a rectangle bent along its
// diagonal, nor triangles that share only a corner.
TEST(EmbreeScene, DirectTraceMakesQuadsOfParallelograms) {
    auto primitives = [](const TriangleMesh& m, int* quads) {
        std::vector<float> v;
        for (const auto& p : m.positions) v.insert(v.end(), {p.x, p.y, p.z});
        std::vector<direct_trace::TriangleData> out;
        direct_trace::append_mesh(out, v.data(), m.indices.data(), m.triangle_count(), 7);
        *quads = 0;
        for (const auto& d : out) {
            *quads += d.quad;
            EXPECT_EQ(d.geom, 7u);
        }
        return int(out.size());
    };
    int quads = 0;
    TriangleMesh rect = TriangleMesh::rectangle();
    rect.transform(Transform::rotate(normalize(Vec3f(1, 2, 3)), 37.f) * Transform::scale(Vec3f(3, 0.5f, 1)));
    EXPECT_EQ(primitives(rect, &quads), 1);
    EXPECT_EQ(quads, 1);
    TriangleMesh cube = TriangleMesh::cube();
    cube.transform(Transform::translate(Vec3f(10, -3, 2)) * Transform::rotate(normalize(Vec3f(1, 1, 0)), 30.f));
    EXPECT_EQ(primitives(cube, &quads), 6);
    EXPECT_EQ(quads, 6);
    TriangleMesh bent = TriangleMesh::rectangle();
    bent.positions[3].z += 1e-3f;
    EXPECT_EQ(primitives(bent, &quads), 2);
    EXPECT_EQ(quads, 0);
    TriangleMesh fan;  // two triangles sharing one corner
    fan.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
    fan.indices = {0, 1, 2, 0, 3, 4};
    EXPECT_EQ(primitives(fan, &quads), 2);
    EXPECT_EQ(quads, 0);
}

// Each instruction-set variant of the direct trace gives the baseline's bits: packets of 16, 8 and
// 5 rays, their occlusion, and single rays, on quads, triangles and spheres.
TEST(EmbreeScene, DirectTraceVariantsGiveTheSameBits) {
    EmbreeScene s;
    for (int k = 0; k < 12; ++k) s.add_sphere(Point3f(1.5f * float(k % 4) - 2.f, 0.4f * float(k / 4) - 0.3f, 0.5f), 0.45f);
    TriangleMesh floor = TriangleMesh::rectangle(), cube = TriangleMesh::cube(), bent = TriangleMesh::rectangle();
    floor.transform(Transform::translate(Vec3f(0, -1, 0)) * Transform::rotate(Vec3f(1, 0, 0), -90.f) * Transform::scale(Vec3f(4, 4, 1)));
    cube.transform(Transform::translate(Vec3f(0.3f, 1.8f, -0.5f)) * Transform::rotate(normalize(Vec3f(1, 1, 0)), 30.f) * Transform::scale(Vec3f(0.6f, 0.6f, 0.6f)));
    bent.positions[3].z += 0.5f;
    bent.transform(Transform::translate(Vec3f(0, 0, -2)) * Transform::scale(Vec3f(3, 3, 1)));
    s.add_mesh(floor), s.add_mesh(cube), s.add_mesh(bent);
    s.commit();
    ASSERT_TRUE(s.traced_directly());
    const std::vector<direct_trace::Variant> variants = direct_trace::available_variants();
    uint64_t state = 4242;
    auto next = [&] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return float(state >> 40) / float(1 << 24);
    };
    int hits = 0;
    for (int packet = 0; packet < 128; ++packet) {
        float soa[7][16];
        bool valid[16];
        for (int i = 0; i < 16; ++i) {
            const Vec3f o(6.f * next() - 3.f, 4.f * next() - 1.f, 4.f * next() - 1.f);
            const Vec3f d = normalize(Vec3f(2.f * next() - 1.f, 2.f * next() - 1.f, 2.f * next() - 1.f));
            const float v[7] = {o.x, o.y, o.z, d.x, d.y, d.z, i % 4 == 3 ? 3.f * next() : kInfinity};
            for (int k = 0; k < 7; ++k) soa[k][i] = v[k];
            valid[i] = (packet + i) % 5 != 2;
        }
        const float* const p[7] = {soa[0], soa[1], soa[2], soa[3], soa[4], soa[5], soa[6]};
        for (int m : {16, 8, 5}) {
            HitLanes base;
            bool base_blocked[16];
            RayHit base_single[16];
            for (size_t v = 0; v < variants.size(); ++v) {
                direct_trace::set_variant(variants[v]);
                HitLanes h;
                bool blocked[16];
                s.intersect_lanes(m, p, valid, h);
                s.occluded_lanes(m, p, valid, blocked);
                for (int i = 0; i < m; ++i) {
                    const std::string at = "variant " + std::to_string(int(variants[v])) + ", packet " +
                                           std::to_string(packet) + " of " + std::to_string(m) + ", lane " + std::to_string(i);
                    const Ray r{Vec3f(soa[0][i], soa[1][i], soa[2][i]), Vec3f(soa[3][i], soa[4][i], soa[5][i]), soa[6][i]};
                    RayHit single;
                    const bool single_hit = s.intersect(r, single);
                    if (valid[i]) {
                        EXPECT_EQ(single_hit, h.hit(i)) << at;
                        EXPECT_EQ(s.occluded(r), blocked[i]) << at;
                    }
                    if (v == 0) {
                        base_blocked[i] = blocked[i], base_single[i] = single;
                        hits += m == 16 && h.hit(i);
                        continue;
                    }
                    EXPECT_EQ(blocked[i], base_blocked[i]) << at;
                    ASSERT_EQ(h.geom_id[i], base.geom_id[i]) << at;
                    if (!h.hit(i)) continue;
                    EXPECT_EQ(h.prim_id[i], base.prim_id[i]) << at;
                    EXPECT_EQ(std::memcmp(&h.t[i], &base.t[i], 4), 0) << at;
                    EXPECT_EQ(std::memcmp(&h.u[i], &base.u[i], 4), 0) << at;
                    EXPECT_EQ(std::memcmp(&h.v[i], &base.v[i], 4), 0) << at;
                    EXPECT_EQ(std::memcmp(&single.t, &base_single[i].t, 4), 0) << at;
                    EXPECT_EQ(std::memcmp(&single.u, &base_single[i].u, 4), 0) << at;
                    EXPECT_EQ(single.prim_id, base_single[i].prim_id) << at;
                }
                if (v == 0) base = h;
            }
        }
    }
    direct_trace::set_variant(variants.back());
    EXPECT_GT(hits, 128 * 16 / 4);  // the rays do reach the primitives
}
