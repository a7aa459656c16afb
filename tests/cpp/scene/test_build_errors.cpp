// Scene description errors name the file and the key path.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include "pellucid/api.h"
#include "pellucid/scene/build.h"
#include "pellucid/scene/json_io.h"
#include "pellucid/util/error.h"
#include "support/error_of.h"

using namespace pellucid;

namespace {
std::string build_error(const std::string& json) { return test::json_scene_error(json); }
const char* kMat = R"("materials": {"white": {"type": "lambertian", "reflectance": 0.5}})";
}  // namespace

TEST(SceneErrors, DanglingMaterialNamesTheKeyPath) {
    std::string e = build_error(std::string("{") + kMat + R"(, "shapes": [
        {"type": "sphere"}, {"type": "sphere"}, {"type": "sphere"}, {"type": "sphere", "material": "gold"}]})");
    EXPECT_EQ(e, "scene.json: shapes[3].material: no material 'gold'");
}

TEST(SceneErrors, UnknownKeyWrongTypeUnknownType) {
    EXPECT_EQ(build_error(R"({"materials": {"m": {"type": "lambertian", "reflectanse": 0.5}}})"),
              "scene.json: materials.m.reflectanse: unknown parameter (did you mean 'reflectance'?)");
    EXPECT_EQ(build_error(R"({"film": {"width": "wide"}})"), "scene.json: film.width: expected a number, got a string");
    EXPECT_NE(build_error(R"({"shapes": [{"type": "teapot"}]})").find("shapes[0].type: unknown shape type 'teapot'"),
              std::string::npos);
    EXPECT_EQ(build_error(R"({"camras": {}})"), "scene.json: camras: unknown parameter (did you mean 'camera'?)");
}

TEST(SceneErrors, OutOfRangeParameters) {
    EXPECT_EQ(build_error(R"({"materials": {"m": {"type": "lambertian", "reflectance": -0.1}}})"),
              "scene.json: materials.m.reflectance: value [-0.100000, -0.100000, -0.100000] is out of range [0, 1]");
    EXPECT_NE(build_error(R"({"materials": {"m": {"type": "lambertian", "reflectance": [0.5, 1.5, 0.5]}}})")
                  .find("materials.m.reflectance: value"), std::string::npos);
    EXPECT_EQ(build_error(R"({"film": {"width": 0}})"), "scene.json: film.width: resolution 0 is out of range [1, 16384]");
    EXPECT_EQ(build_error(R"({"film": {"width": 1000000}})"),
              "scene.json: film.width: resolution 1000000 is out of range [1, 16384]");
    EXPECT_EQ(build_error(R"({"sampler": {"sample_count": 0}})"),
              "scene.json: sampler.sample_count: value 0 is out of range [1, 16777216]");
    EXPECT_NE(build_error(R"({"shapes": [{"type": "sphere", "radius": -1}]})").find("shapes[0].radius"), std::string::npos);
    EXPECT_NE(build_error(R"({"camera": {"type": "perspective", "fov": 0}})").find("camera.fov"), std::string::npos);
}

TEST(SceneErrors, MeshIndicesAndDegenerateTriangles) {
    EXPECT_EQ(build_error(R"({"shapes": [{"type": "mesh", "positions": [0,0,0, 1,0,0, 0,1,0], "indices": [0, 1, 3]}]})"),
              "scene.json: shapes[0].indices[2]: index 3 out of range (mesh has 3 vertices)");
    // A zero-area triangle is skipped with a warning; the remaining one is kept.
    SceneDesc d;
    d.root = parse_json(R"({"shapes": [{"type": "mesh", "positions": [0,0,0, 1,0,0, 0,1,0, 2,0,0],
        "indices": [0, 1, 2, 0, 1, 3]}]})", "t");
    auto scene = build_scene(d);
    EXPECT_EQ(scene->triangle_count, 1u);
}

TEST(SceneErrors, MalformedJsonAndMissingFile) {
    std::string e = build_error("{\"film\": {\"width\": 3,}}");
    EXPECT_NE(e.find("scene.json: malformed JSON"), std::string::npos) << e;
    EXPECT_NE(e.find("line 1"), std::string::npos) << e;
    try {
        load_file("/nonexistent/scene.json");
        FAIL();
    } catch (const Error& err) {
        EXPECT_EQ(std::string(err.what()), "/nonexistent/scene.json: cannot open scene file (does it exist?)");
    }
}

TEST(SceneErrors, SppZeroIsAnError) {
    SceneDesc d;
    d.root = parse_json(R"({"film": {"width": 4, "height": 4}})", "t");
    auto scene = load_desc(d);
    RenderOptions o;
    o.spp = 0;
    EXPECT_THROW(render(*scene, o), Error);
}

TEST(JsonIO, RoundTrip) {
    Node n = parse_json(R"({"a": [1, 2.5, "x", true, null], "b": {"c": -3}})", "t");
    Node m = parse_json(to_json(n), "t2");
    EXPECT_EQ(to_json(n), to_json(m));
    EXPECT_TRUE(n.find("a")->items()[0].is_integer());
    EXPECT_FALSE(n.find("a")->items()[1].is_integer());
}
