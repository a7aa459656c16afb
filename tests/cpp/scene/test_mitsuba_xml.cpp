// Mitsuba 3 XML import: XML snippets -> the JSON-shaped SceneDesc tree (docs/mitsuba-import.md).
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "pellucid/scene/build.h"
#include "pellucid/scene/json_io.h"
#include "pellucid/scene/mitsuba_xml.h"
#include "pellucid/scene/properties.h"
#include "pellucid/util/error.h"
#include "pellucid/util/log.h"
#include "support/scene_util.h"
#include "support/temp_dir.h"

using namespace pellucid;
namespace fs = std::filesystem;

using pellucid::test::LogCapture;
using pellucid::test::scene_from;
using pellucid::test::z_two_sided;

namespace {

/// Structural equality; numbers compare by value (integer 0 == float 0.0) to 1e-9 relative.
::testing::AssertionResult same(const Node& a, const Node& b, const std::string& path = "") {
    if (a.kind() != b.kind())
        return ::testing::AssertionFailure() << path << ": kind " << a.kind_name() << " vs " << b.kind_name();
    switch (a.kind()) {
        case Node::Kind::Null: return ::testing::AssertionSuccess();
        case Node::Kind::Bool:
            if (a.as_bool() != b.as_bool()) return ::testing::AssertionFailure() << path << ": bool differs";
            return ::testing::AssertionSuccess();
        case Node::Kind::Number:
            if (std::fabs(a.as_number() - b.as_number()) > 1e-9 * std::max(1.0, std::fabs(b.as_number())))
                return ::testing::AssertionFailure() << path << ": " << a.as_number() << " vs " << b.as_number();
            return ::testing::AssertionSuccess();
        case Node::Kind::String:
            if (a.as_string() != b.as_string())
                return ::testing::AssertionFailure() << path << ": '" << a.as_string() << "' vs '" << b.as_string() << "'";
            return ::testing::AssertionSuccess();
        case Node::Kind::Array:
            if (a.size() != b.size()) return ::testing::AssertionFailure() << path << ": size " << a.size() << " vs " << b.size();
            for (size_t i = 0; i < a.size(); ++i) {
                auto r = same(a.items()[i], b.items()[i], path_index(path, i));
                if (!r) return r;
            }
            return ::testing::AssertionSuccess();
        case Node::Kind::Object:
            if (a.size() != b.size())
                return ::testing::AssertionFailure() << path << ": " << a.size() << " vs " << b.size() << " keys";
            for (size_t i = 0; i < a.size(); ++i) {
                const auto& [ka, va] = a.members()[i];
                const auto& [kb, vb] = b.members()[i];
                if (ka != kb) return ::testing::AssertionFailure() << path << ": key '" << ka << "' vs '" << kb << "'";
                auto r = same(va, vb, path_join(path, ka));
                if (!r) return r;
            }
            return ::testing::AssertionSuccess();
    }
    return ::testing::AssertionSuccess();
}

::testing::AssertionResult converts_to(const std::string& xml, const std::string& json,
                                       const std::map<std::string, std::string>& params = {}) {
    SceneDesc d = parse_mitsuba_xml(xml, "scene.xml", ".", false, params);
    auto r = same(d.root, parse_json(json, "expected"));
    if (!r) r << "\ngot: " << to_json(d.root);
    return r;
}

std::string scene(const std::string& body) { return "<scene version=\"3.0.0\">\n" + body + "\n</scene>\n"; }

std::string error_of(const std::string& xml, bool lenient = false, const std::string& base = ".") {
    try {
        parse_mitsuba_xml(xml, "scene.xml", base, lenient);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}


void write(const fs::path& p, const std::string& text) {
    fs::create_directories(p.parent_path());
    std::ofstream(p) << text;
}
}  // namespace

TEST(MitsubaXml, SensorFilmSamplerIntegrator) {
    EXPECT_TRUE(converts_to(scene(R"(
  <integrator type="path"><integer name="max_depth" value="8"/><integer name="rr_depth" value="3"/></integrator>
  <sensor type="perspective">
    <float name="fov" value="39.3"/>
    <string name="fov_axis" value="smaller"/>
    <transform name="to_world"><lookat origin="0, 1, 6.8" target="0 1 0" up="0,1,0"/></transform>
    <sampler type="independent"><integer name="sample_count" value="64"/><integer name="seed" value="3"/></sampler>
    <film type="hdrfilm">
      <integer name="width" value="320"/><integer name="height" value="240"/>
      <string name="pixel_format" value="rgb"/>
      <rfilter type="tent"><float name="radius" value="1.5"/></rfilter>
    </film>
  </sensor>)"),
                            R"({
  "camera": {"type": "perspective", "fov": 39.3, "fov_axis": "smaller",
             "to_world": [{"look_at": {"origin": [0, 1, 6.8], "target": [0, 1, 0], "up": [0, 1, 0]}}]},
  "film": {"width": 320, "height": 240, "filter": {"type": "tent", "radius": 1.5}, "reconstruction": "splatting"},
  "sampler": {"type": "independent", "sample_count": 64, "seed": 3},
  "integrator": {"type": "path", "max_depth": 8, "rr_depth": 3}})"));
}

TEST(MitsubaXml, MitsubaDefaultsWhereOursDiffer) {
    // hdrfilm is 768x576 with a (shifted) gaussian rfilter and the sampler takes 4 samples unless told
    // otherwise; volpath -> path.
    EXPECT_TRUE(converts_to(scene(R"(<integrator type="volpath"/>
  <sensor type="perspective"><film type="hdrfilm"/><sampler type="independent"/></sensor>)"),
                            R"({"camera": {"type": "perspective"}, "film": {"width": 768, "height": 576,
                                "filter": {"type": "gaussian", "shift": true}, "reconstruction": "splatting"},
                                "sampler": {"type": "independent", "sample_count": 4},
                                "integrator": {"type": "path"}})"));
}

TEST(MitsubaXml, ShapesMaterialsAndAreaEmitters) {
    EXPECT_TRUE(converts_to(scene(R"(
  <bsdf type="diffuse" id="white"><rgb name="reflectance" value="0.8, 0.7 0.6"/></bsdf>
  <shape type="obj">
    <string name="filename" value="meshes/bunny.obj"/>
    <boolean name="face_normals" value="true"/>
    <ref id="white"/>
  </shape>
  <shape type="ply"><string name="filename" value="a.ply"/><ref name="bsdf" id="white"/></shape>
  <shape type="sphere">
    <point name="center" x="1" y="2" z="3"/><float name="radius" value="0.5"/>
    <bsdf type="diffuse"><spectrum name="reflectance" value="0.25"/></bsdf>
  </shape>
  <shape type="rectangle">
    <boolean name="flip_normals" value="true"/>
    <emitter type="area"><rgb name="radiance" value="10"/></emitter>
  </shape>
  <shape type="cube"/>
  <shape type="disk"/>)"),
                            R"({
  "materials": {"white": {"type": "lambertian", "reflectance": [0.8, 0.7, 0.6], "two_sided": false}},
  "shapes": [
    {"type": "obj", "filename": "meshes/bunny.obj", "face_normals": true, "smooth_normals": false,
     "flip_tex_coords": true, "usemtl": false, "material": "white"},
    {"type": "ply", "filename": "a.ply", "face_normals": false, "smooth_normals": true, "material": "white"},
    {"type": "sphere", "center": [1, 2, 3], "radius": 0.5,
     "material": {"type": "lambertian", "reflectance": 0.25, "two_sided": false}},
    {"type": "rectangle", "flip_normals": true, "material": {"type": "lambertian", "reflectance": 0},
     "emitter": {"type": "area", "radiance": 10}},
    {"type": "cube"},
    {"type": "disk"}]})"));
}

TEST(MitsubaXml, TransformsComposeLikeMitsuba) {
    SceneDesc d = parse_mitsuba_xml(scene(R"(<shape type="cube"><transform name="to_world">
      <scale value="2"/>
      <translate x="1"/>
      <rotate y="1" angle="90"/>
      <scale x="1" y="3"/>
      <matrix value="1 0 0 0  0 1 0 5  0 0 1 0  0 0 0 1"/>
    </transform></shape>)"),
                                    "scene.xml", ".", false);
    const Node& tw = *d.root.find("shapes")->items()[0].find("to_world");
    EXPECT_TRUE(same(tw, parse_json(R"([{"scale": 2}, {"translate": [1, 0, 0]},
        {"rotate": {"axis": [0, 1, 0], "angle": 90}}, {"scale": [1, 3, 1]},
        {"matrix": [1, 0, 0, 0, 0, 1, 0, 5, 0, 0, 1, 0, 0, 0, 0, 1]}])", "e")));
    // Each tag left-multiplies: p -> M * S2 * R * T * S1 * p. (1,0,0) -> (2,0,0) -> (3,0,0)
    // -> rotate 90 deg about y -> (0,0,-3) -> scale y by 3 -> (0,0,-3) -> translate y by 5.
    Properties p(d.root.find("shapes")->items()[0], "scene.xml", "shapes[0]");
    Transform t = p.get_transform("to_world");
    Vec3f q = t.point(Point3f(1, 0, 0));
    EXPECT_NEAR(q.x, 0.f, 1e-5f);
    EXPECT_NEAR(q.y, 5.f, 1e-5f);
    EXPECT_NEAR(q.z, -3.f, 1e-5f);
    Vec3f v = t.point(Point3f(0, 1, 0));  // (0,2,0) -> (1,2,0) -> (0,2,-1) -> (0,6,-1) -> (0,11,-1)
    EXPECT_NEAR(v.x, 0.f, 1e-5f);
    EXPECT_NEAR(v.y, 11.f, 1e-5f);
    EXPECT_NEAR(v.z, -1.f, 1e-5f);
}

TEST(MitsubaXml, BsdfMappings) {
    EXPECT_TRUE(converts_to(scene(R"(
  <bsdf type="conductor" id="au"><string name="material" value="Au"/></bsdf>
  <bsdf type="conductor" id="custom"><rgb name="eta" value="0.2 0.4 1.4"/><rgb name="k" value="3.9 2.4 1.8"/>
    <rgb name="specular_reflectance" value="0.9"/></bsdf>
  <bsdf type="roughconductor" id="rc"><string name="distribution" value="ggx"/>
    <float name="alpha_u" value="0.05"/><float name="alpha_v" value="0.3"/><string name="material" value="Cu"/></bsdf>
  <bsdf type="roughconductor" id="rc_default"><float name="alpha" value="0.2"/></bsdf>
  <bsdf type="dielectric" id="glass"><string name="int_ior" value="bk7"/><float name="ext_ior" value="1.0"/></bsdf>
  <bsdf type="roughdielectric" id="frosted"><string name="distribution" value="ggx"/><float name="alpha" value="0.3"/></bsdf>
  <bsdf type="thindielectric" id="pane"><float name="int_ior" value="1.5"/></bsdf>
  <bsdf type="plastic" id="red"><rgb name="diffuse_reflectance" value="0.5 0.1 0.1"/><float name="int_ior" value="1.9"/></bsdf>
  <bsdf type="roughplastic" id="rp"><float name="alpha" value="0.1"/><string name="distribution" value="ggx"/></bsdf>
  <bsdf type="plastic" id="nl"><boolean name="nonlinear" value="true"/></bsdf>
  <bsdf type="principled" id="p"><rgb name="base_color" value="0.1 0.2 0.3"/><float name="metallic" value="0.7"/>
    <float name="roughness" value="0.3"/><float name="specular" value="0.6"/><float name="spec_tint" value="0.2"/>
    <float name="sheen" value="0.1"/><float name="sheen_tint" value="0.4"/><float name="clearcoat" value="0.5"/>
    <float name="clearcoat_gloss" value="0.8"/><float name="anisotropic" value="0.25"/></bsdf>
  <bsdf type="principled" id="p_default"/>
  <bsdf type="principled" id="p_glass"><float name="spec_trans" value="0.9"/><float name="eta" value="1.33"/>
    <float name="flatness" value="0.2"/><float name="main_specular_sampling_rate" value="2"/></bsdf>
  <bsdf type="principledthin" id="p_thin"><float name="diff_trans" value="1.2"/><float name="spec_trans" value="0.3"/></bsdf>
  <bsdf type="twosided" id="two"><bsdf type="diffuse"><float name="reflectance" value="0.3"/></bsdf></bsdf>)"),
                            R"({"materials": {
  "au": {"type": "conductor", "material": "Au", "two_sided": false},
  "custom": {"type": "conductor", "eta": [0.2, 0.4, 1.4], "k": [3.9, 2.4, 1.8], "specular_reflectance": 0.9,
             "two_sided": false},
  "rc": {"type": "rough_conductor", "distribution": "ggx", "alpha_u": 0.05, "alpha_v": 0.3, "material": "Cu",
         "shadowing": "separable", "two_sided": false},
  "rc_default": {"type": "rough_conductor", "alpha": 0.2, "distribution": "beckmann", "shadowing": "separable",
                 "two_sided": false},
  "glass": {"type": "dielectric", "int_ior": "bk7", "ext_ior": 1.0},
  "frosted": {"type": "rough_dielectric", "distribution": "ggx", "alpha": 0.3, "shadowing": "separable"},
  "pane": {"type": "thin_dielectric", "int_ior": 1.5},
  "red": {"type": "plastic", "diffuse_reflectance": [0.5, 0.1, 0.1], "int_ior": 1.9, "variant": "linear",
          "two_sided": false},
  "rp": {"type": "rough_plastic", "alpha": 0.1, "distribution": "ggx", "variant": "linear",
         "coat_transmittance": "rough", "shadowing": "separable", "two_sided": false},
  "nl": {"type": "plastic", "variant": "coupled", "two_sided": false},
  "p": {"type": "principled", "variant": "2015", "base_color": [0.1, 0.2, 0.3], "metallic": 0.7, "roughness": 0.3,
        "specular": 0.6, "specular_tint": 0.2, "sheen": 0.1, "sheen_tint": 0.4, "clearcoat": 0.5,
        "clearcoat_gloss": 0.8, "anisotropic": 0.25},
  "p_default": {"type": "principled", "variant": "2015", "base_color": 0.5, "sheen_tint": 0, "clearcoat_gloss": 0},
  "p_glass": {"type": "principled", "variant": "2015", "specular_transmission": 0.9, "eta": 1.33, "flatness": 0.2,
              "base_color": 0.5, "sheen_tint": 0, "clearcoat_gloss": 0},
  "p_thin": {"type": "principled", "variant": "2015", "thin": true, "diffuse_transmission": 1.2,
             "specular_transmission": 0.3, "base_color": 0.5, "sheen_tint": 0, "eta": 1.5},
  "two": {"type": "lambertian", "reflectance": 0.3, "two_sided": true}}})"));
}

TEST(MitsubaXml, RoughDiffuseAlphaToSigmaDegrees) {
    // sigma [rad] = alpha / sqrt(2) (Mitsuba's own conversion), written in degrees.
    SceneDesc d = parse_mitsuba_xml(scene(R"(<bsdf type="roughdiffuse" id="r"><float name="alpha" value="0.5"/>
        <rgb name="reflectance" value="0.4"/></bsdf><bsdf type="roughdiffuse" id="d"/>)"),
                                    "scene.xml", ".", false);
    const Node& m = *d.root.find("materials");
    EXPECT_EQ(m.find("r")->find("type")->as_string(), "oren_nayar");
    EXPECT_EQ(m.find("r")->find("variant")->as_string(), "classic");
    EXPECT_NEAR(m.find("r")->find("sigma")->as_number(), 0.5 / std::sqrt(2.0) * 180.0 / M_PI, 1e-9);
    EXPECT_NEAR(m.find("d")->find("sigma")->as_number(), 0.2 / std::sqrt(2.0) * 180.0 / M_PI, 1e-9);
    EXPECT_EQ(m.find("r")->find("reflectance")->as_number(), 0.4);
}

TEST(MitsubaXml, WrappersAndTextures) {
    EXPECT_TRUE(converts_to(scene(R"(
  <texture type="checkerboard" id="checks">
    <rgb name="color0" value="0.1"/><rgb name="color1" value="0.9"/>
    <transform name="to_uv"><scale x="4" y="4"/></transform>
  </texture>
  <bsdf type="diffuse" id="tiles"><ref name="reflectance" id="checks"/></bsdf>
  <bsdf type="roughplastic" id="img">
    <texture type="bitmap" name="diffuse_reflectance">
      <string name="filename" value="textures/wood.png"/><string name="filter_type" value="nearest"/>
      <string name="wrap_mode" value="clamp"/><boolean name="raw" value="false"/>
    </texture>
  </bsdf>
  <bsdf type="bumpmap" id="bumpy">
    <texture type="bitmap"><string name="filename" value="bump.png"/><boolean name="raw" value="true"/></texture>
    <float name="scale" value="0.5"/>
    <ref id="tiles"/>
  </bsdf>
  <bsdf type="normalmap" id="nm">
    <texture name="normalmap" type="bitmap"><string name="filename" value="n.png"/></texture>
    <bsdf type="twosided"><bsdf type="conductor"/></bsdf>
  </bsdf>)"),
                            R"({"materials": {
  "tiles": {"type": "lambertian", "reflectance": {"type": "checkerboard", "color0": 0.1, "color1": 0.9,
                                                   "to_uv": [{"scale": [4, 4, 1]}], "filtered": false},
            "two_sided": false},
  "img": {"type": "rough_plastic", "diffuse_reflectance": {"type": "image", "filename": "textures/wood.png",
          "filter": "nearest", "wrap_mode": "clamp"}, "distribution": "beckmann", "variant": "linear",
          "coat_transmittance": "rough", "shadowing": "separable", "two_sided": false},
  "bumpy": {"type": "lambertian", "reflectance": {"type": "checkerboard", "color0": 0.1, "color1": 0.9,
                                                   "to_uv": [{"scale": [4, 4, 1]}], "filtered": false},
            "two_sided": false,
            "bump_map": {"type": "image", "color_space": "linear", "filename": "bump.png"}, "bump_scale": 0.5,
            "bump_model": "mitsuba", "terminator_model": "estevez", "invalid_normals": "mirror"},
  "nm": {"type": "conductor", "two_sided": true,
         "normal_map": {"type": "image", "filename": "n.png", "color_space": "auto"},
         "bump_model": "mitsuba", "terminator_model": "estevez", "invalid_normals": "mirror"}}})"));
}

TEST(MitsubaXml, Lights) {
    EXPECT_TRUE(converts_to(scene(R"(
  <emitter type="point"><point name="position" value="0, 5, 0"/><rgb name="intensity" value="100"/></emitter>
  <emitter type="spot"><rgb name="intensity" value="50"/><float name="cutoff_angle" value="30"/>
    <float name="beam_width" value="20"/>
    <transform name="to_world"><lookat origin="0 4 0" target="0 0 0" up="0 0 1"/></transform></emitter>
  <emitter type="directional"><vector name="direction" x="0" y="-1" z="0"/><rgb name="irradiance" value="3"/></emitter>
  <emitter type="constant"><rgb name="radiance" value="0.5 0.6 0.7"/></emitter>
  <emitter type="envmap"><string name="filename" value="sky.exr"/><float name="scale" value="2"/>
    <transform name="to_world"><rotate x="1" angle="-90"/></transform></emitter>)"),
                            R"({"lights": [
  {"type": "point", "position": [0, 5, 0], "intensity": 100},
  {"type": "spot", "intensity": 50, "cutoff_angle": 30, "beam_width": 20,
   "to_world": [{"look_at": {"origin": [0, 4, 0], "target": [0, 0, 0], "up": [0, 0, 1]}}]},
  {"type": "directional", "direction": [0, -1, 0], "irradiance": 3},
  {"type": "constant", "radiance": [0.5, 0.6, 0.7]},
  {"type": "envmap", "filename": "sky.exr", "scale": 2, "to_world": [{"rotate": {"axis": [1, 0, 0], "angle": -90}}]}]})"));
}

TEST(MitsubaXml, DefaultsAndParams) {
    std::string xml = scene(R"(<default name="spp" value="16"/>
  <default name="res" value="64"/>
  <sensor type="perspective">
    <sampler type="independent"><integer name="sample_count" value="$spp"/></sampler>
    <film type="hdrfilm"><integer name="width" value="$res"/><integer name="height" value="$res"/></film>
  </sensor>)");
    SceneDesc d = parse_mitsuba_xml(xml, "scene.xml", ".", false);
    EXPECT_EQ(d.root.find("sampler")->find("sample_count")->as_number(), 16);
    EXPECT_TRUE(d.root.find("sampler")->find("sample_count")->is_integer());
    EXPECT_EQ(d.root.find("film")->find("width")->as_number(), 64);
    d = parse_mitsuba_xml(xml, "scene.xml", ".", false, {{"spp", "256"}});
    EXPECT_EQ(d.root.find("sampler")->find("sample_count")->as_number(), 256);
    EXPECT_EQ(d.root.find("film")->find("height")->as_number(), 64);
    EXPECT_EQ(error_of(scene("\n<sensor type=\"perspective\"><float name=\"fov\" value=\"$fov\"/></sensor>")),
              "scene.xml:3: undefined parameter '$fov' (declare it with <default name=\"fov\" value=...> or pass it)");
}

TEST(MitsubaXml, PrincipledEtaOrSpecular) {
    // Mitsuba's principled takes one of the two (specular sets eta); so does the import.
    EXPECT_EQ(error_of(scene("<bsdf type=\"principled\" id=\"a\">\n  <float name=\"eta\" value=\"1.4\"/>"
                             "<float name=\"specular\" value=\"0.3\"/></bsdf>")),
              "scene.xml:2: bsdf plugin 'principled' takes 'eta' or 'specular', not both (specular sets eta)");
    // principledthin has neither metallic nor clearcoat.
    EXPECT_NE(error_of(scene("<bsdf type=\"principledthin\" id=\"a\"><float name=\"metallic\" value=\"1\"/></bsdf>")), "");
}

TEST(MitsubaXml, RefErrorsNameTheLine) {
    EXPECT_EQ(error_of(scene("<shape type=\"cube\">\n  <ref id=\"nope\"/>\n</shape>")),
              "scene.xml:3: unknown reference id 'nope'");
    EXPECT_EQ(error_of(scene("<bsdf type=\"diffuse\" id=\"a\"/>\n<bsdf type=\"diffuse\" id=\"a\"/>")),
              "scene.xml:3: duplicate id 'a' (first defined on line 2)");
    EXPECT_EQ(error_of(scene("<texture type=\"checkerboard\" id=\"t\"/>\n<shape type=\"cube\"><ref id=\"t\"/></shape>")),
              "scene.xml:3: unexpected <ref> inside shape plugin 'cube'");
}

TEST(MitsubaXml, UnsupportedPluginsAndLenientMode) {
    std::string xml = scene(R"(<bsdf type="diffuse" id="ok"/>
<bsdf type="hair" id="h"/>
<shape type="sphere">
  <float name="radius" value="2"/>
  <float name="wobble" value="1"/>
</shape>)");
    EXPECT_EQ(error_of(xml), "scene.xml:3: unsupported bsdf plugin 'hair'");
    LogCapture log;
    SceneDesc d = parse_mitsuba_xml(xml, "scene.xml", ".", true);
    ASSERT_EQ(log.warnings.size(), 2u);
    EXPECT_EQ(log.warnings[0], "scene.xml:3: unsupported bsdf plugin 'hair' (skipped)");
    EXPECT_EQ(log.warnings[1], "scene.xml:6: unsupported parameter 'wobble' of shape plugin 'sphere' (skipped)");
    EXPECT_TRUE(same(d.root, parse_json(R"({"materials": {"ok": {"type": "lambertian", "two_sided": false}},
                                             "shapes": [{"type": "sphere", "radius": 2}]})", "e")));
    // A ref to a skipped bsdf stays an error: its id was never defined.
    EXPECT_EQ(error_of(scene("<bsdf type=\"hair\" id=\"h\"/>\n<shape type=\"cube\"><ref id=\"h\"/></shape>"), true),
              "scene.xml:3: unknown reference id 'h'");
}

TEST(MitsubaXml, MalformedXmlAndOtherErrors) {
    EXPECT_EQ(error_of("<scene version=\"3.0.0\">\n<shape type=\"cube\">\n</scene>\n"),
              "scene.xml:3: malformed XML: Start-end tags mismatch");
    EXPECT_EQ(error_of("<shape type=\"cube\"/>"), "scene.xml:1: expected a <scene> root element, got <shape>");
    EXPECT_EQ(error_of(scene("<shape type=\"sphere\"><float name=\"radius\" value=\"big\"/></shape>")),
              "scene.xml:2: expected a number, got 'big'");
    EXPECT_EQ(error_of(scene("\n\n<volume type=\"gridvolume\" id=\"fog\"/>")),
              "scene.xml:4: volume textures (volume 'gridvolume') are not supported; use a homogeneous medium");
    EXPECT_EQ(error_of(scene("<shape type=\"cube\">\n<ref name=\"interior\" id=\"m\"/></shape>")),
              "scene.xml:3: unknown reference id 'm'");
    EXPECT_EQ(error_of(scene("<emitter type=\"area\"/>")),
              "scene.xml:2: an 'area' emitter must be nested in a <shape>");
    EXPECT_EQ(error_of("<scene version=\"0.6.0\"/>"),
              "scene.xml:1: Mitsuba scene version 0.6.0 is not supported (only 3.x; parameter names changed in 2.0)");
    EXPECT_EQ(error_of(scene("<shape type=\"cube\"><spectrum name=\"x\" value=\"400:0.1, 700:0.3\"/></shape>")),
              "scene.xml:2: spectra given as wavelength:value pairs are not supported; use <rgb>");
}

TEST(MitsubaXml, IncludesResolveRelativeToTheirFile) {
    const test::TempDir tmp("pellucid_mitsuba_");
    const fs::path dir = tmp.path();
    write(dir / "parts" / "objects.xml", scene(R"(<default name="r" value="3"/>
<bsdf type="diffuse" id="grey"/>
<shape type="obj"><string name="filename" value="meshes/a.obj"/><ref id="grey"/></shape>
<include filename="missing.xml"/>)"));
    write(dir / "main.xml", scene(R"(<include filename="parts/objects.xml"/>
<shape type="sphere"><float name="radius" value="$r"/><ref id="grey"/></shape>)"));
    // The include's own include is missing: the error names the included file and its line.
    try {
        read_mitsuba_xml_file((dir / "main.xml").string(), false);
        ADD_FAILURE() << "expected an error";
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()), (dir / "main.xml").parent_path().string() + "/parts/objects.xml:5: "
                                         "cannot open include file '" + (dir / "parts" / "missing.xml").string() + "'");
    }
    write(dir / "parts" / "objects.xml", scene(R"(<default name="r" value="3"/>
<bsdf type="diffuse" id="grey"/>
<shape type="obj"><string name="filename" value="meshes/a.obj"/><ref id="grey"/></shape>)"));
    SceneDesc d = read_mitsuba_xml_file((dir / "main.xml").string(), false);
    EXPECT_EQ(d.source, (dir / "main.xml").string());
    EXPECT_TRUE(same(d.root, parse_json(R"({"materials": {"grey": {"type": "lambertian", "two_sided": false}}, "shapes": [
        {"type": "obj", "filename": "parts/meshes/a.obj", "face_normals": false, "smooth_normals": true, "flip_tex_coords": true, "usemtl": false,
         "material": "grey"},
        {"type": "sphere", "radius": 3, "material": "grey"}]})", "e")));
}

TEST(MitsubaXml, DataFileBuildsWithTheSharedBuilder) {
    // tests/data/mitsuba/spheres.xml uses only what the builder supports today.
    SceneDesc d = read_mitsuba_xml_file(std::string(PELLUCID_SOURCE_DIR) + "/tests/data/mitsuba/spheres.xml", false);
    auto s = build_scene(d);
    EXPECT_EQ(s->width, 64);
    EXPECT_EQ(s->height, 48);
    EXPECT_EQ(s->spp, 256);
    EXPECT_EQ(s->shapes.size(), 3u);
    EXPECT_EQ(s->lights.size(), 2u);
}
