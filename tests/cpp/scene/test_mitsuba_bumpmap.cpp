// Mitsuba 3's bumpmap and normalmap wrappers through the XML importer: bumpmap takes exactly one
// BSDF child and exactly one Texture child, each under any name (Mitsuba's own documentation names
// the texture "arbitrary"); zero or two of either are errors (docs/mitsuba-import.md).
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <string>

#include "pellucid/api.h"
#include "pellucid/scene/build.h"
#include "pellucid/scene/json_io.h"
#include "pellucid/scene/mitsuba_xml.h"
#include "pellucid/util/error.h"
#include "support/scene_util.h"
#include "support/error_of.h"

using namespace pellucid;
using pellucid::test::LogCapture;

namespace {
const char* const kChecker = R"(<texture type="checkerboard" %NAME%><rgb name="color0" value="0.25"/></texture>)";

std::string checker(const std::string& name_attr) {
    std::string s = kChecker;
    s.replace(s.find("%NAME%"), 6, name_attr);
    return s;
}

std::string scene(const std::string& bsdf_body, const std::string& before = "") {
    return "<scene version=\"3.0.0\">\n" + before + "\n<shape type=\"sphere\">\n<bsdf type=\"bumpmap\">\n" + bsdf_body +
           "\n</bsdf>\n</shape>\n</scene>\n";
}

SceneDesc parse(const std::string& xml) { return parse_mitsuba_xml(xml, "scene.xml", ".", false); }

std::string error_of(const std::string& xml) { return test::error_of_call([&] { parse(xml); }); }

const Node& material_of(const SceneDesc& d) { return *d.root.find("shapes")->items()[0].find("material"); }

// The bump map the wrapped material received is the checkerboard (color0 0.25).
void expect_checker_bump(const SceneDesc& d) {
    const Node& m = material_of(d);
    ASSERT_NE(m.find("bump_map"), nullptr) << to_json(d.root);
    EXPECT_EQ(m.find("type")->as_string(), "lambertian");
    EXPECT_EQ(m.find("bump_map")->find("type")->as_string(), "checkerboard");
    EXPECT_EQ(m.find("bump_map")->find("color0")->as_number(), 0.25);
}
}  // namespace

TEST(MitsubaBumpmap, TextureChildUnderAnyNameOrNone) {
    // Mitsuba's documentation example: the texture is named "arbitrary".
    expect_checker_bump(parse(scene(checker("name=\"arbitrary\"") + "<bsdf type=\"diffuse\"/>")));
    expect_checker_bump(parse(scene(checker("") + "<bsdf type=\"diffuse\"/>")));
    // After the bsdf, and as references to a texture with an id, named or not.
    expect_checker_bump(parse(scene("<bsdf type=\"diffuse\"/>" + checker("name=\"height\""))));
    const std::string tex = checker("id=\"t\"");
    expect_checker_bump(parse(scene("<ref name=\"whatever\" id=\"t\"/><bsdf type=\"diffuse\"/>", tex)));
    expect_checker_bump(parse(scene("<ref id=\"t\"/><bsdf type=\"diffuse\"/>", tex)));
    // A named bsdf child is the bsdf child too.
    expect_checker_bump(parse(scene(checker("name=\"a\"") + "<bsdf type=\"diffuse\" name=\"nested\"/>")));
}

TEST(MitsubaBumpmap, ExactlyOneTextureAndOneBsdf) {
    // Two textures (any mix of names) are an error at the second, naming the first's line.
    EXPECT_EQ(error_of(scene(checker("name=\"a\"") + "\n" + checker("") + "<bsdf type=\"diffuse\"/>")),
              "scene.xml:6: bsdf plugin 'bumpmap' takes exactly one nested texture (under any name); the first is on "
              "line 5");
    EXPECT_EQ(error_of(scene(checker("") + "\n" + checker("name=\"b\"") + "<bsdf type=\"diffuse\"/>")),
              "scene.xml:6: bsdf plugin 'bumpmap' takes exactly one nested texture (under any name); the first is on "
              "line 5");
    EXPECT_EQ(error_of(scene(checker("") + "\n" + checker("") + "<bsdf type=\"diffuse\"/>")),
              "scene.xml:6: bsdf plugin 'bumpmap' takes exactly one nested texture (under any name); the first is on "
              "line 5");
    EXPECT_EQ(error_of(scene("<bsdf type=\"diffuse\"/>")),
              "scene.xml:4: bsdf plugin 'bumpmap' needs exactly one nested texture (under any name); it has none");
    EXPECT_EQ(error_of(scene(checker("name=\"a\""))),
              "scene.xml:4: bsdf plugin 'bumpmap' needs exactly one nested bsdf; it has none");
    EXPECT_EQ(error_of(scene(checker("name=\"a\"") + "\n<bsdf type=\"diffuse\"/>\n<bsdf type=\"diffuse\"/>")),
              "scene.xml:7: bsdf plugin 'bumpmap' takes exactly one nested bsdf");
}

TEST(MitsubaBumpmap, ScaleAndPerturbedNormalOptions) {
    SceneDesc d = parse(scene(checker("name=\"a\"") + R"(<bsdf type="diffuse"/><float name="scale" value="0.3"/>
        <boolean name="use_shadowing_function" value="false"/><boolean name="flip_invalid_normals" value="true"/>)"));
    const Node& m = material_of(d);
    EXPECT_EQ(m.find("bump_scale")->as_number(), 0.3);
    ASSERT_NE(m.find("terminator_softening"), nullptr);
    EXPECT_FALSE(m.find("terminator_softening")->as_bool());
    // Mitsuba's defaults (scale 1, both options true) write only Mitsuba's model: its gradient and
    // frame, the mirroring of invalid normals and the Estevez shadowing term.
    d = parse(scene(checker("name=\"a\"") + "<bsdf type=\"diffuse\"/>"));
    EXPECT_EQ(material_of(d).find("bump_scale"), nullptr);
    EXPECT_EQ(material_of(d).find("terminator_softening"), nullptr);
    EXPECT_EQ(material_of(d).find("bump_model")->as_string(), "mitsuba");
    EXPECT_EQ(material_of(d).find("invalid_normals")->as_string(), "mirror");
    EXPECT_EQ(material_of(d).find("terminator_model")->as_string(), "estevez");
    // flip_invalid_normals = false leaves invalid normals as they are.
    d = parse(scene(checker("name=\"a\"") + "<bsdf type=\"diffuse\"/>\n<boolean name=\"flip_invalid_normals\" value=\"false\"/>"));
    EXPECT_EQ(material_of(d).find("invalid_normals")->as_string(), "keep");
    // normalmap takes the same two options.
    d = parse("<scene version=\"3.0.0\"><shape type=\"sphere\"><bsdf type=\"normalmap\">" + checker("name=\"normalmap\"") +
              "<bsdf type=\"diffuse\"/><boolean name=\"use_shadowing_function\" value=\"false\"/></bsdf></shape></scene>");
    EXPECT_FALSE(material_of(d).find("terminator_softening")->as_bool());
    EXPECT_NE(material_of(d).find("normal_map"), nullptr);
}

// Mitsuba's documentation example, with a real bitmap, builds and renders.
TEST(MitsubaBumpmap, DocumentationExampleBuilds) {
    const std::string dir = std::string(PELLUCID_SOURCE_DIR) + "/tests/data/mitsuba";
    SceneDesc d = parse_mitsuba_xml(R"(<scene version="3.0.0">
        <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
            <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform></sensor>
        <shape type="sphere">
            <bsdf type="bumpmap">
                <texture name="arbitrary" type="bitmap">
                    <boolean name="raw" value="true"/>
                    <string name="filename" value="quad.png"/>
                </texture>
                <bsdf type="roughplastic"><string name="distribution" value="ggx"/></bsdf>
            </bsdf>
        </shape>
        <emitter type="constant"/>
    </scene>)",
                                   "scene.xml", dir, false);
    auto scene = build_scene(d);
    ASSERT_EQ(scene->materials.size(), 1u);
    EXPECT_TRUE(scene->material_textures[0].perturbs_normal());
}
