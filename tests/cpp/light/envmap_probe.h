// What tests/cpp/light/test_envmap_lanes.cpp compares across lane types: the packet light table with
// environment-map rows (light_table.h): sample_light_table over lanes of mixed kinds (sphere,
// constant, environment maps of two sizes and rotations, point, spot and directional lights, a
// light with no packet form), with the sample's point, normal, error bound and delta flag, each lane's
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
constexpr int kOutputs = 32;
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
        const LightTableSample<F> ls =
            sample_light_table<F>(*in.lights, light, p, V2<F>{L(in.u[0]), L(in.u[1])}, active);
        putm(ls.valid), putm(ls.infinite), put(ls.wi.x), put(ls.wi.y), put(ls.wi.z);
        put(ls.L.r), put(ls.L.g), put(ls.L.b), put(ls.pdf);
        // The lane's map (lanes of other lights read the table's placeholder rows).
        const EnvmapLanes<F> e = envmap_lanes<F>(*in.lights, light);
        const RGB<F> Le = envmap_Le<F>(e, d);
        put(envmap_pdf<F>(e, d)), put(Le.r), put(Le.g), put(Le.b);  // 9..12
        const M specular = lane::load_mask_as<M>(spec);
        const RGB<F> esc = escaped_radiance<F>(*in.lights, d, true, true, specular, L(in.prev_pdf));
        put(esc.r), put(esc.g), put(esc.b);
        const RGB<F> esc_nee = escaped_radiance<F>(*in.lights, d, false, true, specular, L(in.prev_pdf));
        put(esc_nee.r);
        // NEE's pick of a light from u[0] (pick_light_lanes).
        F sel;
        const IntT<F> picked = pick_light_lanes<F>(*in.lights, L(in.u[0]), &sel);
        put(lane::to_float(picked)), put(sel);  // 17, 18
        // What the shadow ray is built from: the light's point, normal and error bound (19..27),
        // and whether the light is a delta (28).
        put(ls.p.x), put(ls.p.y), put(ls.p.z), put(ls.n.x), put(ls.n.y), put(ls.n.z);
        put(ls.err.x), put(ls.err.y), put(ls.err.z), putm(ls.delta);
        // The spot falloff alone at the lane's u[1] as a cosine (29), and the point light's radiance
        // at p from the lane's row read as a point (30, 31).
        put(spot_falloff<F>(L(in.u[1]) * F(2.f) - F(1.f), F(0.9f), F(0.45f), F(0.2f)));
        const DeltaLightSample<F> pt = point_light_sample<F>(V3<F>(F(0.25f), F(-0.125f), F(0.375f)), RGB<F>(F(3.f)), p);
        put(pt.L.r), putm(pt.valid);
    }
}
}  // namespace pellucid::envmap_probe
