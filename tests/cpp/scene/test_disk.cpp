// The `disk` shape: Mitsuba's unit disk (z = 0, normal +z) as an area-preserving triangle fan.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>

#include "pellucid/api.h"
#include "pellucid/scene/json_io.h"
#include "pellucid/scene/mitsuba_xml.h"
#include "pellucid/scene/registry.h"

using namespace pellucid;

namespace {
ShapeGeometry build(const std::string& json) {
    Node n = parse_json(json, "test");
    Properties p(n, "test", "shapes[0]");
    p.type();
    ShapeGeometry g = shape_registry().at("disk")(p, BuildContext{"test", "."});
    p.check_unqueried();
    return g;
}

double total_area(const TriangleMesh& m) {
    double a = 0.0;
    for (size_t t = 0; t < m.triangle_count(); ++t) a += m.triangle_area(t);
    return a;
}

Vec3f face_normal(const TriangleMesh& m, size_t t) {
    Vec3f a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]],
          c = m.positions[m.indices[3 * t + 2]];
    return normalize(cross(b - a, c - a));
}
}  // namespace

TEST(DiskShape, AreaIsExactlyPiAndTheRimHugsTheCircle) {
    ShapeGeometry g = build(R"({"type": "disk"})");
    ASSERT_FALSE(g.is_sphere);
    const TriangleMesh& m = g.mesh;
    ASSERT_EQ(m.triangle_count(), 128u);
    // The fan's radius is chosen so that its area is π (float rounding only).
    EXPECT_NEAR(total_area(m), 3.14159265358979, 2e-5);
    // Every vertex lies in z = 0 within the circumscribed/inscribed radii of the 128-gon.
    const double R = std::sqrt(2.0 * 3.14159265358979 / (128.0 * std::sin(2.0 * 3.14159265358979 / 128.0)));
    for (const Point3f& p : m.positions) {
        EXPECT_EQ(p.z, 0.f);
        double r = std::hypot(p.x, p.y);
        EXPECT_TRUE(r < 1e-7 || std::fabs(r - R) < 1e-6) << r;
    }
    EXPECT_GT(R, 1.0);
    EXPECT_LT(R * std::cos(3.14159265358979 / 128.0), 1.0);  // the edge midpoints lie inside the unit circle
}

TEST(DiskShape, NormalsFaceUpOrDownWithFlipNormals) {
    for (bool flip : {false, true}) {
        ShapeGeometry g = build(flip ? R"({"type": "disk", "flip_normals": true})" : R"({"type": "disk"})");
        const float want = flip ? -1.f : 1.f;
        for (size_t t = 0; t < g.mesh.triangle_count(); ++t) EXPECT_NEAR(face_normal(g.mesh, t).z, want, 1e-6f);
        for (const Normal3f& n : g.mesh.normals) EXPECT_EQ(n.z, want);
    }
}

TEST(DiskShape, UvIsRadiusAndAngleAsInMitsuba) {
    ShapeGeometry g = build(R"({"type": "disk"})");
    const TriangleMesh& m = g.mesh;
    ASSERT_EQ(m.uvs.size(), m.positions.size());
    for (size_t i = 0; i < m.positions.size(); ++i) {
        const Point3f& p = m.positions[i];
        if (std::hypot(p.x, p.y) < 1e-7) {
            EXPECT_EQ(m.uvs[i].x, 0.f);  // the centre: r = 0
            continue;
        }
        EXPECT_EQ(m.uvs[i].x, 1.f);
        float phi = std::atan2(p.y, p.x);
        if (phi < 0.f) phi += 2.f * 3.14159265f;
        float v = m.uvs[i].y;
        // The seam vertex repeats φ = 0 with v = 1.
        EXPECT_TRUE(std::fabs(v - phi / (2.f * 3.14159265f)) < 1e-5f || (v == 1.f && std::fabs(phi) < 1e-5f)) << v;
    }
}

TEST(DiskShape, BuildsFromJsonAndMitsubaXmlWithTransforms) {
    SceneDesc d;
    d.source = "scene.json";
    d.root = parse_json(R"({"shapes": [{"type": "disk", "to_world": [{"scale": 2}, {"translate": [0, 0, 1]}],
                                        "emitter": {"type": "area", "radiance": 1}}]})", "scene.json");
    auto scene = load_desc(d);
    ASSERT_EQ(scene->meshes.size(), 1u);
    EXPECT_NEAR(total_area(scene->meshes[0]), 4.0 * 3.14159265358979, 1e-4);
    for (const Point3f& p : scene->meshes[0].positions) EXPECT_NEAR(p.z, 1.f, 1e-6f);
    SceneDesc x = parse_mitsuba_xml(R"(<scene version="3.0.0"><shape type="disk">
        <boolean name="flip_normals" value="true"/><transform name="to_world"><scale value="0.5"/></transform>
        </shape></scene>)", "scene.xml", ".", false);
    auto xs = load_desc(x);
    ASSERT_EQ(xs->meshes.size(), 1u);
    EXPECT_NEAR(total_area(xs->meshes[0]), 0.25 * 3.14159265358979, 1e-5);
    EXPECT_NEAR(face_normal(xs->meshes[0], 0).z, -1.f, 1e-6f);
}
