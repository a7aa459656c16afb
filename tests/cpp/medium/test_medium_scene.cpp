// Media in scenes: JSON `media`, interior/exterior per shape, the camera medium, the null material,
// bad input, .vol files, the Mitsuba importer's media, and that media scenes render.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>

#include "pellucid/api.h"
#include "pellucid/integrator/path.h"
#include "pellucid/medium/medium_builder.h"
#include "pellucid/scene/build.h"
#include "pellucid/scene/json_io.h"
#include "pellucid/scene/mitsuba_xml.h"
#include "pellucid/util/log.h"
#include "support/error_of.h"
#include "support/temp_dir.h"

namespace pellucid::test {
namespace {

std::unique_ptr<Scene> build_json(const std::string& json) {
    SceneDesc d;
    d.source = "scene.json";
    d.root = parse_json(json, "scene.json");
    return build_scene(d);
}

const char* kFog = R"("media": {"fog": {"type": "homogeneous", "sigma_t": [0.5, 0.6, 0.7], "albedo": 0.9, "scale": 2,
                                         "phase": {"type": "hg", "g": 0.7}},
                              "ink": {"type": "homogeneous", "sigma_a": 1, "sigma_s": [0, 0.5, 1]}})";

TEST(MediumScene, JsonMediaAttachToShapesAndCamera) {
    auto s = build_json(std::string("{") + kFog + R"(,
        "camera": {"type": "perspective", "medium": "fog"},
        "materials": {"boundary": {"type": "null"}},
        "shapes": [{"type": "cube", "material": "boundary", "interior": "ink", "exterior": "fog"},
                   {"type": "sphere", "material": {"type": "null"}, "interior": "fog"},
                   {"type": "sphere", "center": [3, 0, 0]}]})");
    ASSERT_EQ(s->media.size(), 2u);
    EXPECT_EQ(name_of(s->media[0]), "fog");
    const auto& fog = std::get<HomogeneousMedium>(s->media[0]);
    EXPECT_FLOAT_EQ(fog.sigma_t().g, 1.2f);
    EXPECT_FLOAT_EQ(fog.sigma_s.r, 0.9f);
    EXPECT_FLOAT_EQ(std::get<HGPhase>(fog.phase).g(), 0.7f);
    const auto& ink = std::get<HomogeneousMedium>(s->media[1]);
    EXPECT_EQ(ink.sigma_a, Spectrum(1.f));
    EXPECT_EQ(ink.sigma_s, Spectrum(0.f, 0.5f, 1.f));
    EXPECT_TRUE(std::holds_alternative<IsotropicPhase>(ink.phase));
    EXPECT_EQ(s->camera_medium, 0);
    // Per Embree geometry id (the shape index).
    EXPECT_EQ(s->shapes[0].interior_medium, 1);
    EXPECT_EQ(s->shapes[0].exterior_medium, 0);
    EXPECT_TRUE(s->shapes[0].null_surface);
    EXPECT_EQ(s->shapes[1].interior_medium, 0);
    EXPECT_EQ(s->shapes[1].exterior_medium, -1);
    EXPECT_TRUE(s->shapes[1].null_surface);
    EXPECT_FALSE(s->shapes[2].null_surface);
    EXPECT_EQ(s->shapes[2].interior_medium, -1);
    EXPECT_TRUE(s->has_media());
    EXPECT_FALSE(build_json(R"({"shapes": [{"type": "sphere"}]})")->has_media());
}

TEST(MediumScene, GridMediaFromVolFileAndSmoke) {
    TempDir dir("pellucid_media_");
    const std::string vol = dir.file("d.vol");
    write_vol_file(vol, DensityGrid::smoke(20, 4));
    const DensityGrid back = read_vol_file(vol);
    EXPECT_EQ(back.values(), DensityGrid::smoke(20, 4).values());
    auto s = build_json(R"({"media": {
        "a": {"type": "grid", "density": {"type": "vol", "filename": ")" + vol + R"("}, "sigma_t": 4, "tracking": "delta",
              "to_world": [{"scale": 2}, {"translate": [-1, 0, -1]}]},
        "b": {"type": "grid", "density": {"type": "smoke", "resolution": 24, "seed": 2}, "emission": [1, 0, 0]}}})");
    const auto& a = std::get<GridMedium>(s->media[0]);
    EXPECT_EQ(a.grid->nx(), 20);
    EXPECT_EQ(a.tracking, Tracking::Delta);
    EXPECT_EQ(a.sigma_t, Spectrum(4.f));
    EXPECT_EQ(Vec3f(a.world_to_grid * Vec4f(1.f, 2.f, 1.f, 1.f)), Vec3f(1.f, 1.f, 1.f));
    const auto& b = std::get<GridMedium>(s->media[1]);
    EXPECT_EQ(b.grid->nz(), 24);
    EXPECT_EQ(b.le, Spectrum(1.f, 0.f, 0.f));
    EXPECT_EQ(b.tracking, Tracking::Ratio);
}

TEST(MediumScene, BadInputNamesFileKeyAndValue) {
    auto err = [](const std::string& media) { return json_scene_error(R"({"media": {"m": )" + media + "}}"); };
    EXPECT_EQ(err(R"({"type": "homogeneous", "sigma_a": [0.1, -0.2, 0]})"),
              "scene.json: media.m.sigma_a: value [0.100000, -0.200000, 0.000000] must be finite and >= 0 (a "
              "coefficient per colour channel)");
    EXPECT_EQ(err(R"({"type": "homogeneous", "sigma_t": -1})"),
              "scene.json: media.m.sigma_t: value [-1.000000, -1.000000, -1.000000] must be finite and >= 0 (a "
              "coefficient per colour channel)");
    EXPECT_EQ(err(R"({"type": "homogeneous", "phase": {"type": "hg", "g": 1.5}})"),
              "scene.json: media.m.phase.g: value 1.5 is out of range [-1, 1] (the mean cosine of the scattering angle)");
    EXPECT_EQ(err(R"({"type": "homogeneous", "phase": {"type": "hg", "g": -1.01}})").find("media.m.phase.g: value -1.01"),
              std::string("scene.json: ").size());
    EXPECT_EQ(err(R"({"type": "homogeneous", "sigma_t": 1, "sigma_s": 1})"),
              "scene.json: media.m.sigma_t: give either sigma_a and sigma_s, or sigma_t and albedo, not both");
    EXPECT_EQ(err(R"({"type": "homogeneous", "albedo": 1.2})"),
              "scene.json: media.m.albedo: value [1.200000, 1.200000, 1.200000] is out of range [0, 1]");
    EXPECT_EQ(err(R"({"type": "homogenous"})"),
              "scene.json: media.m.type: unknown medium type 'homogenous' (did you mean 'homogeneous'? known: grid, "
              "homogeneous)");
    EXPECT_EQ(err(R"({"type": "homogeneous", "phase": {"type": "henyey"}})"),
              "scene.json: media.m.phase.type: unknown phase function type 'henyey' (known: hg, isotropic)");
    EXPECT_EQ(err(R"({"type": "homogeneous", "sigma": 1})"),
              "scene.json: media.m.sigma: unknown parameter (did you mean 'sigma_t'?)");
    EXPECT_NE(err(R"({"type": "grid", "density": {"type": "vol", "filename": "missing.vol"}})")
                  .find("scene.json: media.m.density.filename: "), std::string::npos);
    EXPECT_EQ(err(R"({"type": "grid"})"),
              "scene.json: media.m: missing required key 'density' (a grid: {\"type\": \"vol\", \"filename\": ...} or "
              "{\"type\": \"smoke\"})");
    // Unknown medium names, with a did-you-mean.
    EXPECT_EQ(json_scene_error(std::string("{") + kFog + R"(, "shapes": [{"type": "sphere", "interior": "fgo"}]})"),
              "scene.json: shapes[0].interior: no medium 'fgo' (did you mean 'fog'? known: fog, ink)");
    EXPECT_EQ(json_scene_error(R"({"camera": {"type": "perspective", "medium": "air"}})"),
              "scene.json: camera.medium: no medium 'air' (known: none; define media under the top-level 'media')");
    EXPECT_EQ(json_scene_error(R"({"shapes": [{"type": "sphere", "material": {"type": "null", "g": 1}}]})"),
              "scene.json: shapes[0].material.g: unknown parameter");
}

TEST(MediumScene, OpenMeshBoundingAMediumWarns) {
    std::vector<std::string> warnings;
    set_log_sink([&](LogLevel l, const std::string& m) {
        if (l == LogLevel::Warning) warnings.push_back(m);
    });
    build_json(std::string("{") + kFog + R"(, "shapes": [{"type": "rectangle", "interior": "fog"},
                                                         {"type": "cube", "interior": "fog"},
                                                         {"type": "rectangle", "exterior": "fog"}]})");
    set_log_sink(nullptr);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_EQ(warnings[0], "scene.json: shapes[0]: the mesh has an interior medium but is not closed (4 edges are not "
                           "shared by exactly two triangles): unless other shapes close the volume, paths leave the "
                           "medium through its open edges");
    EXPECT_EQ(open_edge_count(TriangleMesh::cube()), 0u);
    EXPECT_EQ(open_edge_count(TriangleMesh::rectangle()), 4u);
}

TEST(MediumScene, MediaScenesRender) {
    // A scene with a medium, and one with only a null boundary, render without error and with
    // finite, non-negative pixels (the analytic checks are in integrator/test_media_render.cpp).
    RenderOptions o;
    o.spp = 2;
    for (const std::string& json :
         {std::string("{") + kFog + R"(, "film": {"width": 4, "height": 4},
                        "shapes": [{"type": "sphere", "interior": "fog"}], "lights": [{"type": "constant"}]})",
          std::string(R"({"film": {"width": 4, "height": 4}, "shapes": [{"type": "sphere", "material": {"type": "null"}}],
                          "lights": [{"type": "constant"}]})")}) {
        auto s = build_json(json);
        const RenderResult r = render(*s, o);
        for (float v : r.image.data) EXPECT_TRUE(std::isfinite(v) && v >= 0.f) << json;
        EXPECT_EQ(r.stats.invalid_samples, 0u) << json;
    }
}

const char* kMitsuba = R"(<scene version="3.0.0">
    <integrator type="volpath"><integer name="max_depth" value="12"/><integer name="rr_depth" value="4"/></integrator>
    <medium type="homogeneous" id="fog">
        <float name="sigma_t" value="0.5"/><rgb name="albedo" value="0.9, 0.8, 0.7"/><float name="scale" value="2"/>
        <phase type="hg"><float name="g" value="-0.4"/></phase>
    </medium>
    <bsdf type="null" id="boundary"/>
    <sensor type="perspective"><ref id="fog"/></sensor>
    <shape type="cube"><ref id="boundary"/><ref name="interior" id="fog"/>
        <medium type="homogeneous" name="exterior"><float name="sigma_a" value="0.1"/><float name="sigma_s" value="0.3"/>
            <phase type="isotropic"/></medium>
    </shape>
    <shape type="sphere"><bsdf type="dielectric"/><ref name="interior" id="fog"/></shape>
</scene>)";

TEST(MediumScene, MitsubaMediaImport) {
    SceneDesc d = parse_mitsuba_xml(kMitsuba, "m.xml", ".", false, {});
    auto s = build_scene(d);
    ASSERT_EQ(s->media.size(), 2u);
    const auto& fog = std::get<HomogeneousMedium>(s->media[0]);
    EXPECT_FLOAT_EQ(fog.sigma_s.g, 0.8f);
    EXPECT_FLOAT_EQ(fog.sigma_a.b, 0.3f);
    EXPECT_FLOAT_EQ(std::get<HGPhase>(fog.phase).g(), -0.4f);
    EXPECT_EQ(name_of(s->media[1]), "medium@m.xml:10");
    const auto& inl = std::get<HomogeneousMedium>(s->media[1]);
    EXPECT_FLOAT_EQ(inl.sigma_s.r, 0.3f);
    EXPECT_EQ(s->camera_medium, 0);
    EXPECT_TRUE(s->shapes[0].null_surface);
    EXPECT_EQ(s->shapes[0].interior_medium, 0);
    EXPECT_EQ(s->shapes[0].exterior_medium, 1);
    EXPECT_FALSE(s->shapes[1].null_surface);
    EXPECT_EQ(s->shapes[1].interior_medium, 0);
    EXPECT_EQ(s->integrator.type, "path");
    EXPECT_EQ(s->integrator.max_depth, 12);
    EXPECT_EQ(s->integrator.rr_depth, 4);
}

TEST(MediumScene, MitsubaMediaErrors) {
    auto err = [](const std::string& body) {
        return error_of_call([&] { build_scene(parse_mitsuba_xml("<scene version=\"3.0.0\">" + body + "</scene>", "m.xml", ".", false, {})); });
    };
    EXPECT_EQ(err(R"(<medium type="heterogeneous" id="m"/>)"),
              "m.xml:1: unsupported medium plugin 'heterogeneous' (known: homogeneous)");
    EXPECT_EQ(err(R"(<medium type="homogeneous" id="m"><phase type="rayleigh"/></medium>)"),
              "m.xml:1: unsupported phase plugin 'rayleigh' (known: isotropic, hg)");
    EXPECT_EQ(err(R"(<medium type="homogeneous" id="m"><float name="sample_emitters" value="1"/></medium>)"),
              "m.xml:1: unsupported parameter 'sample_emitters' of medium plugin 'homogeneous'");
    EXPECT_EQ(err(R"(<shape type="disk"><medium type="homogeneous" name="interior"/></shape>)"),
              "m.xml:1: unsupported parameter 'interior' of shape plugin 'disk'");
    EXPECT_EQ(err(R"(<shape type="sphere"><medium type="homogeneous" name="inside"/></shape>)"),
              "m.xml:1: a medium inside a shape needs name=\"interior\" or name=\"exterior\", got 'inside'");
    // Our builder's checks apply to imported media too.
    EXPECT_EQ(err(R"(<medium type="homogeneous" id="m"><phase type="hg"><float name="g" value="2"/></phase></medium>)"),
              "m.xml: media.m.phase.g: value 2 is out of range [-1, 1] (the mean cosine of the scattering angle)");
}
}  // namespace
}  // namespace pellucid::test
