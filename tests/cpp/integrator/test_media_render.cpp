// The path tracer in participating media, on scenes with analytic answers (docs/media.md). Each
// image is checked per pixel by expect_constant_image: a Šidák-corrected two-sided z-test at
// α = 0.01 against the film's variance, plus the image mean at α = 1e-4; fixed seeds.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "pellucid/integrator/integrator.h"
#include "support/render_checks.h"
#include "support/scene_util.h"

using namespace pellucid;
using pellucid::test::expect_constant_image;
using pellucid::test::kFrontCamera;
using pellucid::test::scene_from;

namespace {
RenderResult render(const Scene& scene) {
    RenderOptions o;
    return make_integrator(scene)->render(scene, o);
}
}  // namespace

TEST(MediaRender, SlabTransmittanceIsBeerLambert) {
    // A purely absorbing slab of thickness 1 (σt = 1.2, null boundaries) in front of a constant
    // environment of radiance 1, seen head-on through a 2° field of view: exp(−1.2). Paths through
    // the slab at the field's edge are 1.5e-4 longer, far below the noise.
    auto scene = scene_from(R"({"camera": {"type": "perspective", "fov": 2,
            "to_world": [{"look_at": {"origin": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0]}}]},
        "film": {"width": 12, "height": 12}, "sampler": {"sample_count": 256, "seed": 5},
        "media": {"ink": {"type": "homogeneous", "sigma_a": 1.2, "sigma_s": 0}},
        "shapes": [{"type": "cube", "material": {"type": "null"}, "interior": "ink",
                    "to_world": [{"scale": [5, 5, 0.5]}]}],
        "lights": [{"type": "constant", "radiance": 1}]})");
    expect_constant_image(render(*scene), std::exp(-1.2), "slab");
}

TEST(MediaRender, AlbedoOneMediumInAWhiteFurnaceIsOne) {
    // A scattering medium of albedo 1 (chromatic σt, hg g = 0.6) bounded by a null sphere, and the
    // same inside an index-matched dielectric sphere, under a constant environment of radiance 1:
    // every pixel is 1.
    for (const char* boundary : {R"({"type": "null"})", R"({"type": "dielectric", "int_ior": 1.0, "ext_ior": 1.0})"}) {
        auto scene = scene_from(std::string("{") + kFrontCamera + R"(,
            "film": {"width": 16, "height": 16}, "sampler": {"sample_count": 256, "seed": 11},
            "media": {"cloud": {"type": "homogeneous", "sigma_s": [0.5, 1.5, 3.0], "sigma_a": 0,
                                "phase": {"type": "hg", "g": 0.6}}},
            "shapes": [{"type": "sphere", "radius": 1.5, "interior": "cloud", "material": )" + boundary + R"(}],
            "lights": [{"type": "constant", "radiance": 1}]})");
        expect_constant_image(render(*scene), 1.0, std::string("furnace, boundary ") + boundary);
    }
}

TEST(MediaRender, InfiniteEmittingMediumIsLeOverOneMinusAlbedo) {
    // The camera inside an infinite medium of albedo a that emits Le: Le/(1 − a) in every direction.
    const double a = 0.6, Le = 0.5;
    auto scene = scene_from(R"({"camera": {"type": "perspective", "fov": 60, "medium": "glow"},
        "film": {"width": 12, "height": 12}, "sampler": {"sample_count": 256, "seed": 2},
        "integrator": {"type": "path", "rr_depth": 40},
        "media": {"glow": {"type": "homogeneous", "sigma_t": 0.8, "albedo": 0.6, "emission": 0.5}}})");
    expect_constant_image(render(*scene), Le / (1 - a), "infinite emitting medium");
}

TEST(MediaRender, ImageIsTheSameAtOneAndTwoThreads) {
    auto scene = scene_from(std::string("{") + kFrontCamera + R"(,
        "film": {"width": 16, "height": 16}, "sampler": {"sample_count": 8, "seed": 4},
        "media": {"fog": {"type": "homogeneous", "sigma_t": 1.0, "albedo": [0.9, 0.7, 0.5]}},
        "shapes": [{"type": "sphere", "radius": 1.2, "interior": "fog", "material": {"type": "null"}},
                   {"type": "rectangle", "material": {"type": "lambertian", "reflectance": 0.5},
                    "to_world": [{"scale": 4}, {"translate": [0, 0, -2]}]}],
        "lights": [{"type": "point", "position": [1, 2, 3], "intensity": 10}, {"type": "constant", "radiance": 0.3}]})");
    RenderOptions one, two;
    one.threads = 1;
    two.threads = 2;
    const RenderResult a = make_integrator(*scene)->render(*scene, one), b = make_integrator(*scene)->render(*scene, two);
    ASSERT_EQ(a.image.data.size(), b.image.data.size());
    EXPECT_EQ(a.image.data, b.image.data);
    double sum = 0;
    for (float v : a.image.data) sum += v;
    EXPECT_GT(sum, 0.0);
}
