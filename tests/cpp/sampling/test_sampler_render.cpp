// Rendering with the sobol sampler: still unbiased on scenes with analytic answers, deterministic
// across thread counts, and lower error than independent sampling at equal spp.
// z-tests: two-sided α = 0.01 Šidák-corrected over the pixels for the per-pixel test, α = 1e-4 for the
// image mean. With sobol the film's per-pixel variance (Welford over a pixel's samples) overestimates
// the variance of the mean (the samples are negatively correlated), so these tests are conservative.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>

#include "pellucid/api.h"
#include "pellucid/scene/mitsuba_xml.h"
#include "pellucid/util/error.h"
#include "support/chi2.h"
#include "support/render_checks.h"
#include "support/scene_util.h"

using namespace pellucid;
using pellucid::test::expect_constant_image;
using pellucid::test::kFrontCamera;
using pellucid::test::scene_from;
using pellucid::test::z_two_sided;


class SobolAnalyticScenes : public ::testing::TestWithParam<std::string> {};

TEST_P(SobolAnalyticScenes, WhiteFurnaceSphereRendersOne) {
    auto scene = scene_from(std::string("{") + kFrontCamera + R"(,
        "film": {"width": 16, "height": 16}, "sampler": {"type": "sobol", "sample_count": 128, "seed": 7},
        "integrator": {"type": "path", "strategy": ")" + GetParam() + R"("},
        "materials": {"white": {"type": "lambertian", "reflectance": 1.0}},
        "shapes": [{"type": "sphere", "radius": 1.5, "material": "white"}],
        "lights": [{"type": "constant", "radiance": 1.0}]})");
    expect_constant_image(render(*scene, RenderOptions{}), 1.0, "furnace " + GetParam());
}

TEST_P(SobolAnalyticScenes, ClosedSphereFromInside) {
    // Le/(1 − a); rr_depth 40 keeps paths long enough to run past the 64 Sobol dimensions (9
    // vertices) into the PCG32 fallback.
    auto scene = scene_from(std::string(R"({"camera": {"type": "perspective", "fov": 60},
        "film": {"width": 16, "height": 16}, "sampler": {"type": "sobol", "sample_count": 128, "seed": 3},
        "integrator": {"type": "path", "rr_depth": 40, "strategy": ")") + GetParam() + R"("},
        "materials": {"m": {"type": "lambertian", "reflectance": 0.5}},
        "shapes": [{"type": "sphere", "radius": 2, "flip_normals": true, "material": "m",
                    "emitter": {"type": "area", "radiance": 0.8}}]})");
    expect_constant_image(render(*scene, RenderOptions{}), 0.8 / (1 - 0.5), "closed sphere " + GetParam());
}

INSTANTIATE_TEST_SUITE_P(Strategies, SobolAnalyticScenes, ::testing::Values("mis", "nee", "bsdf"));

TEST(SobolRender, BitIdenticalAcrossThreadCounts) {
    auto scene = load_file(std::string(PELLUCID_SOURCE_DIR) + "/scenes/cornell_box.json");
    RenderOptions o;
    o.spp = 4;
    o.sampler = "sobol";
    o.threads = 1;
    RenderResult a = render(*scene, o);
    o.threads = 2;
    RenderResult b = render(*scene, o);
    ASSERT_EQ(a.image.data.size(), b.image.data.size());
    const size_t bytes = a.image.data.size() * sizeof(float);
    EXPECT_EQ(0, std::memcmp(a.image.data.data(), b.image.data.data(), bytes));
    o.seed = 1;
    EXPECT_NE(0, std::memcmp(a.image.data.data(), render(*scene, o).image.data.data(), bytes)) << "seed ignored";
    o.seed = -1;
    o.sampler = "independent";
    EXPECT_NE(0, std::memcmp(a.image.data.data(), render(*scene, o).image.data.data(), bytes)) << "sampler ignored";
}

TEST(SobolRender, UnknownSamplerIsAnError) {
    auto scene = load_file(std::string(PELLUCID_SOURCE_DIR) + "/scenes/cornell_box.json");
    RenderOptions o;
    o.sampler = "halton";
    try {
        render(*scene, o);
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("unknown sampler 'halton' (known: independent, sobol)"), std::string::npos)
            << e.what();
    }
    try {
        scene_from(R"({"sampler": {"type": "sobl"}})");
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("sampler.type"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("'sobl'"), std::string::npos) << e.what();
    }
}

TEST(SobolRender, MitsubaLowDiscrepancySamplersImportAsSobol) {
    for (const char* type : {"independent", "stratified", "multijitter", "orthogonal", "ldsampler", "low_discrepancy"}) {
        test::LogCapture log;
        SceneDesc d = parse_mitsuba_xml(std::string(R"(<scene version="3.0.0"><sensor type="perspective"><sampler type=")") +
                                            type + R"("><integer name="sample_count" value="8"/><integer name="seed" value="2"/>
            </sampler></sensor></scene>)",
                                        "scene.xml", ".", false);
        const Node* s = d.root.find("sampler");
        ASSERT_NE(s, nullptr) << type;
        ASSERT_NE(s->find("type"), nullptr) << type;
        EXPECT_EQ(s->find("type")->as_string(), std::string(type) == "independent" ? "independent" : "sobol") << type;
        auto scene = load_desc(d);
        EXPECT_EQ(scene->sampler, std::string(type) == "independent" ? SamplerType::Independent : SamplerType::Sobol);
        EXPECT_EQ(scene->spp, 8);
        EXPECT_EQ(scene->seed, 2u);
        EXPECT_FALSE(log.has("sampler")) << type;  // a documented difference in definition, no warning
    }
}

TEST(SobolRender, LowerErrorThanIndependentAtEqualSpp) {
    // Direct light from a spherical area light on a diffuse floor (soft shadow of a sphere): the light
    // and BSDF 2D samples of each pixel are stratified with sobol. MSE against a 2048-spp independent
    // reference, over 48×48 pixels at 32 spp. The reference's own variance adds 1/64 of the
    // independent MSE to both; each MSE is known to a few percent (2304 pixels × 3 channels), so a
    // ratio below 0.5 is far outside noise (measured: 0.11).
    auto make = [](const char* type, int spp, int seed) {
        return scene_from(std::string(R"({"camera": {"type": "perspective", "fov": 50,
            "to_world": [{"look_at": {"origin": [0, 4, 4], "target": [0, 0, 0], "up": [0, 1, 0]}}]},
            "film": {"width": 48, "height": 48, "filter": {"type": "box"}},
            "sampler": {"type": ")") + type + R"(", "sample_count": )" + std::to_string(spp) +
                                R"(, "seed": )" + std::to_string(seed) + R"(},
            "integrator": {"type": "path", "max_depth": 3},
            "materials": {"m": {"type": "lambertian", "reflectance": 0.6}},
            "shapes": [{"type": "rectangle", "to_world": [{"scale": 3}, {"rotate": {"axis": [1, 0, 0], "angle": -90}}],
                        "material": "m"},
                       {"type": "sphere", "center": [0, 0.6, 0], "radius": 0.5, "material": "m"},
                       {"type": "sphere", "center": [0.8, 2.2, 0.3], "radius": 0.5,
                        "emitter": {"type": "area", "radiance": 4}}]})");
    };
    RenderResult ref = render(*make("independent", 2048, 99), RenderOptions{});
    auto mse = [&](const RenderResult& r) {
        double s = 0;
        for (size_t i = 0; i < r.image.data.size(); ++i) s += std::pow(double(r.image.data[i]) - ref.image.data[i], 2);
        return s / double(r.image.data.size());
    };
    double mi = mse(render(*make("independent", 32, 1), RenderOptions{}));
    double ms = mse(render(*make("sobol", 32, 1), RenderOptions{}));
    std::printf("[ mse ] independent %.4g sobol %.4g ratio %.3f\n", mi, ms, ms / mi);
    EXPECT_LT(ms, 0.5 * mi) << "sobol MSE " << ms << " vs independent " << mi;
}
