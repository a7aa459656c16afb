// What tests/cpp/light/test_envmap_lanes.cpp compares across lane types: the packet light table with
// environment-map rows (light_table.h): sample_light_table over lanes of mixed kinds (sphere,
// constant, environment maps of two sizes and rotations, a light with no packet form), each lane's
// map's density and radiance toward a direction (envmap_pdf, envmap_Le), and the radiance that
// escaping rays take from the lights at infinity (escaped_radiance), and NEE's pick of a light
// (pick_light_lanes), kLaneWidth<F> lanes at a time.
// Instantiated on float in the test and on each SIMD target's packet in envmap_probe_<target>.cpp
// (built with that target's flags, exporting only its entry point).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>

#include "pellucid/light/light_table.h"

namespace pellucid::envmap_probe {

/// Inputs, one entry per case; n is a multiple of 16.
struct In {
    int n = 0;
    const float *u[2], *d[3], *p[3], *prev_pdf;
    const bool *active, *specular;
    const LightTable* lights = nullptr;
    const int32_t* light = nullptr;  ///< per case, a row of `lights`
};
constexpr int kOutputs = 22;
/// Outputs, one array of n floats per quantity (masks as 0/1), zeroed by the caller.
struct Out {
    float* v[kOutputs];
};

template <class F>
void run(const In& in, Out& out) {
    constexpr int W = kLaneWidth<F>;
    using M = MaskT<F>;
    alignas(64) bool act[W], spec[W];
    for (int o = 0; o < in.n; o += W) {
        auto L = [&](const float* a) { return lane::load_as<F>(a + o); };
        for (int i = 0; i < W; ++i) act[i] = in.active[o + i], spec[i] = in.specular[o + i];
        const M active = lane::load_mask_as<M>(act);
        int k = 0;
        auto put = [&](const F& x) { lane::store(out.v[k++] + o, lane::select(active, x, F(0.f))); };
        auto putm = [&](const M& m) { put(lane::select(m, F(1.f), F(0.f))); };
        const IntT<F> light = lane::load_int_as<IntT<F>>(in.light + o);
        const V3<F> d(L(in.d[0]), L(in.d[1]), L(in.d[2])), p(L(in.p[0]), L(in.p[1]), L(in.p[2]));
        const LightTableSample<F> ls = sample_light_table<F>(*in.lights, light, p, V2<F>{L(in.u[0]), L(in.u[1])});
        putm(ls.valid), putm(ls.infinite), put(ls.wi.x), put(ls.wi.y), put(ls.wi.z);
        put(ls.L.r), put(ls.L.g), put(ls.L.b), put(ls.pdf);
        // The lane's map (lanes of other lights read the table's placeholder rows).
        const EnvmapLanes<F> e = envmap_lanes<F>(*in.lights, light);
        const RGB<F> Le = envmap_Le<F>(e, d);
        put(envmap_pdf<F>(e, d)), put(Le.r), put(Le.g), put(Le.b);
        const M specular = lane::load_mask_as<M>(spec);
        const RGB<F> esc = escaped_radiance<F>(*in.lights, d, true, true, specular, L(in.prev_pdf));
        put(esc.r), put(esc.g), put(esc.b);
        const RGB<F> esc_nee = escaped_radiance<F>(*in.lights, d, false, true, specular, L(in.prev_pdf));
        put(esc_nee.r);
        // NEE's pick of a light from u[0] (pick_light_lanes).
        F sel;
        const IntT<F> picked = pick_light_lanes<F>(*in.lights, L(in.u[0]), &sel);
        put(lane::to_float(picked)), put(sel);
    }
}
}  // namespace pellucid::envmap_probe
