// The envmap light: Mitsuba 3's lat-long convention, texel lookup, its exact integral, scene building,
// bad input (missing/corrupt/invalid files name the path and key), zero-power lights skipped with a
// warning, and renders under an environment map that agree across integrator strategies.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "light_cases.h"
#include "pellucid/api.h"
#include "pellucid/image/image_io.h"
#include "pellucid/math/constants.h"
#include "pellucid/sampling/rng.h"
#include "pellucid/sampling/warp.h"
#include "pellucid/scene/json_io.h"
#include "pellucid/util/error.h"
#include "pellucid/util/log.h"
#include "support/chi2.h"
#include "support/scene_util.h"
#include "support/temp_dir.h"

using namespace pellucid;
namespace fs = std::filesystem;

using pellucid::test::LogCapture;
using pellucid::test::TempDir;
using pellucid::test::scene_from;
using pellucid::test::z_two_sided;

namespace {
SceneDesc desc_in(const TempDir& dir, const std::string& json) {
    SceneDesc d;
    d.source = "scene.json";
    d.base_dir = dir.dir();
    d.root = parse_json(json, "scene.json");
    return d;
}
std::string build_error(const SceneDesc& d) {
    try {
        load_desc(d);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}


}  // namespace

TEST(Envmap, MitsubaLatLongConvention) {
    // Mitsuba 3 envmap.cpp: d = (sin φ sin θ, cos θ, −cos φ sin θ), u = φ/2π, v = θ/π; +y is up.
    auto near = [](const Vec3f& a, const Vec3f& b) { return length(a - b) < 1e-6f; };
    EXPECT_TRUE(near(EnvmapLight::uv_to_direction({0.f, 0.5f}), {0, 0, -1}));
    EXPECT_TRUE(near(EnvmapLight::uv_to_direction({0.25f, 0.5f}), {1, 0, 0}));
    EXPECT_TRUE(near(EnvmapLight::uv_to_direction({0.5f, 0.5f}), {0, 0, 1}));
    EXPECT_TRUE(near(EnvmapLight::uv_to_direction({0.75f, 0.5f}), {-1, 0, 0}));
    EXPECT_TRUE(near(EnvmapLight::uv_to_direction({0.3f, 0.f}), {0, 1, 0}));
    EXPECT_TRUE(near(EnvmapLight::uv_to_direction({0.3f, 1.f}), {0, -1, 0}));
    PCG32 rng(1, 1);
    for (int i = 0; i < 1000; ++i) {
        Vec3f d = square_to_uniform_sphere(rng.next_2d());
        Vec2f uv = EnvmapLight::direction_to_uv(d);
        ASSERT_GE(uv.x, 0.f);
        ASSERT_LT(uv.x, 1.f);
        ASSERT_TRUE(near(EnvmapLight::uv_to_direction(uv), d)) << to_string(d);
    }
}

TEST(Envmap, TexelCentresAndRotation) {
    // Column x is centred at u = (x + ½)/W, row y at v = y/(H − 1); to_world rotates the map.
    const int W = 8, H = 5;
    Image img = test::asymmetric_envmap_image(W, H);
    const Mat3f R = test::test_rotation();
    EnvmapLight light(img, 3.f, R);
    for (int y = 1; y < H - 1; ++y)
        for (int x = 0; x < W; ++x) {
            Vec2f uv((x + 0.5f) / W, float(y) / float(H - 1));
            Spectrum L = light.Le(normalize(R * EnvmapLight::uv_to_direction(uv)));
            const float* p = img.pixel(x, y);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(L[c], 3.f * p[c], 1e-4f * (1.f + 3.f * p[c])) << x << "," << y;
        }
    // Halfway between two columns (wrapping from the last to the first): the mean of both.
    Vec2f uv(0.f, 0.5f);  // between column W−1 (u = 1 − ½/W) and column 0 (u = ½/W)
    Spectrum L = light.Le(normalize(R * EnvmapLight::uv_to_direction(uv)));
    EXPECT_NEAR(L.b, 3.f * 0.5f * (img.pixel(W - 1, 2)[2] + img.pixel(0, 2)[2]), 1e-4f);
}

TEST(Envmap, IntegralIsExactForTheBilinearRadiance) {
    EnvmapLight light(test::asymmetric_envmap_image(), 1.f, Mat3f(1.f));
    // ∫ L̄ dω = ∫∫ L̄(u, v) 2π² sin(πv) du dv by a fine midpoint rule.
    const int nu = 1600, nv = 800;
    double sum = 0;
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            Vec2f uv(float((i + 0.5) / nu), float((j + 0.5) / nv));
            sum += double(light.lookup(uv).average()) * std::sin(M_PI * uv.y);
        }
    sum *= 2 * M_PI * M_PI / (double(nu) * nv);
    EXPECT_NEAR(light.integral(), sum, 2e-5 * sum);
}

TEST(Envmap, BuildsFromAnExrFile) {
    TempDir dir("pellucid_envmap_");
    write_image_file(dir.file("sky.exr"), test::asymmetric_envmap_image());
    auto scene = load_desc(desc_in(dir, R"({"lights": [{"type": "envmap", "filename": "sky.exr", "scale": 2,
        "to_world": [{"rotate": {"axis": [1, 0, 0], "angle": -90}}]}]})"));
    ASSERT_EQ(scene->lights.size(), 1u);
    ASSERT_TRUE(std::holds_alternative<EnvmapLight>(scene->lights[0]));
    EXPECT_EQ(scene->infinite_lights, std::vector<uint32_t>{0});
    // The rotation about x by −90° takes the map's +y (v = 0) to world −z... and the map's +z to +y.
    const auto& env = std::get<EnvmapLight>(scene->lights[0]);
    EnvmapLight ref(test::asymmetric_envmap_image(), 2.f, Mat3f(1.f));
    for (Vec3f d : {Vec3f(0.3f, 0.5f, 0.81f), Vec3f(-0.7f, 0.1f, -0.2f)}) {
        d = normalize(d);
        Vec3f world = Vec3f(d.x, d.z, -d.y);  // R_x(−90°) applied to d
        Spectrum a = env.Le(world), b = ref.Le(d);
        EXPECT_NEAR(a.r, b.r, 1e-4f);
        EXPECT_NEAR(a.g, b.g, 1e-4f);
    }
}

TEST(EnvmapErrors, MissingFileNamesPathAndKey) {
    TempDir dir("pellucid_envmap_");
    std::string e = build_error(desc_in(dir, R"({"lights": [{"type": "constant"},
        {"type": "envmap", "filename": "nothere.exr"}]})"));
    EXPECT_NE(e.find("scene.json: lights[1].filename: "), std::string::npos) << e;
    EXPECT_NE(e.find(dir.file("nothere.exr")), std::string::npos) << e;
    EXPECT_NE(e.find("not found"), std::string::npos) << e;
    // filename is required.
    e = build_error(desc_in(dir, R"({"lights": [{"type": "envmap"}]})"));
    EXPECT_EQ(e, "scene.json: lights[0]: missing required key 'filename'");
}

TEST(EnvmapErrors, CorruptFileNamesPathAndKey) {
    TempDir dir("pellucid_envmap_");
    for (const char* name : {"bad.exr", "bad.hdr"}) {
        std::ofstream(dir.file(name), std::ios::binary) << "this is not an image\n\x01\x02\x03";
        std::string e = build_error(desc_in(dir, std::string(R"({"lights": [{"type": "envmap", "filename": ")") + name + "\"}]}"));
        EXPECT_NE(e.find("scene.json: lights[0].filename: "), std::string::npos) << e;
        EXPECT_NE(e.find(dir.file(name)), std::string::npos) << e;
    }
    // A truncated EXR: a valid file cut in half.
    write_image_file(dir.file("full.exr"), test::asymmetric_envmap_image(64, 32));
    std::ifstream in(dir.file("full.exr"), std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(dir.file("cut.exr"), std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    std::string e = build_error(desc_in(dir, R"({"lights": [{"type": "envmap", "filename": "cut.exr"}]})"));
    EXPECT_NE(e.find("lights[0].filename: " + dir.file("cut.exr")), std::string::npos) << e;
}

TEST(EnvmapErrors, InvalidContentsAndParameters) {
    TempDir dir("pellucid_envmap_");
    Image img = test::asymmetric_envmap_image();
    img.pixel(3, 2)[1] = std::nanf("");
    write_image_file(dir.file("nan.exr"), img);
    std::string e = build_error(desc_in(dir, R"({"lights": [{"type": "envmap", "filename": "nan.exr"}]})"));
    EXPECT_NE(e.find("lights[0].filename: " + dir.file("nan.exr") + ": pixel (3, 2) has radiance nan"),
              std::string::npos) << e;
    img = test::asymmetric_envmap_image();
    img.pixel(0, 0)[0] = -1.f;
    write_image_file(dir.file("neg.exr"), img);
    e = build_error(desc_in(dir, R"({"lights": [{"type": "envmap", "filename": "neg.exr"}]})"));
    EXPECT_NE(e.find("pixel (0, 0) has radiance -1"), std::string::npos) << e;
    write_image_file(dir.file("tiny.exr"), Image(4, 2));
    e = build_error(desc_in(dir, R"({"lights": [{"type": "envmap", "filename": "tiny.exr"}]})"));
    EXPECT_NE(e.find("tiny.exr: the environment map is 4x2 pixels; it must be at least 2x3"), std::string::npos) << e;
    write_image_file(dir.file("ok.exr"), test::asymmetric_envmap_image());
    e = build_error(desc_in(dir, R"({"lights": [{"type": "envmap", "filename": "ok.exr", "scale": -2}]})"));
    EXPECT_NE(e.find("lights[0].scale: value -2"), std::string::npos) << e;
    e = build_error(desc_in(dir, R"({"lights": [{"type": "envmap", "filename": "ok.exr", "to_world": [{"scale": [1, 2, 1]}]}]})"));
    EXPECT_NE(e.find("lights[0].to_world: an envmap's transform must be a rotation"), std::string::npos) << e;
    e = build_error(desc_in(dir, R"({"lights": [{"type": "envmap", "filename": "ok.exr", "scael": 1}]})"));
    EXPECT_NE(e.find("lights[0].scael: unknown parameter"), std::string::npos) << e;
}

TEST(ZeroPowerLights, SkippedWithAWarningAndTheSceneRenders) {
    TempDir dir("pellucid_envmap_");
    write_image_file(dir.file("sky.exr"), test::asymmetric_envmap_image());
    write_image_file(dir.file("black.exr"), Image(8, 4));
    LogCapture log;
    auto scene = load_desc(desc_in(dir, R"({"film": {"width": 8, "height": 8}, "sampler": {"sample_count": 4},
        "camera": {"type": "perspective", "fov": 40,
                   "to_world": [{"look_at": {"origin": [0, 0, 4], "target": [0, 0, 0], "up": [0, 1, 0]}}]},
        "shapes": [{"type": "sphere", "emitter": {"type": "area", "radiance": 0}}],
        "lights": [{"type": "point", "position": [0, 3, 3], "intensity": 0},
                   {"type": "envmap", "filename": "sky.exr", "scale": 0},
                   {"type": "envmap", "filename": "black.exr"},
                   {"type": "spot", "intensity": [0, 0, 0]},
                   {"type": "directional", "irradiance": 0},
                   {"type": "constant", "radiance": 0},
                   {"type": "point", "position": [0, 3, 3], "intensity": 20}]})"));
    for (int i = 0; i < 6; ++i)
        EXPECT_TRUE(log.has("scene.json: lights[" + std::to_string(i) + "]: light has zero power; skipped")) << i;
    EXPECT_TRUE(log.has("scene.json: shapes[0].emitter: emitter has zero radiance; skipped"));
    ASSERT_EQ(scene->lights.size(), 1u);  // only the last point light
    EXPECT_TRUE(std::holds_alternative<PointLight>(scene->lights[0]));
    EXPECT_TRUE(scene->infinite_lights.empty());
    RenderResult r = render(*scene, RenderOptions{});
    double sum = 0;
    for (float v : r.image.data) sum += v;
    EXPECT_GT(sum, 0.0);  // the remaining light lights the sphere
    EXPECT_EQ(r.stats.invalid_samples, 0u);
}

class EnvmapRender : public ::testing::TestWithParam<std::string> {};

TEST_P(EnvmapRender, UniformMapFurnace) {
    // An envmap of constant radiance 1 around a white Lambertian sphere: every pixel is 1.
    TempDir dir("pellucid_envmap_");
    Image one(6, 4);
    std::fill(one.data.begin(), one.data.end(), 1.f);
    write_image_file(dir.file("one.exr"), one);
    auto scene = load_desc(desc_in(dir, R"({"film": {"width": 12, "height": 12}, "sampler": {"sample_count": 128, "seed": 3},
        "camera": {"type": "perspective", "fov": 40,
                   "to_world": [{"look_at": {"origin": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0]}}]},
        "integrator": {"type": "path", "strategy": ")" + GetParam() + R"("},
        "shapes": [{"type": "sphere", "radius": 1.5, "material": {"type": "lambertian", "reflectance": 1}}],
        "lights": [{"type": "envmap", "filename": "one.exr", "to_world": [{"rotate": {"axis": [0, 0, 1], "angle": 30}}]}]})"));
    RenderResult r = render(*scene, RenderOptions{});
    size_t n = r.image.data.size();
    double z = z_two_sided(test::sidak_alpha(0.01, int(n))), sum = 0, sum_var = 0;
    int fails = 0;
    for (size_t i = 0; i < n; ++i) {
        double d = std::fabs(r.image.data[i] - 1.0), s2 = r.variance.data[i] + 1e-12;
        fails += d / std::sqrt(s2) > z;
        sum += r.image.data[i];
        sum_var += r.variance.data[i];
    }
    EXPECT_EQ(fails, 0) << "pixels failing the per-pixel z-test at |z| > " << z;
    EXPECT_LT(std::fabs(sum / n - 1.0), z_two_sided(1e-4) * std::sqrt(sum_var) / n + 1e-6);
    EXPECT_EQ(r.stats.invalid_samples, 0u);
}
INSTANTIATE_TEST_SUITE_P(Strategies, EnvmapRender, ::testing::Values("mis", "nee", "bsdf"));

TEST(EnvmapRender, StrategiesAgreeUnderAnAsymmetricMap) {
    // BSDF sampling alone and light sampling alone (nee) estimate the same image as MIS: pixel by
    // pixel, |a − b| / sqrt(var a + var b) below the Šidák-corrected two-sided α = 0.01 bound.
    TempDir dir("pellucid_envmap_");
    write_image_file(dir.file("sky.exr"), test::asymmetric_envmap_image(16, 9));
    auto make = [&](const char* strategy) {
        return load_desc(desc_in(dir, std::string(R"({"film": {"width": 12, "height": 12}, "sampler": {"sample_count": 256, "seed": 5},
            "camera": {"type": "perspective", "fov": 35,
                       "to_world": [{"look_at": {"origin": [0, 1, 5], "target": [0, 0, 0], "up": [0, 1, 0]}}]},
            "integrator": {"type": "path", "max_depth": 3, "strategy": ")") + strategy + R"("},
            "shapes": [{"type": "sphere", "radius": 1.2, "material": {"type": "lambertian", "reflectance": [0.8, 0.5, 0.3]}}],
            "lights": [{"type": "envmap", "filename": "sky.exr", "to_world": [{"rotate": {"axis": [1, 1, 0], "angle": 50}}]}]})"));
    };
    RenderResult mis = render(*make("mis"), RenderOptions{});
    for (const char* other : {"bsdf", "nee"}) {
        RenderResult o = render(*make(other), RenderOptions{});
        size_t n = mis.image.data.size();
        double z = z_two_sided(test::sidak_alpha(0.01, int(2 * n)));
        int fails = 0;
        for (size_t i = 0; i < n; ++i) {
            double d = std::fabs(mis.image.data[i] - o.image.data[i]);
            double s = std::sqrt(mis.variance.data[i] + o.variance.data[i] + 1e-12);
            fails += d / s > z;
        }
        EXPECT_EQ(fails, 0) << other << " vs mis: pixels beyond |z| > " << z;
    }
}

TEST(Envmap, MitsubaXmlSceneBuildsTheSameLight) {
    // <emitter type="envmap"> from a Mitsuba 3 XML file builds the same light as the JSON form, with
    // the file resolved against the XML file's directory.
    TempDir dir("pellucid_envmap_");
    fs::create_directories(dir.file("tex"));
    write_image_file(dir.file("tex/sky.exr"), test::asymmetric_envmap_image());
    std::ofstream(dir.file("scene.xml")) << R"(<scene version="3.0.0">
  <emitter type="envmap"><string name="filename" value="tex/sky.exr"/><float name="scale" value="2"/>
    <transform name="to_world"><rotate x="1" angle="-90"/></transform></emitter>
</scene>)";
    auto xml = load_file(dir.file("scene.xml"));
    auto json = load_desc(desc_in(dir, R"({"lights": [{"type": "envmap", "filename": "tex/sky.exr", "scale": 2,
        "to_world": [{"rotate": {"axis": [1, 0, 0], "angle": -90}}]}]})"));
    ASSERT_EQ(xml->lights.size(), 1u);
    const auto& a = std::get<EnvmapLight>(xml->lights[0]);
    const auto& b = std::get<EnvmapLight>(json->lights[0]);
    PCG32 rng(4, 2);
    for (int i = 0; i < 100; ++i) {
        Vec3f d = square_to_uniform_sphere(rng.next_2d());
        EXPECT_EQ(a.Le(d), b.Le(d));
        EXPECT_EQ(a.pdf_li({}, d), b.pdf_li({}, d));
    }
}
