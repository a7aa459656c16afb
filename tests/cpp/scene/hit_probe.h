// What tests/cpp/scene/test_hit_lanes.cpp compares across lane types: the path kernel's hit
// vertices (scene/hit_packets.h: fetch_hit_vertex one lane at a time, hit_vertices for the packet)
// over an array of kernel hits, kLaneWidth<F> lanes at a time. It is instantiated on float in the
// test and on each SIMD target's packet in hit_probe_<target>.cpp (built with that target's flags,
// exporting only its entry point, as the renderer's kernels do).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include "pellucid/scene/hit_packets.h"

namespace pellucid::hit_probe {

/// n hits (a multiple of 16), every one a hit of rays[i] in scene.
struct In {
    const Scene* scene = nullptr;
    int n = 0;
    const Ray* rays = nullptr;
    const RayHit* hits = nullptr;
};
/// p, p_error, ng, and the shading frame's s, t and n: three arrays of n floats each.
constexpr int kOutputs = 18;
struct Out {
    float* v[kOutputs];
};

template <class F>
void run(const In& in, Out& out) {
    constexpr int W = kLaneWidth<F>;
    HitVertexInputs<W> hv{};
    for (int o = 0; o < in.n; o += W) {
        hv.clear();
        for (int i = 0; i < W; ++i) fetch_hit_vertex(*in.scene, in.rays[o + i], in.hits[o + i], i, hv);
        const HitVertexT<F> v = hit_vertices<F>(hv);
        const V3<F>* q[6] = {&v.p, &v.p_error, &v.ng, &v.shading.s, &v.shading.t, &v.shading.n};
        for (int k = 0; k < 6; ++k) {
            lane::store(out.v[3 * k] + o, q[k]->x);
            lane::store(out.v[3 * k + 1] + o, q[k]->y);
            lane::store(out.v[3 * k + 2] + o, q[k]->z);
        }
    }
}
void run_avx512(const In& in, Out& out);
void run_avx2(const In& in, Out& out);
void run_sse4(const In& in, Out& out);
void run_neon(const In& in, Out& out);
}  // namespace pellucid::hit_probe
