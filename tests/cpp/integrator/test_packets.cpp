// The path tracer's packet driver (render_tile_packets in integrator/path.cpp) against the
// one-path-at-a-time loop: each path keeps its own sampler and the film receives the estimates in
// the same order, so the two must give the same image and variance, bit for bit. Any slip in the
// driver's bookkeeping (a path resumed in the wrong slot, a shadow ray applied to the wrong path or
// twice, a sample filed under the wrong pixel) changes pixels.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "pellucid/api.h"
#include "pellucid/scene/json_io.h"

using namespace pellucid;

namespace {
std::shared_ptr<const Scene> load_with_packets(const std::string& file, bool packets, int width = 0, int height = 0) {
    SceneDesc desc = read_json_file(std::string(PELLUCID_SOURCE_DIR) + "/scenes/" + file);
    Node integrator = desc.root.find("integrator") ? *desc.root.find("integrator") : Node::object();
    integrator.set("packets", Node::boolean(packets));
    integrator.set("lanes", Node::boolean(false));  // the general loop's drivers (path_lanes.h has its own tests)
    desc.root.set("integrator", integrator);
    if (width > 0) {
        Node film = *desc.root.find("film");
        film.set("width", Node::number(width, true));
        film.set("height", Node::number(height, true));
        desc.root.set("film", film);
    }
    return load_desc(desc);
}

size_t differing(const Image& a, const Image& b) {
    size_t n = 0;
    for (size_t i = 0; i < a.data.size(); ++i) n += std::memcmp(&a.data[i], &b.data[i], sizeof(float)) != 0;
    return n;
}
}  // namespace

class PacketTracing : public ::testing::TestWithParam<std::string> {};

TEST_P(PacketTracing, SameImageAsOnePathAtATime) {
    // Splatting (cornell_box) and filter-sampling films, area/environment/point lights, spheres,
    // glass, metals, textures with ray differentials and bump maps; both samplers; and a pass of 3
    // samples per pixel, so that paths of one pixel are in flight together and finish out of order.
    auto with = load_with_packets(GetParam(), true), without = load_with_packets(GetParam(), false);
    for (const char* sampler : {"independent", "sobol"}) {
        RenderOptions o;
        o.spp = 3;
        o.seed = 5;
        o.threads = 2;
        o.sampler = sampler;
        RenderResult a = render(*with, o), b = render(*without, o);
        ASSERT_EQ(a.image.data.size(), b.image.data.size());
        EXPECT_EQ(0u, differing(a.image, b.image)) << GetParam() << " " << sampler << ": image";
        EXPECT_EQ(0u, differing(a.variance, b.variance)) << GetParam() << " " << sampler << ": variance";
        EXPECT_EQ(a.stats.invalid_samples, b.stats.invalid_samples);
        EXPECT_EQ(a.stats.samples, b.stats.samples);
    }
}

INSTANTIATE_TEST_SUITE_P(Scenes, PacketTracing,
                         ::testing::Values("cornell_box.json", "veach_mis.json", "env_spheres.json",
                                           "material_balls.json", "textured_bump.json"),
                         [](const auto& info) { return info.param.substr(0, info.param.find('.')); });

TEST(PacketTracing, ChunksOfWholePixels) {
    // 200 spp run in passes of 25 samples, so a 16×16 tile goes through in chunks of 4096 / 25 = 163
    // pixels: the second chunk of each tile starts mid-row. The image must still match.
    auto with = load_with_packets("cornell_box.json", true, 40, 24), without = load_with_packets("cornell_box.json", false, 40, 24);
    RenderOptions o;
    o.spp = 200;
    o.seed = 3;
    RenderResult a = render(*with, o), b = render(*without, o);
    EXPECT_EQ(0u, differing(a.image, b.image));
    EXPECT_EQ(0u, differing(a.variance, b.variance));
}
