// Embree hit distances, ids and normals on hand-built meshes and spheres.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include "pellucid/geometry/embree_scene.h"
#include "pellucid/scene/build.h"
#include "pellucid/scene/json_io.h"

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
