// OBJ per-face materials: `usemtl` names mapped to scene materials by id, the shape's `materials`
// renames, the fallbacks and errors, area emission on such a shape, and the Mitsuba importer
// (which ignores usemtl, as Mitsuba does).
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "pellucid/api.h"
#include "pellucid/light/area.h"
#include "pellucid/scene/json_io.h"
#include "pellucid/scene/mitsuba_xml.h"
#include "pellucid/util/error.h"
#include "support/scene_util.h"
#include "support/temp_dir.h"

using namespace pellucid;
namespace fs = std::filesystem;

namespace {
// In the z = 0 plane, facing +z: a triangle before any usemtl (x in [2, 3]), the left square
// x in [-1, 0] as "red" (plus a zero-area triangle that the builder drops, so the per-face ids
// must be compacted with the triangles), the right square x in [0, 1] as "blue", and a trailing
// "unused" with no faces.
const char* kObj = R"(v -1 -1 0
v 0 -1 0
v 0 1 0
v -1 1 0
v 1 -1 0
v 1 1 0
v -0.5 -1 0
v 2 -1 0
v 3 -1 0
v 2 1 0
f 8 9 10
usemtl red
f 1 2 3 4
f 1 7 2
usemtl blue
f 2 5 6 3
usemtl unused
)";

struct ObjMaterials : ::testing::Test {
    test::TempDir tmp{"pellucid_obj_materials_"};
    fs::path dir = tmp.path();
    test::LogCapture log;  // the zero-area triangle is dropped with a warning
    void SetUp() override { std::ofstream(dir / "two.obj") << kObj; }

    std::shared_ptr<const Scene> build(const std::string& shape, const std::string& extra = "") const {
        return test::scene_from(R"({"materials": {
            "red": {"type": "lambertian", "reflectance": [0.8, 0.1, 0.1]},
            "blue": {"type": "lambertian", "reflectance": [0.1, 0.1, 0.8]},
            "green": {"type": "lambertian", "reflectance": [0.1, 0.8, 0.1]},
            "grey": {"type": "lambertian", "reflectance": 0.5}},
            "shapes": [)" + shape + "]" + extra + "}",
                                dir.string());
    }
    std::string error(const std::string& shape) const {
        try {
            build(shape);
        } catch (const Error& e) {
            return e.what();
        }
        return "";
    }
    /// Name of the material hit straight down at (x, y).
    static std::string material_at(const Scene& s, float x, float y) {
        SurfaceInteraction si;
        if (!s.intersect(Ray{Point3f(x, y, 1.f), Vec3f(0, 0, -1), kInfinity}, si)) return "<miss>";
        return s.material_names.at(si.material_id);
    }
};
}  // namespace

TEST_F(ObjMaterials, FacesTakeTheSceneMaterialOfTheirUsemtlName) {
    auto s = build(R"({"type": "obj", "filename": "two.obj", "material": "grey"})");
    EXPECT_TRUE(log.has("skipped 1 zero-area triangle"));
    // Both triangles of each square (the fan's (1,2,3) and (1,3,4)), and the face before usemtl.
    EXPECT_EQ(material_at(*s, -0.75f, -0.5f), "red");
    EXPECT_EQ(material_at(*s, -0.25f, 0.5f), "red");
    EXPECT_EQ(material_at(*s, 0.75f, -0.5f), "blue");
    EXPECT_EQ(material_at(*s, 0.25f, 0.5f), "blue");
    EXPECT_EQ(material_at(*s, 2.2f, -0.5f), "grey");
    ASSERT_EQ(s->shapes.size(), 1u);
    EXPECT_EQ(s->shapes[0].face_materials.size(), s->meshes[0].triangle_count());
}

TEST_F(ObjMaterials, RendersEachFaceWithItsMaterial) {
    // The albedo AOV of a Lambertian face is its reflectance exactly (one cosine-weighted sample
    // has weight R), so every pixel must show the colour of the face under its centre.
    auto s = build(R"({"type": "obj", "filename": "two.obj"})", R"(,
        "film": {"width": 8, "height": 4, "filter": {"type": "box", "radius": 0.001}},
        "camera": {"type": "perspective", "fov": 30,
                   "to_world": [{"look_at": {"origin": [0, 0, 3], "target": [0, 0, 0], "up": [0, 1, 0]}}]},
        "sampler": {"sample_count": 2}, "integrator": {"type": "aov", "aov": "albedo"})");
    RenderResult r = render(*s, RenderOptions{});
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) {
            const float* px = r.image.pixel(x, y);
            const bool left = x < 4;  // the camera looks down -z with +x to the right
            EXPECT_NEAR(px[0], left ? 0.8f : 0.1f, 1e-5f) << "pixel " << x << "," << y;
            EXPECT_NEAR(px[1], 0.1f, 1e-5f) << "pixel " << x << "," << y;
            EXPECT_NEAR(px[2], left ? 0.1f : 0.8f, 1e-5f) << "pixel " << x << "," << y;
        }
}

TEST_F(ObjMaterials, RenameMapAndFallbacks) {
    auto s = build(R"({"type": "obj", "filename": "two.obj", "material": "grey", "materials": {"red": "green"}})");
    EXPECT_EQ(material_at(*s, -0.5f, 0.f), "green");
    EXPECT_EQ(material_at(*s, 0.5f, 0.f), "blue");
    // A name that is neither renamed nor a scene material falls back to the shape's material.
    fs::path other = dir / "other.obj";
    std::ofstream(other) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nusemtl brass\nf 1 2 3\nusemtl blue\nf 2 4 3\n";
    auto t = build(R"({"type": "obj", "filename": "other.obj", "material": {"type": "lambertian", "reflectance": 0.3}})");
    EXPECT_EQ(material_at(*t, 0.2f, 0.2f), "shapes[0].material");
    EXPECT_EQ(material_at(*t, 0.8f, 0.8f), "blue");
    // Everything resolving to one material needs no per-face ids.
    auto u = build(R"({"type": "obj", "filename": "other.obj", "material": "blue", "materials": {"brass": "blue"}})");
    EXPECT_TRUE(u->shapes[0].face_materials.empty());
    EXPECT_EQ(material_at(*u, 0.2f, 0.2f), "blue");
    // usemtl: false ignores the names.
    auto v = build(R"({"type": "obj", "filename": "two.obj", "material": "grey", "usemtl": false})");
    EXPECT_TRUE(v->shapes[0].face_materials.empty());
    EXPECT_EQ(material_at(*v, -0.5f, 0.f), "grey");
    EXPECT_EQ(material_at(*v, 0.5f, 0.f), "grey");
    // Without a shape material, faces before any usemtl get the default material.
    auto w = build(R"({"type": "obj", "filename": "two.obj"})");
    EXPECT_EQ(material_at(*w, 2.2f, -0.5f), "<default>");
    EXPECT_EQ(material_at(*w, -0.5f, 0.f), "red");
}

TEST_F(ObjMaterials, ErrorsNameTheFileKeyAndName) {
    std::ofstream(dir / "brass.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl brass\nf 1 2 3\n";
    EXPECT_EQ(error(R"({"type": "sphere"}, {"type": "obj", "filename": "brass.obj"})"),
              "test: shapes[1]: mesh 'brass.obj' face material 'brass' is not a scene material (define it under "
              "'materials', rename it with the shape's 'materials', or give the shape a 'material')");
    EXPECT_EQ(error(R"({"type": "obj", "filename": "two.obj", "materials": {"red": "gold"}})"),
              "test: shapes[0].materials.red: no material 'gold'");
    EXPECT_EQ(error(R"({"type": "obj", "filename": "two.obj", "materials": {"copper": "red"}})"),
              "test: shapes[0].materials.copper: mesh 'two.obj' has no usemtl 'copper' (its names: red, blue, unused)");
    EXPECT_EQ(error(R"({"type": "obj", "filename": "two.obj", "materials": {"red": 3}})"),
              "test: shapes[0].materials.red: expected a material id (string), got a number");
    EXPECT_EQ(error(R"({"type": "obj", "filename": "two.obj", "materials": ["red"]})"),
              "test: shapes[0].materials: expected an object {\"usemtl name\": \"material id\"}, got a array");
    EXPECT_EQ(error(R"({"type": "obj", "filename": "two.obj", "usemtl": false, "materials": {"red": "blue"}})"),
              "test: shapes[0].materials: renames usemtl names, but 'usemtl' is false");
    // A rename is checked against the file's names: a mesh without usemtl has none.
    std::ofstream(dir / "plain.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    EXPECT_EQ(error(R"({"type": "obj", "filename": "plain.obj", "materials": {"red": "blue"}})"),
              "test: shapes[0].materials.red: mesh 'plain.obj' has no usemtl 'red' (its names: none)");
    // `materials` and `usemtl` belong to obj only.
    EXPECT_EQ(error(R"({"type": "rectangle", "usemtl": true})"), "test: shapes[0].usemtl: unknown parameter");
}

TEST_F(ObjMaterials, AreaEmissionCoversEveryFace) {
    auto s = build(R"({"type": "obj", "filename": "two.obj", "material": "grey",
                       "emitter": {"type": "area", "radiance": 2}})");
    ASSERT_EQ(s->lights.size(), 1u);
    const AreaLight& light = std::get<AreaLight>(s->lights[0]);
    // Areas: red square 2, blue square 2, the pre-usemtl triangle 1 (the zero-area one adds none).
    EXPECT_NEAR(light.area(), 5.f, 1e-5f);
    EXPECT_NEAR(light.power(), 2.f * kPi * 5.f, 1e-3f);
    for (float x : {-0.5f, 0.5f, 2.2f}) {
        SurfaceInteraction si;
        ASSERT_TRUE(s->intersect(Ray{Point3f(x, -0.5f, 1.f), Vec3f(0, 0, -1), kInfinity}, si));
        EXPECT_EQ(s->emitted(si)[0], 2.f) << "x = " << x;
    }
    // Area sampling from above: with a stratified 64x64 grid of u the share of samples on each
    // part is its share of the area to the grid's resolution (deterministic, no statistics).
    int left = 0, right = 0, far = 0;
    const int n = 64;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            auto ls = light.sample_li(LightSampleContext{Point3f(0, 0, 2), Normal3f(0, 0, -1)},
                                      Vec2f((i + 0.5f) / n, (j + 0.5f) / n));
            ASSERT_TRUE(ls.has_value());
            (ls->p_light.x > 1.5f ? far : ls->p_light.x < 0.f ? left : right)++;
        }
    EXPECT_NEAR(left / double(n * n), 0.4, 0.01);
    EXPECT_NEAR(right / double(n * n), 0.4, 0.01);
    EXPECT_NEAR(far / double(n * n), 0.2, 0.01);
}

TEST_F(ObjMaterials, MitsubaImportIgnoresUsemtl) {
    // Mitsuba gives an OBJ shape its one bsdf whatever the file's usemtl names; so do we, even
    // when they coincide with bsdf ids of the scene.
    std::ofstream(dir / "scene.xml") << R"(<scene version="3.0.0">
  <bsdf type="diffuse" id="red"><rgb name="reflectance" value="0.8, 0.1, 0.1"/></bsdf>
  <bsdf type="diffuse" id="blue"><rgb name="reflectance" value="0.1, 0.1, 0.8"/></bsdf>
  <bsdf type="diffuse" id="grey"/>
  <shape type="obj"><string name="filename" value="two.obj"/><ref id="grey"/></shape>
</scene>)";
    auto s = load_file((dir / "scene.xml").string());
    EXPECT_EQ(material_at(*s, -0.5f, 0.f), "grey");
    EXPECT_EQ(material_at(*s, 0.5f, 0.f), "grey");
    EXPECT_TRUE(s->shapes[0].face_materials.empty());
}
