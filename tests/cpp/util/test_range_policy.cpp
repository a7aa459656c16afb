// One range-check policy for every parameter, constant or textured (docs/scene-format.md, "Limits
// and numbers"): a texture whose values leave the parameter's range is an error naming the key,
// the value and where the value comes from, as a constant out of range is.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <string>

#include "support/error_of.h"

namespace {
std::string material_error(const std::string& material) {
    return pellucid::test::json_scene_error(R"({"materials": {"m": )" + material + "}}");
}
}  // namespace

TEST(RangePolicy, TexturedColourOutOfRangeIsAnErrorLikeAConstant) {
    EXPECT_EQ(material_error(R"({"type": "lambertian", "reflectance": -0.5})"),
              "scene.json: materials.m.reflectance: value [-0.500000, -0.500000, -0.500000] is out of range [0, 1]");
    // Silently clamped to 0 before.
    EXPECT_EQ(material_error(R"({"type": "lambertian", "reflectance": {"type": "checkerboard", "color1": -5}})"),
              "scene.json: materials.m.reflectance: the texture reaches -5 (from materials.m.reflectance.color1), out "
              "of range [0, 1]");
    EXPECT_EQ(material_error(R"({"type": "lambertian", "reflectance": {"type": "noise", "color0": [0, 0, 0],
                                 "color1": [1, 1.5, 1]}})"),
              "scene.json: materials.m.reflectance: the texture reaches 1.5 (from materials.m.reflectance.color1), out "
              "of range [0, 1]");
    // Within range: builds.
    EXPECT_EQ(material_error(R"({"type": "lambertian", "reflectance": {"type": "checkerboard", "color1": 1}})"), "");
}

TEST(RangePolicy, ScaleAndMixPropagateRanges) {
    EXPECT_EQ(material_error(R"({"type": "lambertian", "reflectance": {"type": "scale", "scale": 3,
                                 "texture": {"type": "checkerboard"}}})"),
              "scene.json: materials.m.reflectance: the texture reaches 1.2 (from materials.m.reflectance), out of "
              "range [0, 1]");
    EXPECT_EQ(material_error(R"({"type": "lambertian", "reflectance": {"type": "scale", "scale": 2,
                                 "texture": {"type": "checkerboard"}}})"),
              "");
    // mix of two in-range colours stays in range; amount itself must lie in [0, 1].
    EXPECT_EQ(material_error(R"({"type": "lambertian", "reflectance": {"type": "mix", "texture0": 0.2,
                                 "texture1": 0.9}})"),
              "");
    EXPECT_EQ(material_error(R"({"type": "lambertian", "reflectance": {"type": "mix", "amount": 2}})"),
              "scene.json: materials.m.reflectance.amount: the texture's channel average reaches 2 (from "
              "materials.m.reflectance.amount), out of range [0, 1]");
}

TEST(RangePolicy, FloatParametersCheckTheChannelAverage) {
    EXPECT_EQ(material_error(R"({"type": "principled", "metallic": {"type": "checkerboard", "color0": -1}})"),
              "scene.json: materials.m.metallic: the texture's channel average reaches -1 (from "
              "materials.m.metallic.color0), out of range [0, 1]");
    // Roughness above 1 is clamped with a warning, for constants and textures alike; below 0 it is an error.
    EXPECT_EQ(material_error(R"({"type": "rough_conductor", "alpha": {"type": "checkerboard", "color0": 2}})"), "");
    EXPECT_EQ(material_error(R"({"type": "rough_conductor", "alpha": {"type": "checkerboard", "color0": -0.1}})"),
              "scene.json: materials.m.alpha: the texture's channel average reaches -0.1 (from materials.m.alpha.color0); "
              "it must be >= 0");
}

TEST(RangePolicy, TextureValuesMustFitAFloat) {
    EXPECT_EQ(material_error(R"({"type": "lambertian", "bump_map": {"type": "scale", "scale": 3e38,
                                 "texture": {"type": "checkerboard", "color0": 10}}})"),
              "scene.json: materials.m.bump_map: the texture's values overflow a 32-bit float (up to inf)");
}
