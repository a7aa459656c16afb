// "Did you mean" suggestions: the edit distance, the choice of near names, and the messages that
// scene files get for a mistyped or Mitsuba-named type or key.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include "pellucid/util/suggest.h"
#include "support/error_of.h"

using namespace pellucid;

namespace {
std::string error_of(const std::string& json) { return test::json_scene_error(json); }
std::string material_error(const std::string& body) {
    return error_of(std::string(R"({"materials": {"m": )") + body + "}}");
}
}  // namespace

TEST(Suggest, EditDistance) {
    EXPECT_EQ(edit_distance("", ""), 0u);
    EXPECT_EQ(edit_distance("abc", ""), 3u);
    EXPECT_EQ(edit_distance("", "ab"), 2u);
    EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
    EXPECT_EQ(edit_distance("alpah", "alpha"), 1u);  // an adjacent swap counts once
    EXPECT_EQ(edit_distance("Alpha", "aLPHA"), 0u);  // case is ignored
    EXPECT_EQ(edit_distance("roughconductor", "rough_conductor"), 1u);
    EXPECT_EQ(edit_distance("ca", "abc"), 3u);  // optimal string alignment: no edit of a swapped pair
}

TEST(Suggest, ClosestNamesKeepsOnlyNearOnes) {
    const std::vector<std::string> materials = {"conductor", "dielectric", "lambertian", "rough_conductor",
                                                "rough_dielectric", "plastic"};
    EXPECT_EQ(closest_names("lambertain", materials), std::vector<std::string>{"lambertian"});
    EXPECT_EQ(closest_names("roughconductor", materials),
              (std::vector<std::string>{"rough_conductor", "conductor"}));
    EXPECT_EQ(closest_names("RoughDielectric", materials),
              (std::vector<std::string>{"rough_dielectric", "dielectric"}));
    EXPECT_TRUE(closest_names("velvet", materials).empty());
    EXPECT_TRUE(closest_names("lambertian", materials).empty());  // an exact name is no suggestion
    EXPECT_EQ(did_you_mean("plastik", materials), "did you mean 'plastic'?");
    EXPECT_EQ(did_you_mean("x", materials), "");
}

TEST(Suggest, SceneErrorsNameTheNearestKeyOrType) {
    EXPECT_EQ(material_error(R"({"type": "lambertian", "reflectanse": 0.5})"),
              "scene.json: materials.m.reflectanse: unknown parameter (did you mean 'reflectance'?)");
    EXPECT_EQ(material_error(R"({"type": "lambertain"})").rfind(
                  "scene.json: materials.m.type: unknown material type 'lambertain' (did you mean 'lambertian'? "
                  "known: conductor, ", 0),
              0u)
        << material_error(R"({"type": "lambertain"})");
    EXPECT_EQ(material_error(R"({"type": "velvet"})").find("did you mean"), std::string::npos);
    EXPECT_NE(error_of(R"({"shapes": [{"type": "spehre"}]})")
                  .find("shapes[0].type: unknown shape type 'spehre' (did you mean 'sphere'? known: "),
              std::string::npos);
    EXPECT_NE(error_of(R"({"lights": [{"type": "spotlight"}]})")
                  .find("lights[0].type: unknown light type 'spotlight' (did you mean 'spot'? known: "),
              std::string::npos)
        << error_of(R"({"lights": [{"type": "spotlight"}]})");
}

TEST(Suggest, MitsubaNamesInJsonNameOurs) {
    EXPECT_EQ(material_error(R"({"type": "diffuse"})").rfind(
                  "scene.json: materials.m.type: unknown material type 'diffuse' (Mitsuba's 'diffuse' is "
                  "'lambertian' here; known: ",
                  0),
              0u)
        << material_error(R"({"type": "diffuse"})");
    EXPECT_NE(material_error(R"({"type": "roughconductor"})")
                  .find("unknown material type 'roughconductor' (Mitsuba's 'roughconductor' is 'rough_conductor' here;"),
              std::string::npos);
    EXPECT_NE(material_error(R"({"type": "bumpmap"})").find("Mitsuba's 'bumpmap' is the material key 'bump_map' here"),
              std::string::npos);
    // Keys: a Mitsuba parameter of the plugin this type imports from.
    EXPECT_EQ(material_error(R"({"type": "principled", "spec_trans": 0.5})"),
              "scene.json: materials.m.spec_trans: unknown parameter (Mitsuba's 'spec_trans' is "
              "'specular_transmission' here)");
    EXPECT_EQ(material_error(R"({"type": "oren_nayar", "alpha": 0.2})"),
              "scene.json: materials.m.alpha: unknown parameter (Mitsuba's 'alpha' is converted to 'sigma' here)");
    EXPECT_EQ(material_error(R"({"type": "rough_conductor", "sample_visible": true})"),
              "scene.json: materials.m.sample_visible: unknown parameter (Mitsuba's 'sample_visible' has no "
              "counterpart here)");
}
