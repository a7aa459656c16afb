// The lane kernel (integrator/path_lanes.h) against the general path tracer, on analytic scenes,
// and on which scenes it takes.
// SPDX-License-Identifier: Apache-2.0
//
// The kernel's images are not bit-identical to the general loop's (different warps of the same
// random numbers), so agreement is statistical: a per-pixel z-test of two independent renders
// (different seeds) with each pixel's own variance, on films that sample the filter (a splatting
// film's pixels share samples, so their z values are correlated). Under agreement |z| > 3.29
// (two-sided α = 0.001) in about 0.1 % of the pixel channels; the tests fail above 1 %. They also
// fail on a mean z beyond ±4 standard errors (α ≈ 6e-5): a bias of a few tenths of a standard
// deviation per pixel, e.g. a MIS weight lost on one strategy, shifts the mean long before single
// pixels fail. The mean is over the green channel only, one value per pixel, since the three
// channels of a pixel come from the same paths.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>

#include "pellucid/api.h"
#include "pellucid/integrator/path_lanes.h"
#include "pellucid/scene/json_io.h"
#include "support/render_checks.h"
#include "support/scene_util.h"

using namespace pellucid;
using pellucid::test::expect_constant_image;
using pellucid::test::scene_from;

namespace {
std::shared_ptr<const Scene> cornell(bool lanes, const std::string& strategy = "mis", int max_depth = 8,
                                     int rr_depth = 5) {
    SceneDesc desc = read_json_file(std::string(PELLUCID_SOURCE_DIR) + "/scenes/cornell_box.json");
    Node integrator = Node::object();
    integrator.set("type", Node::string("path"));
    integrator.set("lanes", Node::boolean(lanes));
    integrator.set("strategy", Node::string(strategy));
    integrator.set("max_depth", Node::number(max_depth, true));
    integrator.set("rr_depth", Node::number(rr_depth, true));
    desc.root.set("integrator", integrator);
    Node film = *desc.root.find("film");
    film.set("width", Node::number(40, true));
    film.set("height", Node::number(40, true));
    film.set("reconstruction", Node::string("filter_sampling"));
    desc.root.set("film", film);
    return load_desc(desc);
}

/// Per-pixel z-test of a against b (see the top of this file).
void expect_agreement(const RenderResult& a, const RenderResult& b, const std::string& what) {
    ASSERT_EQ(a.image.data.size(), b.image.data.size());
    size_t n_all = 0, tail = 0, n = 0;
    double sum = 0, sum2 = 0;
    for (size_t i = 0; i < a.image.data.size(); ++i) {
        const double v = double(a.variance.data[i]) + double(b.variance.data[i]);
        if (!(v > 0.0)) {
            EXPECT_EQ(a.image.data[i], b.image.data[i]) << what << ": noiseless channel " << i;
            continue;
        }
        const double z = (double(a.image.data[i]) - double(b.image.data[i])) / std::sqrt(v);
        ++n_all;
        tail += std::fabs(z) > 3.29;
        if (i % 3 != 1) continue;  // the mean: green only
        ++n;
        sum += z;
        sum2 += z * z;
    }
    ASSERT_GT(n, 0u);
    const double mean = sum / double(n), sd = std::sqrt(std::max(0.0, sum2 / double(n) - mean * mean));
    EXPECT_LT(double(tail) / double(n_all), 0.01) << what << ": pixel channels with |z| > 3.29";
    EXPECT_LT(std::fabs(mean), 4.0 * sd / std::sqrt(double(n)) + 1e-3) << what << ": mean z " << mean;
    EXPECT_EQ(a.stats.invalid_samples, 0u) << what;
}

RenderResult render_with(const Scene& s, int spp, int64_t seed, const char* sampler = "independent", int threads = 2) {
    RenderOptions o;
    o.spp = spp;
    o.seed = seed;
    o.threads = threads;
    o.sampler = sampler;
    return render(s, o);
}
}  // namespace

TEST(PathLanes, TakesTheCornellBox) {
    auto s = cornell(true);
    std::string why;
    EXPECT_NE(make_lane_scene(*s, s->integrator, &why), nullptr) << why;
}

TEST(PathLanes, AgreesWithTheGeneralLoopOnTheCornellBox) {
    // Both samplers; every strategy ("direct": paths of two segments, emission and direct light
    // only, where a wrong MIS weight or light pdf is not diluted by indirect light; "nee" and
    // "bsdf" each leave one of the two estimators alone); and roulette from the first bounce with
    // unbounded depth.
    struct Case {
        const char* strategy;
        int max_depth, rr_depth;
        const char* sampler;
    };
    for (const Case& c : {Case{"mis", 8, 5, "independent"}, Case{"mis", 8, 5, "sobol"}, Case{"direct", 8, 5, "independent"},
                          Case{"nee", 8, 5, "independent"}, Case{"bsdf", 8, 5, "independent"},
                          Case{"mis", -1, 1, "independent"}}) {
        const std::string what = std::string(c.strategy) + " max_depth " + std::to_string(c.max_depth) + " rr_depth " +
                                 std::to_string(c.rr_depth) + " " + c.sampler;
        auto lanes = cornell(true, c.strategy, c.max_depth, c.rr_depth), general = cornell(false, c.strategy, c.max_depth, c.rr_depth);
        ASSERT_NE(make_lane_scene(*lanes, lanes->integrator), nullptr) << what;
        expect_agreement(render_with(*lanes, 256, 11, c.sampler), render_with(*general, 256, 12, c.sampler), what);
    }
}

TEST(PathLanes, AgreesWithManyEmittersOfUnequalPower) {
    // Three area lights of unequal power (a 2-triangle rectangle, a 12-triangle cube, a 2-triangle
    // rectangle): 16 emitting triangles, picked by power then area through the kernel's binary
    // search, one of them one-sided and facing away from part of the scene.
    const std::string json = std::string(R"({"camera": {"type": "perspective", "fov": 50,
        "to_world": [{"look_at": {"origin": [0, 1, 6], "target": [0, 0.5, 0], "up": [0, 1, 0]}}]},
        "film": {"width": 32, "height": 32},
        "integrator": {"type": "path", "max_depth": 6, "lanes": LANES},
        "materials": {"floor": {"type": "lambertian", "reflectance": [0.7, 0.6, 0.5]},
                      "dim": {"type": "lambertian", "reflectance": 0.2}},
        "shapes": [{"type": "rectangle", "material": "floor", "to_world": [{"scale": 4}, {"rotate": {"axis": [1, 0, 0], "angle": -90}}]},
                   {"type": "rectangle", "material": "dim", "to_world": [{"scale": 0.5}, {"rotate": {"axis": [1, 0, 0], "angle": 90}}, {"translate": [-1, 2.5, 0]}],
                    "emitter": {"type": "area", "radiance": [6, 5, 4]}},
                   {"type": "cube", "material": "dim", "to_world": [{"scale": 0.3}, {"translate": [1.2, 0.8, -0.5]}],
                    "emitter": {"type": "area", "radiance": [1, 2, 3]}},
                   {"type": "rectangle", "material": "dim", "to_world": [{"scale": 0.2}, {"rotate": {"axis": [0, 1, 0], "angle": 30}}, {"translate": [0, 0.6, 1]}],
                    "emitter": {"type": "area", "radiance": 20}}]})");
    auto make = [&](bool lanes) {
        std::string j = json;
        j.replace(j.find("LANES"), 5, lanes ? "true" : "false");
        return scene_from(j);
    };
    auto lanes = make(true), general = make(false);
    ASSERT_NE(make_lane_scene(*lanes, lanes->integrator), nullptr);
    expect_agreement(render_with(*lanes, 512, 21), render_with(*general, 512, 22), "three lights");
}

TEST(PathLanes, ClosedBoxFromInside) {
    // Inside a closed box with albedo a and emission Le everywhere, radiance is Le/(1 − a): here on
    // one-sided emitters facing inward (flip_normals), with unbounded depth and roulette.
    auto scene = scene_from(R"({"camera": {"type": "perspective", "fov": 60},
        "film": {"width": 20, "height": 20}, "sampler": {"sample_count": 1024, "seed": 9},
        "integrator": {"type": "path", "rr_depth": 3},
        "materials": {"m": {"type": "lambertian", "reflectance": 0.4}},
        "shapes": [{"type": "cube", "to_world": [{"scale": 3}], "flip_normals": true, "material": "m",
                    "emitter": {"type": "area", "radiance": 0.9}}]})");
    std::string why;
    ASSERT_NE(make_lane_scene(*scene, scene->integrator, &why), nullptr) << why;
    expect_constant_image(render(*scene, RenderOptions{}), 0.9 / 0.6, "closed box (lanes)");
}

TEST(PathLanes, SameImageAtAnyThreadCount) {
    auto s = cornell(true);
    for (const char* sampler : {"independent", "sobol"}) {
        RenderResult a = render_with(*s, 8, 3, sampler, 1), b = render_with(*s, 8, 3, sampler, 2);
        ASSERT_EQ(a.image.data.size(), b.image.data.size());
        EXPECT_EQ(0, std::memcmp(a.image.data.data(), b.image.data.data(), a.image.data.size() * sizeof(float))) << sampler;
        EXPECT_EQ(0, std::memcmp(a.variance.data.data(), b.variance.data.data(), a.variance.data.size() * sizeof(float)))
            << sampler;
    }
}

TEST(PathLanes, LeavesScenesThatNeedMoreToTheGeneralLoop) {
    // Each scene needs one thing the kernel does not model; the reason names it.
    const std::string base = R"("camera": {"type": "perspective"}, "integrator": {"type": "path"},)";
    struct Case {
        std::string scene, reason;
    };
    const Case cases[] = {
        {R"("materials": {"m": {"type": "plastic"}}, "shapes": [{"type": "rectangle", "material": "m",
            "emitter": {"type": "area", "radiance": 1}}])", "material 'm' is not lambertian"},
        {R"("materials": {"m": {"type": "lambertian"}}, "shapes": [{"type": "sphere", "material": "m",
            "emitter": {"type": "area", "radiance": 1}}])", "spherical area light"},
        {R"("materials": {"m": {"type": "lambertian"}}, "shapes": [{"type": "sphere", "material": "m"},
            {"type": "rectangle", "material": "m", "emitter": {"type": "area", "radiance": 1}}])", "is a sphere"},
        {R"("materials": {"m": {"type": "lambertian"}}, "shapes": [{"type": "rectangle", "material": "m"}],
            "lights": [{"type": "constant", "radiance": 1}])", "infinite light"},
        {R"("materials": {"m": {"type": "lambertian"}}, "shapes": [{"type": "rectangle", "material": "m"}],
            "lights": [{"type": "point", "position": [0, 0, 1], "intensity": 1}])", "other than an area light"},
        {R"("materials": {"m": {"type": "lambertian"}}, "shapes": [{"type": "rectangle", "material": "m"}])", "no lights"},
        {R"("materials": {"m": {"type": "lambertian", "two_sided": false}}, "shapes": [{"type": "rectangle",
            "material": "m", "emitter": {"type": "area", "radiance": 1}}])", "one-sided material"},
    };
    for (const Case& c : cases) {
        auto s = scene_from("{" + base + c.scene + "}");
        std::string why;
        EXPECT_EQ(make_lane_scene(*s, s->integrator, &why), nullptr) << c.scene;
        EXPECT_NE(why.find(c.reason), std::string::npos) << "reason '" << why << "' for " << c.scene;
    }
}
