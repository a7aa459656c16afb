// Inputs past a limit, or numbers that do not survive conversion to float, get an error naming the
// file and the key, never a crash or a silently wrong value.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <string>

#include "pellucid/scene/build.h"
#include "pellucid/scene/json_io.h"
#include "pellucid/util/error.h"
#include "pellucid/util/limits.h"
#include "support/error_of.h"

using namespace pellucid;

namespace {
std::string error_of(const std::string& json) { return test::json_scene_error(json); }
std::string nested(int depth) { return std::string(size_t(depth), '[') + std::string(size_t(depth), ']'); }
}  // namespace

TEST(InputLimits, DeepJsonNestingIsAnErrorNotACrash) {
    // 25,000 levels crashed the recursive conversion with SIGSEGV before the limit existed.
    std::string e = error_of(R"({"film": )" + nested(25000) + "}");
    EXPECT_NE(e.find("scene.json: objects and arrays nested deeper than 256 levels"), std::string::npos) << e;
    EXPECT_NE(e.find("PELLUCID_MAX_SCENE_DEPTH"), std::string::npos) << e;
    // At the limit the parser accepts the nesting (the build then rejects the value by key).
    std::string at = error_of(R"({"film": )" + nested(kDefaultMaxSceneDepth - 1) + "}");
    EXPECT_EQ(at.find("nested deeper"), std::string::npos) << at;
    EXPECT_NE(at.find("film"), std::string::npos) << at;
}

TEST(InputLimits, JsonNumberOverflowingADoubleNamesTheFile) {
    std::string e = error_of(R"({"film": {"width": 1e999}})");
    EXPECT_EQ(e.rfind("scene.json: malformed JSON: ", 0), 0u) << e;
    EXPECT_NE(e.find("1e999"), std::string::npos) << e;
}

TEST(InputLimits, NumbersThatOverflowAFloatAreRejectedByKey) {
    // 1e39 is finite as a double and infinite as a float: it spoiled the image silently before.
    const std::string light = R"({"shapes": [{"type": "sphere", "emitter": {"type": "area", "radiance": 1e39}}]})";
    EXPECT_EQ(error_of(light),
              "scene.json: shapes[0].emitter.radiance: value 1e+39 overflows a 32-bit float (largest: 3.4e38)");
    EXPECT_EQ(error_of(R"({"lights": [{"type": "constant", "radiance": [1, 1e39, 1]}]})"),
              "scene.json: lights[0].radiance: value 1e+39 overflows a 32-bit float (largest: 3.4e38)");
    EXPECT_NE(error_of(R"({"shapes": [{"type": "sphere", "to_world": [{"translate": [0, 0, 1e308]}]}]})")
                  .find("shapes[0].to_world[0].translate: expected finite numbers that fit a 32-bit float"),
              std::string::npos);
    EXPECT_TRUE(fits_float(3.4e38));
    EXPECT_FALSE(fits_float(3.5e38));
    EXPECT_FALSE(fits_float(-1e39));
}

TEST(InputLimits, IntegersKeepTheirValueOrAreRejected) {
    EXPECT_EQ(error_of(R"({"film": {"width": 3000000000}})"),
              "scene.json: film.width: value 3000000000 is out of range (a 32-bit integer: at most 2147483647 in "
              "magnitude)");
    EXPECT_EQ(error_of(R"({"film": {"width": 2.5}})"), "scene.json: film.width: expected an integer, got 2.5");
}

TEST(InputLimits, DegenerateCameraUpIsAnError) {
    // up = 0 (or a double that underflows a float to 0) made the camera's frame NaN, and Embree
    // aborted on the first ray.
    const std::string cam = R"({"camera": {"type": "perspective", "to_world": [{"look_at": {"origin": [0, 0, 5],
        "target": [0, 0, 0], "up": )";
    EXPECT_EQ(error_of(cam + "[0, 0, 0]}}]}}"),
              "scene.json: camera.to_world[0].look_at.up: up vector [0.000000, 0.000000, 0.000000] is zero (or underflows a float)");
    EXPECT_EQ(error_of(cam + "[0, 1e-309, 0]}}]}}"),
              "scene.json: camera.to_world[0].look_at.up: up vector [0.000000, 0.000000, 0.000000] is zero (or underflows a float)");
    EXPECT_EQ(error_of(cam + "[0, 0, 1]}}]}}"), "scene.json: camera.to_world[0].look_at.up: up is parallel to the view direction");
}

TEST(InputLimits, CoordinatesBeyondTheRayOriginLimitAreErrors) {
    EXPECT_NE(error_of(R"({"camera": {"type": "perspective", "to_world": [{"translate": [0, 0, 1e30]}]}})")
                  .find("scene.json: camera.to_world: the camera position [0, 0, 1e+30] is beyond the coordinate limit"),
              std::string::npos);
    EXPECT_NE(error_of(R"({"shapes": [{"type": "mesh", "positions": [0, 0, 0, 1, 0, 0, 0, 9.2e18, 0],
                           "indices": [0, 1, 2], "emitter": {"type": "area"}}]})")
                  .find("shapes[0]: positions: vertex 2 at [0, 9.2e+18, 0] (after to_world) is beyond the coordinate limit"),
              std::string::npos);
    EXPECT_NE(error_of(R"({"shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 2e18}]})")
                  .find("shapes[0].to_world: the sphere"),
              std::string::npos);
    EXPECT_NE(error_of(R"({"lights": [{"type": "point", "position": [0, 5e18, 0], "intensity": 1}]})")
                  .find("lights[0].position: the light position"),
              std::string::npos);
    // Large but valid coordinates still build.
    EXPECT_EQ(error_of(R"({"shapes": [{"type": "sphere", "center": [0, 0, 1e9], "radius": 1}]})"), "");
}
