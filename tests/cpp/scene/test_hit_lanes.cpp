// The path kernel's hit vertices (scene/hit_packets.h) against Scene::fill_hit, bit for bit, on the
// float instantiation and on every SIMD target: spheres (one rotated, translated and with flipped
// normals), a flat-shaded rectangle, a torus with interpolated normals and no uvs, and a mesh with
// interpolated normals and uvs (one of its triangles with degenerate uvs).
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "pellucid/integrator/simd_target.h"
#include "pellucid/sampling/rng.h"
#include "pellucid/sampling/warp.h"
#include "pellucid/scene/build.h"
#include "pellucid/scene/json_io.h"
#include "scene/hit_probe.h"
#include "support/probe_outputs.h"
#include "support/temp_dir.h"

using namespace pellucid;

namespace {
constexpr int kN = 2048;
using Outputs = test::ProbeOutputs<hit_probe::Out, hit_probe::kOutputs, kN>;

std::unique_ptr<Scene> hit_scene(const test::TempDir& tmp) {
    // Smooth normals with uvs; the second triangle pair repeats a uv (a degenerate uv solve).
    std::ofstream(tmp.file("smooth.obj")) << "v -1 -1 0\nv 1 -1 0\nv 1 1 0.3\nv -1 1 0\nv 1 -1 0.5\n"
                                             "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                                             "vn 0 0 1\nvn 0.3 0 1\nvn 0 0.3 1\nvn -0.2 -0.2 1\nvn 0.5 0.5 1\n"
                                             "f 1/1/1 2/2/2 3/3/3\nf 1/1/1 3/3/3 4/4/4\nf 2/2/2 5/2/5 3/3/3\n";
    const std::string json = R"({"shapes": [
        {"type": "sphere", "radius": 0.7, "flip_normals": true,
         "to_world": [{"rotate": {"axis": [1, 2, 3], "angle": 40}}, {"translate": [-1.5, 0, 0]}]},
        {"type": "sphere", "center": [1.5, 0, 0], "radius": 0.5},
        {"type": "rectangle", "to_world": [{"rotate": {"axis": [1, 0, 0], "angle": -70}}, {"translate": [0, -1.5, 0]}]},
        {"type": "obj", "filename": ")" + std::string(PELLUCID_SOURCE_DIR) + R"(/scenes/meshes/torus.obj",
         "to_world": [{"scale": 0.6}, {"translate": [0, 1.5, 0]}]},
        {"type": "obj", "filename": ")" + tmp.file("smooth.obj") + R"(", "to_world": [{"translate": [0, 0, -1.5]}]}]})";
    SceneDesc d;
    d.source = "hits.json";
    d.root = parse_json(json, "hits.json");
    return build_scene(d);
}

/// kN rays from a sphere of radius 6 toward points near the shapes, each a hit; per shape, how many.
struct Hits {
    std::vector<Ray> rays;
    std::vector<RayHit> hits;
    int per_shape[5] = {0, 0, 0, 0, 0};
    explicit Hits(const Scene& scene) {
        PCG32 rng(7, 11);
        for (int tries = 0; int(rays.size()) < kN && tries < 100 * kN; ++tries) {
            const Vec3f o = 6.f * square_to_uniform_sphere(rng.next_2d());
            const Vec3f target(4.f * rng.next_float() - 2.f, 4.f * rng.next_float() - 2.f, 4.f * rng.next_float() - 2.f);
            const Ray r{o, normalize(target - o), kInfinity};
            RayHit h;
            h.t = r.tmax;
            if (!scene.accel.intersect(r, h)) continue;
            rays.push_back(r);
            hits.push_back(h);
            ++per_shape[h.geom_id];
        }
    }
    hit_probe::In in(const Scene& scene) const { return {&scene, int(rays.size()), rays.data(), hits.data()}; }
};

/// Scene::fill_hit's p, p_error, ng and shading frame of every hit.
void fill_hits(const Scene& scene, const Hits& hits, Outputs& out) {
    for (int i = 0; i < int(hits.rays.size()); ++i) {
        SurfaceInteraction si;
        scene.fill_hit(hits.rays[size_t(i)], hits.hits[size_t(i)], si, false);
        const Vec3f* q[6] = {&si.p, &si.p_error, &si.ng, &si.shading.s, &si.shading.t, &si.shading.n};
        for (int k = 0; k < 6; ++k)
            for (int c = 0; c < 3; ++c) out.out.v[3 * k + c][i] = (*q[k])[c];
    }
}

bool run_target(SimdTarget t, const hit_probe::In& in, Outputs& out) {
    switch (t) {
#ifdef PELLUCID_HIT_PROBE_AVX512
        case SimdTarget::AVX512: hit_probe::run_avx512(in, out.out); return true;
#endif
#ifdef PELLUCID_HIT_PROBE_AVX2
        case SimdTarget::AVX2: hit_probe::run_avx2(in, out.out); return true;
#endif
#ifdef PELLUCID_HIT_PROBE_SSE4
        case SimdTarget::SSE4: hit_probe::run_sse4(in, out.out); return true;
#endif
        default: return false;
    }
}
}  // namespace

TEST(HitLanes, EveryShapeIsHit) {
    const test::TempDir tmp("pellucid_hit_lanes_");
    const auto scene = hit_scene(tmp);
    const Hits hits(*scene);
    ASSERT_EQ(int(hits.rays.size()), kN);
    for (int s = 0; s < 5; ++s) EXPECT_GE(hits.per_shape[s], 64) << "shape " << s;
    // Shape 3 has interpolated normals and no uvs, shape 4 interpolated normals and uvs; the
    // rectangle is flat-shaded.
    EXPECT_FALSE(scene->meshes[scene->shapes[2].mesh_index].flat.empty());
    EXPECT_TRUE(scene->meshes[scene->shapes[3].mesh_index].flat.empty());
    EXPECT_TRUE(scene->meshes[scene->shapes[3].mesh_index].uvs.empty());
    EXPECT_TRUE(scene->meshes[scene->shapes[4].mesh_index].flat.empty());
    EXPECT_FALSE(scene->meshes[scene->shapes[4].mesh_index].uvs.empty());
}

TEST(HitLanes, FloatAndEveryTargetGiveFillHitsBits) {
    const test::TempDir tmp("pellucid_hit_lanes_");
    const auto scene = hit_scene(tmp);
    const Hits hits(*scene);
    ASSERT_EQ(int(hits.rays.size()), kN);
    Outputs want, scalar;
    fill_hits(*scene, hits, want);
    hit_probe::run<float>(hits.in(*scene), scalar.out);
    EXPECT_EQ(test::count_differing(want, scalar, "float"), 0u);
    int targets = 0;
    for (SimdTarget t : available_simd_targets()) {
        Outputs packet;
        if (!run_target(t, hits.in(*scene), packet)) continue;
        ++targets;
        EXPECT_EQ(test::count_differing(want, packet, to_string(t).c_str()), 0u);
    }
    RecordProperty("targets", targets);
}

TEST(HitLanes, AHitChangedInOneLaneIsSeen) {
    // The comparison itself: moving one hit along its triangle must change that lane's vertex only.
    const test::TempDir tmp("pellucid_hit_lanes_");
    const auto scene = hit_scene(tmp);
    Hits hits(*scene);
    Outputs before, after;
    fill_hits(*scene, hits, before);
    int lane = 0;
    while (scene->shapes[hits.hits[size_t(lane)].geom_id].kind != ShapeRecord::Kind::Mesh) ++lane;
    hits.hits[size_t(lane)].u *= 0.5f;
    for (SimdTarget t : available_simd_targets()) {
        if (!run_target(t, hits.in(*scene), after)) continue;
        EXPECT_EQ(test::differing_cases(before, after), std::vector<int>{lane}) << to_string(t);
    }
    hit_probe::run<float>(hits.in(*scene), after.out);
    EXPECT_EQ(test::differing_cases(before, after), std::vector<int>{lane});
}
