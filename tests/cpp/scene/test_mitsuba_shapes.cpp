// Built-in shapes as Mitsuba 3 defines them: the cube's per-face uv layout and `flip_normals` on
// every shape, through the Mitsuba XML importer and the JSON builders.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "pellucid/api.h"
#include "pellucid/scene/build.h"
#include "pellucid/scene/mitsuba_xml.h"
#include "support/scene_util.h"
#include "support/temp_dir.h"

using namespace pellucid;
namespace fs = std::filesystem;

namespace {
std::unique_ptr<Scene> from_xml(const std::string& body, const std::string& base = ".") {
    return build_scene(parse_mitsuba_xml("<scene version=\"3.0.0\">\n" + body + "\n</scene>\n", "scene.xml", base, false));
}

SurfaceInteraction hit(const Scene& s, const Point3f& o, const Vec3f& d) {
    SurfaceInteraction si;
    EXPECT_TRUE(s.intersect(Ray{o, d, kInfinity}, si)) << "ray from " << o.x << "," << o.y << "," << o.z;
    return si;
}

void expect_vec(const Vec3f& got, const Vec3f& want, const char* what, float tol = 1e-5f) {
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], want[k], tol) << what << " component " << k;
}
}  // namespace

// Expected values printed by Mitsuba 3.9.1 (scalar_rgb) for the same rays: ray_intersect on
// {"type": "cube"} and its SurfaceInteraction's p, n, uv, dp_du, dp_dv.
TEST(MitsubaShapes, CubeUvAndTangentsMatchMitsubaOnEveryFace) {
    struct Case {
        Point3f o;
        Vec3f d, n;
        Vec2f uv;
        Vec3f dpdu, dpdv;
    };
    const Case cases[6] = {
        {{5, 0.3f, -0.4f}, {-1, 0, 0}, {1, 0, 0}, {0.65f, 0.7f}, {0, 2, 0}, {0, 0, -2}},
        {{-5, 0.3f, -0.4f}, {1, 0, 0}, {-1, 0, 0}, {0.65f, 0.3f}, {0, 2, 0}, {0, 0, 2}},
        {{0.2f, 5, -0.4f}, {0, -1, 0}, {0, 1, 0}, {0.4f, 0.7f}, {-2, 0, 0}, {0, 0, -2}},
        {{0.2f, -5, -0.4f}, {0, 1, 0}, {0, -1, 0}, {0.3f, 0.6f}, {0, 0, 2}, {2, 0, 0}},
        {{0.2f, 0.3f, 5}, {0, 0, -1}, {0, 0, 1}, {0.65f, 0.6f}, {0, 2, 0}, {2, 0, 0}},
        {{0.2f, 0.3f, -5}, {0, 0, 1}, {0, 0, -1}, {0.35f, 0.6f}, {0, -2, 0}, {2, 0, 0}},
    };
    auto scene = from_xml(R"(<shape type="cube"/>)");
    for (const Case& c : cases) {
        SCOPED_TRACE("face " + std::to_string(c.n.x) + "," + std::to_string(c.n.y) + "," + std::to_string(c.n.z));
        SurfaceInteraction si = hit(*scene, c.o, c.d);
        expect_vec(si.ng, c.n, "ng");
        expect_vec(si.shading.n, c.n, "shading normal");
        EXPECT_NEAR(si.uv.x, c.uv.x, 1e-5f);
        EXPECT_NEAR(si.uv.y, c.uv.y, 1e-5f);
        expect_vec(si.dpdu, c.dpdu, "dpdu");
        expect_vec(si.dpdv, c.dpdv, "dpdv");
    }
}

TEST(MitsubaShapes, CubeIsClosedWithOutwardWinding) {
    TriangleMesh m = TriangleMesh::cube();
    ASSERT_EQ(m.triangle_count(), 12u);
    for (size_t t = 0; t < m.triangle_count(); ++t) {
        const Point3f &a = m.positions[m.indices[3 * t]], &b = m.positions[m.indices[3 * t + 1]],
                      &c = m.positions[m.indices[3 * t + 2]];
        Vec3f n = normalize(cross(b - a, c - a));
        Vec3f centre = (a + b + c) / 3.f;
        EXPECT_GT(dot(n, centre), 0.5f) << "triangle " << t << " faces inward";
        expect_vec(m.normals[m.indices[3 * t]], n, "vertex normal");
        EXPECT_NEAR(m.triangle_area(t), 2.f, 1e-6f);
    }
}

// Mitsuba's flip_normals (every shape has it) negates the geometric and shading normals, keeps
// uv and dp/du, dp/dv (checked against Mitsuba 3.9.1), and an area emitter then emits on the
// other side.
TEST(MitsubaShapes, FlipNormalsOnEveryShape) {
    const test::TempDir tmp("pellucid_mitsuba_shapes_");
    const fs::path dir = tmp.path();
    std::ofstream(dir / "quad.obj") << "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                                       "f 1/1 2/2 3/3 4/4\n";
    std::ofstream(dir / "quad.ply") << "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                                       "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                       "end_header\n-1 -1 0\n1 -1 0\n1 1 0\n-1 1 0\n4 0 1 2 3\n";
    const char* kinds[] = {"rectangle", "cube", "disk", "obj", "ply", "sphere"};
    for (const char* kind : kinds) {
        for (bool flip : {false, true}) {
            SCOPED_TRACE(std::string(kind) + (flip ? " flipped" : ""));
            std::string file = std::string(kind) == "obj" ? R"(<string name="filename" value="quad.obj"/>)"
                               : std::string(kind) == "ply" ? R"(<string name="filename" value="quad.ply"/>)"
                                                            : "";
            auto scene = from_xml(std::string("<shape type=\"") + kind + "\">" + file +
                                      "<boolean name=\"flip_normals\" value=\"" + (flip ? "true" : "false") +
                                      "\"/><emitter type=\"area\"><rgb name=\"radiance\" value=\"2\"/></emitter></shape>",
                                  dir.string());
            // From above (+z), onto the top of each shape (z = 0 plane, or the cube's/sphere's top).
            SurfaceInteraction si = hit(*scene, Point3f(0.2f, 0.3f, 5.f), Vec3f(0, 0, -1));
            const float up = flip ? -1.f : 1.f;
            if (std::string(kind) == "sphere") EXPECT_GT(si.ng.z * up, 0.9f);
            else EXPECT_NEAR(si.ng.z, up, 1e-5f);
            EXPECT_GT(si.shading.n.z * up, 0.9f);
            Spectrum le = scene->emitted(si);
            EXPECT_EQ(le[0], flip ? 0.f : 2.f) << "emission toward +z";
            if (std::string(kind) == "rectangle") {  // uv and tangents do not change (as in Mitsuba)
                EXPECT_NEAR(si.uv.x, 0.6f, 1e-5f);
                EXPECT_NEAR(si.uv.y, 0.65f, 1e-5f);
                expect_vec(si.dpdu, Vec3f(2, 0, 0), "dpdu");
                expect_vec(si.dpdv, Vec3f(0, 2, 0), "dpdv");
            }
            if (std::string(kind) == "obj") {  // flip_tex_coords is Mitsuba's default for OBJ
                EXPECT_NEAR(si.uv.x, 0.6f, 1e-5f);
                EXPECT_NEAR(si.uv.y, 1.f - 0.65f, 1e-5f);
            }
            // From below, onto a planar shape's back: emits only when flipped.
            if (std::string(kind) != "cube" && std::string(kind) != "sphere") {
                SurfaceInteraction below = hit(*scene, Point3f(0.2f, 0.3f, -5.f), Vec3f(0, 0, 1));
                EXPECT_EQ(scene->emitted(below)[0], flip ? 2.f : 0.f) << "emission toward -z";
            }
        }
    }
}

TEST(MitsubaShapes, FlipNormalsInJson) {
    for (const char* kind : {"rectangle", "cube"}) {
        auto scene = test::scene_from(std::string(R"({"shapes": [{"type": ")") + kind + R"(", "flip_normals": true}]})");
        SurfaceInteraction si = hit(*scene, Point3f(0.2f, 0.3f, 5.f), Vec3f(0, 0, -1));
        EXPECT_NEAR(si.ng.z, -1.f, 1e-6f) << kind;
    }
    auto mesh = test::scene_from(R"({"shapes": [{"type": "mesh", "positions": [0,0,0, 1,0,0, 0,1,0],
        "indices": [0, 1, 2], "flip_normals": true}]})");
    SurfaceInteraction si = hit(*mesh, Point3f(0.2f, 0.3f, 5.f), Vec3f(0, 0, -1));
    EXPECT_NEAR(si.ng.z, -1.f, 1e-6f);
}
