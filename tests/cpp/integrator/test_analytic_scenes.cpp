// Integrators on scenes with analytic answers (pbrt-v4 integrators_test.cpp; Nori test-furnace).
// Every test uses a fixed seed; per-pixel z-tests use a two-sided α = 0.01 with a Šidák correction
// over the pixels, and the image mean is tested at α = 1e-4 against its standard error.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "pellucid/api.h"
#include "pellucid/util/error.h"
#include "pellucid/scene/json_io.h"
#include "support/chi2.h"
#include "support/render_checks.h"
#include "support/scene_util.h"

using namespace pellucid;

using pellucid::test::LogCapture;
using pellucid::test::expect_constant_image;
using pellucid::test::kFrontCamera;
using pellucid::test::scene_from;
using pellucid::test::z_two_sided;


class AnalyticScenes : public ::testing::TestWithParam<std::string> {};

TEST_P(AnalyticScenes, WhiteFurnaceSphereRendersOne) {
    // A white Lambertian sphere under a constant environment of radiance 1: every pixel is 1.
    auto scene = scene_from(std::string("{") + kFrontCamera + R"(,
        "film": {"width": 24, "height": 24}, "sampler": {"sample_count": 256, "seed": 7},
        "integrator": {"type": "path", "strategy": ")" + GetParam() + R"("},
        "materials": {"white": {"type": "lambertian", "reflectance": 1.0}},
        "shapes": [{"type": "sphere", "radius": 1.5, "material": "white"}],
        "lights": [{"type": "constant", "radiance": 1.0}]})");
    RenderOptions o;
    expect_constant_image(render(*scene, o), 1.0, "furnace");
}

TEST_P(AnalyticScenes, ClosedSphereFromInside) {
    // Inside a closed sphere with albedo a and emission Le, radiance is Le/(1 − a) everywhere.
    const double a = 0.5, Le = 0.8;
    auto scene = scene_from(std::string(R"({"camera": {"type": "perspective", "fov": 60},
        "film": {"width": 20, "height": 20}, "sampler": {"sample_count": 256, "seed": 3},
        "integrator": {"type": "path", "rr_depth": 40, "strategy": ")") + GetParam() + R"("},
        "materials": {"m": {"type": "lambertian", "reflectance": 0.5}},
        "shapes": [{"type": "sphere", "radius": 2, "flip_normals": true, "material": "m",
                    "emitter": {"type": "area", "radiance": 0.8}}]})");
    RenderOptions o;
    expect_constant_image(render(*scene, o), Le / (1 - a), "closed sphere");
}

TEST_P(AnalyticScenes, ClosedMeshBoxFromInside) {
    // The same law on a closed cube built from triangles, light sampled by area on every face. A
    // mirroring scale keeps normals outward, so the emitter is two-sided. NEE near the cube's edges
    // samples light points at distance → 0 (G ∝ 1/d²): a heavy-tailed estimator whose per-pixel
    // sample variance is unreliable at 256 spp (over 20 seeds its image means spread 2.1× wider than
    // the film's variance predicts); 1024 spp makes the per-pixel test valid again.
    auto scene = scene_from(std::string(R"({"camera": {"type": "perspective", "fov": 60},
        "film": {"width": 20, "height": 20}, "sampler": {"sample_count": 1024, "seed": 5},
        "integrator": {"type": "path", "rr_depth": 40, "strategy": ")") + GetParam() + R"("},
        "materials": {"m": {"type": "lambertian", "reflectance": 0.25}},
        "shapes": [{"type": "cube", "to_world": [{"scale": -3}], "material": "m",
                    "emitter": {"type": "area", "radiance": 0.6, "two_sided": true}}]})");
    RenderOptions o;
    expect_constant_image(render(*scene, o), 0.6 / 0.75, "closed box");
}

TEST(RussianRoulette, UnbiasedInClosedSphere) {
    // Default RR (from depth 5, q = min(max β, 0.95)): the image mean still converges to Le/(1 − a).
    auto scene = scene_from(R"({"camera": {"type": "perspective", "fov": 60},
        "film": {"width": 16, "height": 16}, "sampler": {"sample_count": 1024, "seed": 11},
        "materials": {"m": {"type": "lambertian", "reflectance": 0.7}},
        "shapes": [{"type": "sphere", "radius": 2, "flip_normals": true, "material": "m",
                    "emitter": {"type": "area", "radiance": 0.3}}]})");
    RenderResult r = render(*scene, RenderOptions{});
    double sum = 0, sum_var = 0;
    for (size_t i = 0; i < r.image.data.size(); ++i) {
        sum += r.image.data[i];
        sum_var += r.variance.data[i];
    }
    double n = double(r.image.data.size()), mean = sum / n, se = std::sqrt(sum_var) / n;
    EXPECT_LT(std::fabs(mean - 0.3 / 0.3), z_two_sided(1e-4) * se) << "mean " << mean << " se " << se;
}

INSTANTIATE_TEST_SUITE_P(Strategies, AnalyticScenes, ::testing::Values("mis", "nee", "bsdf"));

TEST(Determinism, BitIdenticalAcrossThreadCounts) {
    auto scene = load_file(std::string(PELLUCID_SOURCE_DIR) + "/scenes/cornell_box.json");
    RenderOptions o;
    o.spp = 4;
    o.threads = 1;
    RenderResult a = render(*scene, o);
    o.threads = 2;
    RenderResult b = render(*scene, o);
    ASSERT_EQ(a.image.data.size(), b.image.data.size());
    EXPECT_EQ(0, std::memcmp(a.image.data.data(), b.image.data.data(), a.image.data.size() * sizeof(float)));
    o.seed = 1;
    RenderResult c = render(*scene, o);
    EXPECT_NE(0, std::memcmp(a.image.data.data(), c.image.data.data(), a.image.data.size() * sizeof(float)));
}

TEST(RenderBudget, TimeBudgetAndCancellationKeepWork) {
    // A small film, so that a pass takes a small part of the budget even under the sanitizers on a
    // slow 2-core machine (a 2-spp pass of the 256² Cornell box took 6 to 9 s there): the render then
    // runs several passes and the test sees the loop stop at the budget, not one pass's length.
    std::ifstream in(std::string(PELLUCID_SOURCE_DIR) + "/scenes/tests/tiny_box.json");
    std::stringstream text;
    text << in.rdbuf();
    const std::string tent = R"("filter": {"type": "tent"})";
    std::string splatting = text.str();
    ASSERT_NE(splatting.find(tent), std::string::npos);
    splatting.replace(splatting.find(tent), tent.size(), tent + R"(, "reconstruction": "splatting")");
    RenderOptions o;
    o.time_budget = 0.3;
    for (bool splat : {false, true}) {  // filter sampling, then splatting's 2-spp passes
        auto budgeted = scene_from(splat ? splatting : text.str());
        ASSERT_EQ(budgeted->film_splatting, splat);
        RenderResult r = render(*budgeted, o);
        EXPECT_GE(r.stats.spp, 1);
        EXPECT_LT(r.stats.seconds, 5.0);
    }
    auto scene = scene_from(text.str());
    std::atomic<bool> cancel{true};
    o = RenderOptions();
    o.cancel = &cancel;
    RenderResult c = render(*scene, o);
    EXPECT_TRUE(c.stats.cancelled);
}

class DeltaLights : public ::testing::TestWithParam<std::string> {};

TEST_P(DeltaLights, PointLightInsideDiffuseSphere) {
    // A point light of intensity I at the centre of a closed diffuse sphere of radius R and albedo a:
    // direct irradiance I/R² everywhere, so the radiance is (a/π)(I/R²)/(1 − a).
    const double a = 0.6, I = 5.0, R = 2.0;
    auto scene = scene_from(std::string(R"({"camera": {"type": "perspective", "fov": 60},
        "film": {"width": 16, "height": 16}, "sampler": {"sample_count": 128, "seed": 9},
        "integrator": {"type": "path", "rr_depth": 40, "light_selection": ")") + GetParam() + R"("},
        "materials": {"m": {"type": "lambertian", "reflectance": 0.6}},
        "shapes": [{"type": "sphere", "radius": 2, "material": "m"}],
        "lights": [{"type": "point", "position": [0.0, 0.0, 0.0], "intensity": 5}]})");
    expect_constant_image(render(*scene, RenderOptions{}), (a / M_PI) * (I / (R * R)) / (1 - a), "point light");
}

TEST_P(DeltaLights, MixedLightsAgreeAcrossSelection) {
    // Selection by power or uniformly changes only the noise. Inside a closed sphere the constant
    // environment and the directional light are fully occluded, so only the point light counts.
    const double a = 0.5, I = 3.0, R = 1.5;
    auto scene = scene_from(std::string(R"({"camera": {"type": "perspective", "fov": 50},
        "film": {"width": 12, "height": 12}, "sampler": {"sample_count": 128, "seed": 4},
        "integrator": {"type": "path", "rr_depth": 40, "light_selection": ")") + GetParam() + R"("},
        "shapes": [{"type": "sphere", "radius": 1.5, "material": {"type": "lambertian", "reflectance": 0.5}}],
        "lights": [{"type": "point", "position": [0, 0, 0], "intensity": 3},
                   {"type": "constant", "radiance": 0.2},
                   {"type": "directional", "direction": [0, -1, 0], "irradiance": 4}]})");
    expect_constant_image(render(*scene, RenderOptions{}), (a / M_PI) * (I / (R * R)) / (1 - a), "mixed lights");
}

INSTANTIATE_TEST_SUITE_P(Selection, DeltaLights, ::testing::Values("balanced", "power", "uniform"));

TEST(SceneErrors, LightParameters) {
    SceneDesc d;
    d.source = "s.json";
    d.root = parse_json(R"({"lights": [{"type": "spot", "cutoff_angle": 120}]})", "s.json");
    try {
        load_desc(d);
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()), "s.json: lights[0].cutoff_angle: value 120 is out of range [0.001, 90]");
    }
}

TEST(Strategies, AgreePixelByPixelOnGlossyAndDiffuse) {
    // bsdf, nee, mis and direct estimate the same integral: on a small scene with glossy and diffuse
    // surfaces under an area light and an environment, every pair agrees within noise under a
    // per-pixel z-test with both variances (α = 0.01, Šidák over the pixels, ≥ 99.75 % must pass).
    // "direct" is compared with mis restricted to max_depth 2, which is its definition. The gold is
    // α = 0.35: with α = 0.15, pure light sampling of the constant environment at grazing angles
    // lands in the lobe so rarely that its per-pixel sample variance is unreliable (skewed, heavy
    // tail); the BxDF's eval and sample agree there (tests/python/test_bxdf_api.py, albedo).
    // bsdf renders 2048 spp: its hits on the small light are rare and large, and at 512 spp its
    // pixels' own variances understate them, which mis, whose light takes every NEE sample (the
    // constant environment takes none under mis), no longer hides (mis against bsdf at 512 spp
    // failed on 9 seeds of 9, with 5 to 24 channels; at 2048, at most 3).
    auto make = [](const std::string& strategy, int max_depth) {
        const int spp = strategy == "bsdf" ? 2048 : 512;
        return scene_from(std::string(R"({"camera": {"type": "perspective", "fov": 45,
            "to_world": [{"look_at": {"origin": [0, 1.5, 4], "target": [0, 0, 0], "up": [0, 1, 0]}}]},
            "film": {"width": 24, "height": 18}, "sampler": {"sample_count": )") + std::to_string(spp) +
            R"(, "seed": 21},
            "integrator": {"type": "path", "max_depth": )" + std::to_string(max_depth) +
            R"(, "strategy": ")" + strategy + R"("},
            "materials": {"gold": {"type": "rough_conductor", "alpha": 0.35, "material": "Au"},
                          "white": {"type": "lambertian", "reflectance": 0.7}},
            "shapes": [{"type": "sphere", "radius": 0.8, "material": "gold"},
                       {"type": "rectangle", "material": "white",
                        "to_world": [{"scale": 3}, {"rotate": {"axis": [1, 0, 0], "angle": -90}}, {"translate": [0, -0.8, 0]}]},
                       {"type": "rectangle", "to_world": [{"scale": 0.5}, {"rotate": {"axis": [1, 0, 0], "angle": 90}}, {"translate": [0.5, 2.5, 0.5]}],
                        "emitter": {"type": "area", "radiance": 8}}],
            "lights": [{"type": "constant", "radiance": 0.3}]})");
    };
    auto compare = [](const RenderResult& a, const RenderResult& b, const char* what) {
        size_t n = a.image.data.size();
        double z_max = z_two_sided(test::sidak_alpha(0.01, int(n)));
        int fails = 0;
        std::ostringstream worst;
        for (size_t i = 0; i < n; ++i) {
            double s2 = a.variance.data[i] + b.variance.data[i] + 1e-12;
            double z = (a.image.data[i] - b.image.data[i]) / std::sqrt(s2);
            if (std::fabs(z) > z_max) {
                ++fails;
                worst << " [px " << i / 3 << " ch " << i % 3 << " z=" << z << " a=" << a.image.data[i] << " b=" << b.image.data[i] << "]";
            }
        }
        EXPECT_LE(fails, int(0.0025 * double(n))) << what << worst.str();
    };
    RenderResult mis = render(*make("mis", 4), RenderOptions{});
    compare(mis, render(*make("nee", 4), RenderOptions{}), "mis vs nee");
    compare(mis, render(*make("bsdf", 4), RenderOptions{}), "mis vs bsdf");
    compare(render(*make("mis", 2), RenderOptions{}), render(*make("direct", -1), RenderOptions{}), "mis(2) vs direct");
}
