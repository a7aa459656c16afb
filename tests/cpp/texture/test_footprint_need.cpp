// Which scenes need pixel footprints (Scene::needs_footprints, material_reads_footprint,
// texture_reads_footprint), and that skipping them changes no bit where they are not needed.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "pellucid/api.h"
#include "pellucid/texture/texture_system.h"
#include "support/scene_util.h"
#include "support/temp_dir.h"

namespace pellucid::test {
namespace {

// A 3×3 random RGB float image at `path` (an in-memory texture: bilinear lookups read no MIP level).
void write_small_image(const std::string& path) {
    std::vector<float> px(27);
    for (size_t i = 0; i < px.size(); ++i) px[i] = float((i * 37) % 11) / 11.f;
    write_test_image(path, 3, 3, 3, 32, px.data());
}

// A small splatting scene: a textured floor (material `floor`, given as JSON), a smooth glass
// sphere (a delta bounce, which carries ray differentials on where footprints are needed) and a
// rough plastic sphere, under an area light and a constant environment.
std::string scene_json(const std::string& floor) {
    return R"({
      "camera": {"type": "perspective", "fov": 45,
                 "to_world": [{"look_at": {"origin": [0, 1.5, 4], "target": [0, 0.3, 0], "up": [0, 1, 0]}}]},
      "film": {"width": 40, "height": 32, "filter": {"type": "gaussian", "stddev": 0.5, "shift": true},
               "reconstruction": "splatting"},
      "sampler": {"type": "independent", "sample_count": 4, "seed": 3},
      "integrator": {"type": "path", "max_depth": 6},
      "materials": {
        "floor": )" + floor + R"(,
        "glass": {"type": "dielectric", "int_ior": 1.5},
        "plastic": {"type": "rough_plastic", "alpha": 0.2, "diffuse_reflectance": [0.6, 0.3, 0.2]},
        "white": {"type": "lambertian", "reflectance": 0.8}
      },
      "shapes": [
        {"type": "rectangle", "material": "floor", "to_world": [{"scale": 4}, {"rotate": {"axis": [1, 0, 0], "angle": -90}}]},
        {"type": "sphere", "center": [-0.6, 0.5, 0], "radius": 0.5, "material": "glass"},
        {"type": "sphere", "center": [0.7, 0.4, 0.3], "radius": 0.4, "material": "plastic"},
        {"type": "rectangle", "material": "white", "emitter": {"type": "area", "radiance": 6},
         "to_world": [{"scale": 0.5}, {"rotate": {"axis": [1, 0, 0], "angle": 90}}, {"translate": [0, 2.5, 0]}]}
      ],
      "lights": [{"type": "constant", "radiance": 0.3}]
    })";
}

struct Case {
    const char* what;
    std::string floor;
    bool textures, footprints;
};

std::vector<Case> cases() {
    const std::string img = R"({"type": "image", "filename": "img.exr", "filter": ")";
    return {
        {"constant", R"({"type": "lambertian", "reflectance": 0.5})", false, false},
        {"bilinear image", R"({"type": "lambertian", "reflectance": )" + img + R"(bilinear"}})", true, false},
        {"nearest image", R"({"type": "lambertian", "reflectance": )" + img + R"(nearest"}})", true, false},
        {"trilinear image", R"({"type": "lambertian", "reflectance": )" + img + R"(trilinear"}})", true, true},
        {"point-sampled checkerboard",
         R"({"type": "lambertian", "reflectance": {"type": "checkerboard", "filtered": false, "to_uv": [{"scale": [9, 9, 1]}]}})",
         true, false},
        {"filtered checkerboard",
         R"({"type": "lambertian", "reflectance": {"type": "checkerboard", "to_uv": [{"scale": [9, 9, 1]}]}})", true, true},
        {"Mitsuba bump on a bilinear image",
         R"({"type": "lambertian", "reflectance": 0.5, "bump_map": )" + img +
             R"(bilinear"}, "bump_scale": 0.05, "bump_model": "mitsuba"})",
         true, false},
        {"footprint bump on a bilinear image",
         R"({"type": "lambertian", "reflectance": 0.5, "bump_map": )" + img + R"(bilinear"}, "bump_scale": 0.05})", true,
         true},
    };
}

// Each case's flags: textures read, and footprints needed exactly where a texture or bump step
// reads them.
TEST(FootprintNeed, FollowsTheTexturesAndBumpModels) {
    const TempDir tmp("pellucid_footprint_");
    write_small_image(tmp.file("img.exr"));
    for (const Case& c : cases()) {
        const auto scene = scene_from(scene_json(c.floor), tmp.path().string());
        EXPECT_EQ(scene->has_textures, c.textures) << c.what;
        EXPECT_EQ(scene->needs_footprints, c.footprints) << c.what;
    }
}

// Where no material reads footprints, rendering with them (the flag forced on) gives the image the
// renderer gives without them, bit for bit, on every case above; where one does, the two differ
// (so the comparison sees the footprints at all). 4 spp at 40×32, one thread and two.
TEST(FootprintNeed, SkippingThemChangesNoBitWhereNoneIsRead) {
    const TempDir tmp("pellucid_footprint_");
    write_small_image(tmp.file("img.exr"));
    for (const Case& c : cases()) {
        if (!c.textures) continue;
        const auto scene = scene_from(scene_json(c.floor), tmp.path().string());
        Scene& s = const_cast<Scene&>(*scene);
        for (int threads : {1, 2}) {
            RenderOptions o;
            o.threads = threads;
            s.needs_footprints = false;
            const Image without = render(s, o).image;
            s.needs_footprints = true;
            const Image with = render(s, o).image;
            s.needs_footprints = c.footprints;
            ASSERT_EQ(without.data.size(), with.data.size());
            const bool same = std::memcmp(without.data.data(), with.data.data(), with.data.size() * sizeof(float)) == 0;
            EXPECT_EQ(same, !c.footprints) << c.what << ", " << threads << " threads";
        }
    }
}

}  // namespace
}  // namespace pellucid::test
