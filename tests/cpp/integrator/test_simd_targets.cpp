// The path tracer (integrator/path_kernel.h) on every SIMD target this build and CPU have, against
// its width-1 instantiation. Every target is compiled without floating-point contraction and the
// estimator's packet arithmetic is lane-wise IEEE arithmetic, so a lane computes exactly what the
// scalar instantiation computes for the same inputs: the images must agree bit for bit. Any slip
// in the packet bookkeeping (a path restarted in the wrong lane, a shadow ray credited to another
// path, a mask that lets a BSDF lane through the Lambertian pass) changes pixels.
// SPDX-License-Identifier: Apache-2.0
// (Built for the baseline instruction set, where GCC notes that PCG32x4's 32-byte vectors would
// change the ABI of a call; its functions are always inlined.)
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <set>
#include <string>

#include "pellucid/api.h"
#include "pellucid/integrator/path_services.h"
#include "pellucid/integrator/simd_target.h"
#include "pellucid/scene/hit_packets.h"
#include "pellucid/scene/json_io.h"
#include "support/temp_dir.h"

using namespace pellucid;

namespace {
// A file of scenes/, or a path relative to the repository (one with a '/').
std::shared_ptr<const Scene> load_scene(const std::string& file, int width = 0, int height = 0) {
    const std::string dir = file.find('/') == std::string::npos ? "/scenes/" : "/";
    SceneDesc desc = read_json_file(std::string(PELLUCID_SOURCE_DIR) + dir + file);
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

RenderResult render_on(const Scene& scene, SimdTarget t, RenderOptions o) {
    set_simd_target(t);
    RenderResult r = render(scene, o);
    set_simd_target(std::nullopt);
    return r;
}
}  // namespace

TEST(SimdTargets, TheWidestAvailableIsChosen) {
    const std::vector<SimdTarget> avail = available_simd_targets();
    ASSERT_FALSE(avail.empty());
    EXPECT_EQ(avail.front(), SimdTarget::Scalar);
    EXPECT_EQ(simd_target(), avail.back());
    for (SimdTarget t : avail) EXPECT_EQ(parse_simd_target(to_string(t), "t"), t);
    EXPECT_THROW(parse_simd_target("avx1024", "t"), Error);
}

namespace {
/// Both samplers, 3 samples per pixel (so that paths of one pixel are in flight together and finish
/// out of order): every target's image and variance must be the scalar target's, bit for bit.
void expect_every_target_gives_the_scalar_image(const Scene& scene, const std::string& name) {
    for (const char* sampler : {"independent", "sobol"}) {
        RenderOptions o;
        o.spp = 3;
        o.seed = 5;
        o.threads = 2;
        o.sampler = sampler;
        const RenderResult ref = render_on(scene, SimdTarget::Scalar, o);
        for (SimdTarget t : available_simd_targets()) {
            if (t == SimdTarget::Scalar) continue;
            const RenderResult r = render_on(scene, t, o);
            ASSERT_EQ(r.image.data.size(), ref.image.data.size());
            EXPECT_EQ(0u, differing(r.image, ref.image)) << name << " " << sampler << " " << to_string(t);
            EXPECT_EQ(0u, differing(r.variance, ref.variance)) << name << " " << sampler << " " << to_string(t);
            EXPECT_EQ(r.stats.invalid_samples, ref.stats.invalid_samples);
            EXPECT_EQ(r.stats.samples, ref.stats.samples);
        }
    }
}
}  // namespace

namespace {
/// Every target, the scalar one too, renders the same image from either path setup of the scene.
void expect_setups_give_the_same_image(const Scene& scene, const PathSetup& with, const PathSetup& without, int spp,
                                       int seed, const std::string& name) {
    RenderOptions o;
    o.spp = spp;
    o.seed = seed;
    std::vector<SimdTarget> targets = available_simd_targets();
    targets.push_back(SimdTarget::Scalar);
    for (SimdTarget t : targets) {
        const PathTileFn tile = path_tile_function(t);
        const RenderResult a = render_loop(scene, o, [&](const TileJob& j, Film& f) { return tile(with, j, f); });
        const RenderResult b = render_loop(scene, o, [&](const TileJob& j, Film& f) { return tile(without, j, f); });
        EXPECT_EQ(0u, differing(a.image, b.image)) << name << " " << to_string(t);
    }
}
}  // namespace

class SimdTargetRender : public ::testing::TestWithParam<std::string> {};

TEST_P(SimdTargetRender, EveryTargetGivesTheScalarImage) {
    // Splatting (cornell_box) and filter-sampling films, area/environment/point lights, spheres,
    // glass, metals, textures with ray differentials and bump maps (BSDF lanes beside packet
    // Lambertian lanes), plastics (smooth, and GGX rough with the smooth coat in material_balls;
    // with two rough coat tables, linear and coupled, beside a Beckmann one on the BSDF lanes in
    // the suite's plastics; thin dielectrics beside the rough ones in the suite's glass, classic and
    // EON Oren–Nayar in its no_twin).
    auto scene = load_scene(GetParam(), 64, 48);
    expect_every_target_gives_the_scalar_image(*scene, GetParam());
}

TEST(SimdTargetRender, BeckmannRoughConductors) {
    // env_spheres.json with its clay sphere and its rough gold turned into Beckmann rough
    // conductors (the packet form RoughConductorBeckmannT): isotropic height-correlated copper,
    // anisotropic separable gold, beside the mirror, the glass and the Lambertian ground.
    SceneDesc desc = read_json_file(std::string(PELLUCID_SOURCE_DIR) + "/scenes/env_spheres.json");
    Node film = *desc.root.find("film");
    film.set("width", Node::number(64, true));
    film.set("height", Node::number(48, true));
    desc.root.set("film", film);
    Node materials = *desc.root.find("materials");
    Node copper = Node::object(), gold = Node::object();
    copper.set("type", Node::string("rough_conductor"));
    copper.set("material", Node::string("Cu"));
    copper.set("distribution", Node::string("beckmann"));
    copper.set("alpha", Node::number(0.3));
    gold.set("type", Node::string("rough_conductor"));
    gold.set("material", Node::string("Au"));
    gold.set("distribution", Node::string("beckmann"));
    gold.set("alpha_u", Node::number(0.05));
    gold.set("alpha_v", Node::number(0.4));
    gold.set("shadowing", Node::string("separable"));
    materials.set("clay", copper);
    materials.set("gold", gold);
    desc.root.set("materials", materials);
    auto scene = load_desc(desc);
    int beckmann = 0;
    for (const BxDF& b : scene->material_bxdfs) beckmann += std::holds_alternative<RoughConductorBeckmann>(b);
    ASSERT_EQ(beckmann, 2);
    const PathSetup ps = make_path_setup(*scene, 8, 5, true, true, SamplerType::Independent);
    EXPECT_EQ(std::count(ps.packet_kind.begin(), ps.packet_kind.end(), int32_t(kPacketRoughConductorBeckmann)), 2);
    expect_every_target_gives_the_scalar_image(*scene, "env_spheres with Beckmann conductors");
}

TEST(SimdTargetRender, PacketKindsMatchTheirModels) {
    // Every material of these scenes (every BxDF of the variant between them) is shaded by the
    // packet form of its own model or as a BSDF lane: a packet kind given to a material of another
    // model would render it as that model on every target alike, which the bit-identity tests
    // cannot see. (Rough conductors that are effectively smooth collapse to the smooth one.)
    const char* files[] = {"bench/suite/glass.json",     "bench/suite/principled.json", "bench/suite/no_twin.json",
                           "bench/suite/plastics.json",  "bench/suite/many_materials.json",
                           "bench/suite/env_rough_metal.json", "scenes/material_balls.json", "scenes/subsurface.json"};
    std::set<size_t> seen;
    for (const char* file : files) {
        auto scene = load_desc(read_json_file(std::string(PELLUCID_SOURCE_DIR) + "/" + file));
        const PathSetup ps = make_path_setup(*scene, 8, 5, true, true, SamplerType::Independent);
        for (size_t m = 0; m < scene->material_bxdfs.size(); ++m) {
            const BxDF& b = scene->material_bxdfs[m];
            seen.insert(b.index());
            std::set<int32_t> allowed{kBSDFLane};
            if (std::holds_alternative<Lambertian>(b)) allowed.insert(kPacketLambertian);
            if (std::holds_alternative<SmoothDielectric>(b)) allowed.insert(kPacketSmoothDielectric);
            if (std::holds_alternative<SmoothConductor<ConductorFresnel>>(b)) allowed.insert(kPacketSmoothConductor);
            if (std::holds_alternative<RoughConductor>(b)) allowed.insert({kPacketRoughConductor, kPacketSmoothConductor});
            if (std::holds_alternative<RoughConductorBeckmann>(b))
                allowed.insert({kPacketRoughConductorBeckmann, kPacketSmoothConductor});
            if (std::holds_alternative<SmoothPlastic>(b) || std::holds_alternative<RoughPlastic<GGX>>(b))
                allowed.insert(kPacketPlastic);
            if (std::holds_alternative<RoughPlastic<Beckmann>>(b)) allowed.insert(kPacketPlasticBeckmann);
            if (std::holds_alternative<RoughDielectric<GGX>>(b)) allowed.insert(kPacketRoughDielectric);
            if (std::holds_alternative<RoughDielectric<Beckmann>>(b)) allowed.insert(kPacketRoughDielectricBeckmann);
            if (std::holds_alternative<ThinDielectric>(b)) allowed.insert(kPacketThinDielectric);
            if (std::holds_alternative<OrenNayar>(b)) allowed.insert(kPacketOrenNayar);
            if (std::holds_alternative<PrincipledBSDF>(b)) allowed.insert({kPacketPrincipled, kPacketPrincipledThin, kPacketPrincipledSolid});
            if (std::holds_alternative<Principled>(b)) allowed.insert(kPacketPrincipled2012);
            EXPECT_TRUE(allowed.count(ps.packet_kind[m])) << file << ": material " << m << " (BxDF alternative "
                                                           << b.index() << ") has packet kind " << ps.packet_kind[m];
        }
    }
    EXPECT_EQ(seen.size(), std::variant_size_v<BxDF>);  // every model was checked
}

TEST(SimdTargetRender, SuitePlasticsAreAllPacketForms) {
    // bench/suite/plastics.json (rendered by every target in Scenes/SimdTargetRender): its smooth,
    // GGX and Beckmann plastics all run as packet forms, the Beckmann one as kPacketPlasticBeckmann.
    auto scene = load_desc(read_json_file(std::string(PELLUCID_SOURCE_DIR) + "/bench/suite/plastics.json"));
    const PathSetup ps = make_path_setup(*scene, 8, 5, true, true, SamplerType::Independent);
    int plastics = 0, beckmann = 0;
    for (size_t m = 0; m < scene->material_bxdfs.size(); ++m) {
        const BxDF& b = scene->material_bxdfs[m];
        const bool is_plastic = std::holds_alternative<SmoothPlastic>(b) || std::holds_alternative<RoughPlastic<GGX>>(b) ||
                                std::holds_alternative<RoughPlastic<Beckmann>>(b);
        plastics += is_plastic;
        beckmann += std::holds_alternative<RoughPlastic<Beckmann>>(b);
        if (is_plastic)
            EXPECT_EQ(ps.packet_kind[m], std::holds_alternative<RoughPlastic<Beckmann>>(b) ? int32_t(kPacketPlasticBeckmann)
                                                                                          : int32_t(kPacketPlastic))
                << m;
    }
    EXPECT_EQ(plastics, 4);  // smooth, GGX, Beckmann and the GGX box
    EXPECT_EQ(beckmann, 1);
}

INSTANTIATE_TEST_SUITE_P(Scenes, SimdTargetRender,
                         ::testing::Values("cornell_box.json", "veach_mis.json", "env_spheres.json",
                                           "material_balls.json", "textured_bump.json", "bench/suite/plastics.json",
                                           "bench/suite/glass.json", "bench/suite/no_twin.json"),
                         [](const auto& info) {
                             const std::string name = info.param.substr(info.param.rfind('/') + 1);
                             return name.substr(0, name.find('.'));
                         });

TEST(SimdTargetRender, ChunksOfWholePixels) {
    // 200 spp run in passes of 25 samples, so a 16×16 tile goes through in chunks of 4096 / 25 = 163
    // pixels: the second chunk of each tile starts mid-row. Every target must still agree.
    auto scene = load_scene("cornell_box.json", 40, 24);
    RenderOptions o;
    o.spp = 200;
    o.seed = 3;
    const RenderResult ref = render_on(*scene, SimdTarget::Scalar, o);
    for (SimdTarget t : available_simd_targets()) {
        const RenderResult r = render_on(*scene, t, o);
        EXPECT_EQ(0u, differing(r.image, ref.image)) << to_string(t);
        EXPECT_EQ(0u, differing(r.variance, ref.variance)) << to_string(t);
    }
}

TEST(SimdTargetRender, SameImageAtAnyThreadCount) {
    auto scene = load_scene("material_balls.json", 48, 32);
    RenderOptions o;
    o.spp = 8;
    o.seed = 11;
    o.threads = 1;
    const RenderResult one = render(*scene, o);
    o.threads = 2;
    const RenderResult two = render(*scene, o);
    EXPECT_EQ(0u, differing(one.image, two.image));
    EXPECT_EQ(0u, differing(one.variance, two.variance));
}

TEST(SimdTargetRender, ForcingAMissingTargetIsAnError) {
    for (SimdTarget t : {SimdTarget::SSE4, SimdTarget::NEON, SimdTarget::AVX2, SimdTarget::AVX512}) {
        bool avail = false;
        for (SimdTarget a : available_simd_targets()) avail = avail || a == t;
        if (!avail) {
            EXPECT_THROW(set_simd_target(t), Error) << to_string(t);
        }
    }
}

TEST(SimdTargetRender, RoughDielectricsWithoutMultipleScatteringArePacketForms) {
    // bench/suite/glass.json's GGX and Beckmann rough dielectrics run as their packet forms; a GGX one
    // with Kulla–Conty compensation, whose extra lobe has no packet form, stays a BSDF lane.
    SceneDesc desc = read_json_file(std::string(PELLUCID_SOURCE_DIR) + "/bench/suite/glass.json");
    Node materials = *desc.root.find("materials");
    Node frosted = *materials.find("frosted");
    frosted.set("multiple_scattering", Node::boolean(true));
    frosted.set("alpha", Node::number(0.6));
    frosted.set("shadowing", Node::string("height_correlated"));
    materials.set("compensated", frosted);
    desc.root.set("materials", materials);
    auto scene = load_desc(desc);
    const PathSetup ps = make_path_setup(*scene, 8, 5, true, true, SamplerType::Independent);
    int ggx = 0, beckmann = 0, compensated = 0;
    for (size_t m = 0; m < scene->material_bxdfs.size(); ++m) {
        const BxDF& b = scene->material_bxdfs[m];
        if (const auto* g = std::get_if<RoughDielectric<GGX>>(&b)) {
            if (g->multiscatter()) {
                ++compensated;
                EXPECT_EQ(ps.packet_kind[m], int32_t(kBSDFLane)) << m;
            } else {
                ++ggx;
                EXPECT_EQ(ps.packet_kind[m], int32_t(kPacketRoughDielectric)) << m;
            }
        }
        if (std::holds_alternative<RoughDielectric<Beckmann>>(b)) {
            ++beckmann;
            EXPECT_EQ(ps.packet_kind[m], int32_t(kPacketRoughDielectricBeckmann)) << m;
        }
    }
    EXPECT_EQ(ggx, 1);
    EXPECT_EQ(beckmann, 1);
    EXPECT_EQ(compensated, 1);
}

TEST(SimdTargetRender, ThinDielectricsAndOrenNayarArePacketForms) {
    // The suite's thin dielectrics (glass.json, many_materials.json) and its Oren–Nayar materials,
    // EON and classic (no_twin.json), run as their packet forms: kPacketThinDielectric and
    // kPacketOrenNayar, with the variant in the parameters.
    int thin = 0, eon = 0, classic = 0;
    for (const char* file : {"glass.json", "many_materials.json", "no_twin.json"}) {
        auto scene = load_desc(read_json_file(std::string(PELLUCID_SOURCE_DIR) + "/bench/suite/" + file));
        const PathSetup ps = make_path_setup(*scene, 8, 5, true, true, SamplerType::Independent);
        for (size_t m = 0; m < scene->material_bxdfs.size(); ++m) {
            const BxDF& b = scene->material_bxdfs[m];
            if (std::holds_alternative<ThinDielectric>(b)) {
                ++thin;
                EXPECT_EQ(ps.packet_kind[m], int32_t(kPacketThinDielectric)) << file << " " << m;
            }
            if (const auto* o = std::get_if<OrenNayar>(&b)) {
                ++(o->lanes().classic ? classic : eon);
                EXPECT_EQ(ps.packet_kind[m], int32_t(kPacketOrenNayar)) << file << " " << m;
                EXPECT_EQ(ps.packet_params[kPacketParams * m + 10], o->lanes().classic ? 1.f : 0.f) << file << " " << m;
            }
        }
    }
    EXPECT_EQ(thin, 2);
    EXPECT_EQ(eon, 1);
    EXPECT_EQ(classic, 1);
}

TEST(SimdTargetRender, TexturedMaterialsTakeTheirModelsPacketForm) {
    // The suite's glass floor (a Lambertian whose one texture is a point-sampled checkerboard) is one
    // of PathSetup::tex_lanes: the packet Lambertian with the colour of its hit's square
    // (checkerboard_square), which is the albedo of the BSDF built at that hit. textured_bump's
    // bump-mapped Lambertians are built at each hit and shaded by the packet Lambertian with that
    // hit's texel (with their softened terminators), and its textured, bump-mapped rough plastic by
    // the packet plastic with that hit's parameters and the material's rough coat table, which every
    // hit's BSDF shares (PathSetup::textured_coat).
    auto glass = load_scene("bench/suite/glass.json");
    const PathSetup ps = make_path_setup(*glass, 8, 5, true, true, SamplerType::Independent);
    const auto it = std::find(glass->material_names.begin(), glass->material_names.end(), "checker");
    ASSERT_NE(it, glass->material_names.end());
    const size_t checker = size_t(it - glass->material_names.begin());
    EXPECT_EQ(ps.packet_kind[checker], kBSDFLane);
    EXPECT_TRUE(ps.textured_packet[checker]);
    ASSERT_GE(ps.tex_lane[checker], 0);
    EXPECT_FALSE(ps.tri_uv.empty());
    const PathSetup::TexLaneMaterial& tm = ps.tex_lanes[size_t(ps.tex_lane[checker])];
    ASSERT_EQ(tm.reflectance, PathSetup::TexLaneMaterial::kChecker);
    EXPECT_FALSE(tm.bump);
    // Hits on the floor: the square's colour is the BSDF's albedo there, and both colours occur.
    std::set<float> reds;
    for (int k = 0; k < 64; ++k) {
        const Ray r{glass->camera.origin(), glass->camera.direction<float>(4.f * float(k) + 2.f, 250.f), kInfinity};
        SurfaceInteraction si;
        if (!glass->intersect(r, si) || si.material_id != checker) continue;
        glass->compute_footprint(si, RayDifferential(r));
        const BSDF b = glass->bsdf(si);
        float q[kPacketParams];
        ASSERT_EQ(path_services::packet_form(ps, uint32_t(checker), b, q), kPacketLambertian);
        const Spectrum albedo = std::get<Lambertian>(b.bxdf()).albedo();
        const float w = checkerboard_square<float>(tm.to_uv, si.uv.x, si.uv.y);
        for (int c = 0; c < 3; ++c) {
            EXPECT_EQ(q[c], albedo[c]);
            EXPECT_EQ(tm.albedo[0][c] * (1.f - w) + tm.albedo[1][c] * w, q[c]);
        }
        reds.insert(q[0]);
    }
    EXPECT_EQ(reds.size(), 2u);
    auto bump = load_scene("bench/suite/textured_bump.json");
    const PathSetup pb = make_path_setup(*bump, 8, 5, true, true, SamplerType::Independent);
    int built = 0;
    for (size_t m = 0; m < bump->material_bxdfs.size(); ++m) {
        const bool lambertian = std::holds_alternative<Lambertian>(bump->material_bxdfs[m]);
        EXPECT_TRUE(pb.textured_packet[m]) << bump->material_names[m];
        EXPECT_GE(pb.tex_lane[m], 0) << bump->material_names[m];
        EXPECT_EQ(pb.textured_coat[m] != nullptr, !lambertian) << bump->material_names[m];
        built += pb.textured_packet[m];
    }
    EXPECT_EQ(built, 3);
    // Hits on the plastic ball: the packet plastic, with the hit's diffuse texel and the offset of
    // the material's coat table, whose values are the hit's BSDF's table.
    const auto ball_it = std::find(bump->material_names.begin(), bump->material_names.end(), "ball");
    ASSERT_NE(ball_it, bump->material_names.end());
    const uint32_t ball = uint32_t(ball_it - bump->material_names.begin());
    std::set<float> diffuse;
    for (int k = 0; k < 64; ++k) {
        const Ray r{bump->camera.origin(), bump->camera.direction<float>(100.f + float(k), 128.f + 0.5f * float(k)), kInfinity};
        SurfaceInteraction si;
        if (!bump->intersect(r, si) || si.material_id != ball) continue;
        bump->compute_footprint(si, RayDifferential(r));
        const BSDF b = bump->bsdf(si);
        float q[kPacketParams];
        ASSERT_EQ(path_services::packet_form(pb, ball, b, q), kPacketPlastic);
        EXPECT_EQ(q[kPlasticCoatParam], pb.textured_coat_offset[ball]);
        const RoughCoatTable* t = std::get<RoughPlastic<GGX>>(b.bxdf()).base().coat_table();
        ASSERT_NE(t, nullptr);
        EXPECT_EQ(t, pb.textured_coat[ball]);
        EXPECT_TRUE(std::equal(t->values(), t->values() + kCoatTableSize, pb.coat_tables.data() + size_t(q[kPlasticCoatParam])));
        diffuse.insert(q[1]);
    }
    EXPECT_GT(diffuse.size(), 4u);  // (the texture varies over the ball)
}

// The triangle and sphere tables (PathSetup::tri_table, sphere_table): hits on their shapes take
// their vertices, materials and the start of their vertex as packets, gathered by triangle or
// sphere. Without the tables every lane records its hit one at a time (Scene::fill_hit or
// fetch_hit_vertex); both must give the same bits on every target. The suite's Cornell box with
// spheres mixes triangle-table lanes (the box), sphere-table lanes and emitter lanes in one packet;
// the plastics and glass scenes have several packet forms on meshes and spheres, many_materials 36
// spheres of 36 materials, env_spheres spheres under an environment map.
TEST(SimdTargetRender, ShapeTableLanesEqualLaneByLaneRecords) {
    for (const char* file : {"bench/suite/cornell_spheres.json", "bench/suite/plastics.json", "bench/suite/glass.json",
                             "bench/suite/many_materials.json", "bench/suite/env_spheres.json"}) {
        auto scene = load_scene(file, 40, 32);
        const PathSetup with = make_path_setup(*scene, 8, 5, true, true, SamplerType::Independent);
        // Some row of either table holds a material its lanes shade.
        auto lane_rows = [](const std::vector<float>& table, int stride, int slot) {
            int n = 0;
            for (size_t r = 0; r + size_t(stride) <= table.size(); r += size_t(stride)) {
                int32_t m;
                std::memcpy(&m, &table[r + size_t(slot)], sizeof m);
                n += m >= 0;
            }
            return n;
        };
        EXPECT_GT(lane_rows(with.tri_table, PathSetup::kTriStride, 21) + lane_rows(with.sphere_table, PathSetup::kSphereStride, 14), 0)
            << file;
        PathSetup without = with;
        without.tri_base.clear();
        without.tri_table.clear();
        without.sphere_row.clear();
        without.sphere_table.clear();
        expect_setups_give_the_same_image(*scene, with, without, 16, 5, file);
    }
}

TEST(SimdTargetRender, LargeMeshHitsArePrefetchedWithoutChangingTheImage) {
    // A bowl of 182 x 182 quads (66,248 triangles, above kPrefetchTriangles) with vertex normals, so
    // that its hits are recorded one lane at a time with their index rows and vertices requested
    // first (prefetch_index_rows, prefetch_vertices): the path setup asks for it, and every target
    // renders the image it renders without it, bit for bit (the requests read each hit's index row,
    // which the sanitizer build checks).
    const test::TempDir tmp("pellucid_prefetch_");
    const int n = 182;
    {
        std::ofstream ply(tmp.file("bowl.ply"));
        ply << "ply\nformat ascii 1.0\nelement vertex " << (n + 1) * (n + 1)
            << "\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\n"
               "property float nz\nelement face "
            << n * n << "\nproperty list uchar int vertex_indices\nend_header\n";
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) {
                const float x = -1.f + 2.f * float(i) / float(n), z = -1.f + 2.f * float(j) / float(n);
                const float nx = -0.6f * x, ny = 1.f, nz = -0.6f * z, l = std::sqrt(nx * nx + ny * ny + nz * nz);
                ply << x << ' ' << 0.3f * (x * x + z * z) << ' ' << z << ' ' << nx / l << ' ' << ny / l << ' ' << nz / l << '\n';
            }
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const int a = j * (n + 1) + i;
                ply << "4 " << a << ' ' << a + n + 1 << ' ' << a + n + 2 << ' ' << a + 1 << '\n';
            }
    }
    std::ofstream(tmp.file("scene.json")) << R"({
        "camera": {"type": "perspective", "fov": 50, "to_world": [{"look_at": {"origin": [0, 2, 2.5], "target": [0, 0.2, 0], "up": [0, 1, 0]}}]},
        "film": {"width": 40, "height": 32},
        "sampler": {"type": "independent", "sample_count": 8},
        "integrator": {"type": "path", "max_depth": 6},
        "materials": {"gold": {"type": "rough_conductor", "material": "Au", "alpha": 0.2},
                      "clay": {"type": "lambertian", "reflectance": 0.5}},
        "shapes": [{"type": "ply", "filename": "bowl.ply", "material": "gold"},
                   {"type": "sphere", "center": [0, 0.6, 0], "radius": 0.3, "material": "clay"}],
        "lights": [{"type": "constant", "radiance": 0.5}, {"type": "directional", "direction": [-0.3, -1, -0.4], "irradiance": 2}]
    })";
    auto scene = load_file(tmp.file("scene.json"));
    ASSERT_EQ(scene->meshes.size(), 1u);
    ASSERT_GT(scene->meshes[0].triangle_count(), kPrefetchTriangles);
    const PathSetup with = make_path_setup(*scene, 6, 5, true, true, SamplerType::Independent);
    EXPECT_TRUE(with.prefetch_hits);
    PathSetup without = with;
    without.prefetch_hits = false;
    expect_setups_give_the_same_image(*scene, with, without, 8, 3, "bowl");
    // The suite's Cornell box (36 triangles) asks for none.
    auto small = load_scene("bench/suite/cornell_lambert.json", 16, 16);
    EXPECT_FALSE(make_path_setup(*small, 6, 5, true, true, SamplerType::Independent).prefetch_hits);
}

TEST(SimdTargetRender, PacketStartedSamplesAreStartSamples) {
    // The kernel starts a packet's paths with start_independent_samples (independent sampler,
    // splatting film): each lane's film position and sampler must be start_sample's, bit for bit,
    // for pixels and samples across the image and its seeds.
    auto scene = load_scene("cornell_box.json", 40, 24);
    const PathSetup ps = make_path_setup(*scene, 8, 5, true, true, SamplerType::Independent);
    constexpr int N = 16;
    for (uint64_t seed : {0ull, 7ull}) {
        uint64_t stream[N], sample[N], state[N], inc[N];
        float cx[N], cy[N], fx[N], fy[N];
        int px[N], py[N];
        Sampler::PixelSeed seeds[N];
        for (int i = 0; i < N; ++i) {
            px[i] = (7 * i + 3) % 40, py[i] = (5 * i + 1) % 24;
            seeds[i] = path_services::pixel_seed(ps, px[i], py[i], seed);
            stream[i] = seeds[i].stream, sample[i] = uint64_t(i * i * 37);
            cx[i] = float(px[i]) + 0.5f, cy[i] = float(py[i]) + 0.5f;
        }
        path_services::start_independent_samples<N>(stream, sample, cx, cy, state, inc, fx, fy);
        for (int i = 0; i < N; ++i) {
            Sampler want;
            float wx, wy;
            path_services::start_sample(ps, true, px[i], py[i], int(sample[i]), seeds[i], &want, &wx, &wy);
            EXPECT_EQ(fx[i], wx) << i;
            EXPECT_EQ(fy[i], wy) << i;
            Sampler got = Sampler::independent_after_pixel(PCG32::from_state(state[i], inc[i]), seeds[i], sample[i]);
            EXPECT_EQ(got.dimension(), want.dimension());
            for (int k = 0; k < 4; ++k) EXPECT_EQ(got.get_1d(), want.get_1d()) << i;
        }
    }
}

TEST(SimdTargetRender, TexLanesEqualTheirBSDFLanes) {
    // The materials of PathSetup::tex_lanes (textured, bump-mapped Lambertians whose textures the
    // packet pass evaluates: texture_lanes.h, bump_normal_mitsuba_lanes, mirror_invalid_normal) give
    // the image of the same scene with them built one lane at a time by Scene::textured_bsdf, bit
    // for bit, on the scalar target and the widest: textured_bump's floor (an image reflectance and
    // height map, the invalid normals mirrored, Estevez's terminator), panel (a point-sampled
    // checkerboard with the height map) and ball (a rough plastic with an image Kd and the height
    // map), and a variant with the floor's normals kept and constant colours on the panel and ball. Both samplers: the independent one draws for all lanes at once, Sobol's lane by lane.
    for (int variant = 0; variant < 2; ++variant) {
        SceneDesc desc = read_json_file(std::string(PELLUCID_SOURCE_DIR) + "/bench/suite/textured_bump.json");
        Node film = *desc.root.find("film");
        film.set("width", Node::number(40, true));
        film.set("height", Node::number(32, true));
        desc.root.set("film", film);
        if (variant == 1) {
            Node mats = *desc.root.find("materials");
            Node floor = *mats.find("floor"), panel = *mats.find("panel"), ball = *mats.find("ball");
            floor.set("invalid_normals", Node::string("keep"));
            panel.set("reflectance", Node::number(0.4));
            ball.set("diffuse_reflectance", Node::number(0.3));
            mats.set("floor", floor);
            mats.set("panel", panel);
            mats.set("ball", ball);
            desc.root.set("materials", mats);
        }
        auto scene = load_desc(desc);
        // With the shape tables (the floor's and panel's triangles and the ball are vertex lanes,
        // their uv and tangents from tri_uv and sphere_vertex), without them (full records), and
        // the materials built one lane at a time.
        const PathSetup with = make_path_setup(*scene, 8, 5, true, true, SamplerType::Independent);
        PathSetup records = with;
        records.tri_base.clear();
        records.tri_table.clear();
        records.sphere_row.clear();
        records.sphere_table.clear();
        PathSetup without = records;
        int lanes = 0;
        for (auto& t : without.tex_lane) lanes += t >= 0, t = -1;
        EXPECT_EQ(lanes, 3) << variant;
        EXPECT_FALSE(with.tri_uv.empty());
        EXPECT_FALSE(with.tri_base.empty());
        EXPECT_FALSE(with.sphere_row.empty());
        // The height map is grey: its lookups read a one-channel copy, one for the three materials.
        ASSERT_EQ(with.grey_images.size(), 1u);
        EXPECT_EQ(with.tex_lanes[0].height.texels, with.grey_images[0].texels->data());
        EXPECT_EQ(with.tex_lanes[0].height.n, 1);
        for (const char* sampler : {"independent", "sobol"}) {
            RenderOptions o;
            o.spp = 16;
            o.seed = 5;
            o.sampler = sampler;
            const SamplerType type = std::string(sampler) == "sobol" ? SamplerType::Sobol : SamplerType::Independent;
            PathSetup w = with, r = records, wo = without;
            w.sampler = r.sampler = wo.sampler = type;
            for (SimdTarget t : {SimdTarget::Scalar, available_simd_targets().back()}) {
                const PathTileFn tile = path_tile_function(t);
                const RenderResult b = render_loop(*scene, o, [&](const TileJob& j, Film& f) { return tile(wo, j, f); });
                for (const PathSetup* ps : {&w, &r}) {
                    const RenderResult a = render_loop(*scene, o, [&](const TileJob& j, Film& f) { return tile(*ps, j, f); });
                    EXPECT_EQ(0u, differing(a.image, b.image))
                        << variant << " " << sampler << " " << to_string(t) << (ps == &w ? " tables" : " records");
                    EXPECT_EQ(a.stats.samples, b.stats.samples);
                }
            }
        }
    }
}

TEST(SimdTargetRender, PacketFormsEqualBSDFLanes) {
    // A material's packet form is its BxDF: the same scene rendered with every material on BSDF
    // lanes (packet kinds cleared, and with them the shape tables, whose lanes are packet-form
    // lanes) gives the same image bit for bit. A form that the packet pass handles differently
    // from its BSDF (a lobe NEE does not reach, another frame) shows here; the bit-identity of the
    // targets cannot see it, as every target runs the same pass. (glass.json's floor is one of
    // PathSetup::tex_lanes, which are built one lane at a time here too.)
    for (const char* file : {"bench/suite/principled.json", "bench/suite/cornell_spheres.json", "bench/suite/no_twin.json",
                             "bench/suite/env_spheres.json", "bench/suite/glass.json"}) {
        auto scene = load_scene(file, 40, 32);
        const PathSetup with = make_path_setup(*scene, 8, 5, true, true, SamplerType::Independent);
        PathSetup without = with;
        int forms = 0;
        for (auto& k : without.packet_kind) forms += k != kBSDFLane, k = kBSDFLane;
        for (auto& t : without.textured_packet) t = 0;
        for (auto& t : without.tex_lane) t = -1;
        without.tri_base.clear();
        without.tri_table.clear();
        without.sphere_row.clear();
        without.sphere_table.clear();
        EXPECT_GT(forms, 0) << file;
        RenderOptions o;
        o.spp = 16;
        o.seed = 5;
        for (SimdTarget t : {SimdTarget::Scalar, available_simd_targets().back()}) {
            const PathTileFn tile = path_tile_function(t);
            const RenderResult a = render_loop(*scene, o, [&](const TileJob& j, Film& f) { return tile(with, j, f); });
            const RenderResult b = render_loop(*scene, o, [&](const TileJob& j, Film& f) { return tile(without, j, f); });
            EXPECT_EQ(0u, differing(a.image, b.image)) << file << " " << to_string(t);
        }
    }
}
