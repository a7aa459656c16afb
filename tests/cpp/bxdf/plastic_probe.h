// What tests/cpp/bxdf/test_plastic_lanes.cpp compares across lane types: the plastics' packet form
// (RoughPlasticT over GGXT, whose effectively smooth lanes are SmoothPlasticT) built from packet
// parameters by plastic_lanes, as the path tracer builds it, evaluated over arrays of cases,
// kLaneWidth<F> lanes at a time: eval, pdf and sample under three sets of allowed lobes. It is
// instantiated on float in the test and on each SIMD target's packet in plastic_probe_<target>.cpp
// (built with that target's flags, exporting only its entry point, as the renderer's kernels do).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include "pellucid/bxdf/plastic.h"

namespace pellucid::plastic_probe {

/// Inputs, one array entry per case; n is a multiple of 16. q[k] holds each case's packet
/// parameter k (plastic_packet_params); `plastic` false marks a lane of another model, whose
/// parameters are not a plastic's (the path tracer's other packet kinds).
struct In {
    int n = 0;
    const float* q[kPlasticParams];
    const float *wo[3], *wi[3], *u[3];
    const bool *plastic, *active;
    const float* tables = nullptr;
};
/// The lobes allowed in each context: all, the base only, the coat only.
constexpr int kContexts = 3;
constexpr BxDFFlags kAllowed[kContexts] = {BxDFFlags::All, BxDFFlags::DiffuseReflection,
                                           BxDFFlags::GlossyReflection | BxDFFlags::SpecularReflection};
/// Per context: eval (3), pdf, and the sample's valid, wi (3), weight (3), pdf and lobe.
constexpr int kPerContext = 13;
constexpr int kOutputs = kContexts * kPerContext;
/// Outputs, one array of n floats per quantity (masks as 0/1; 0 on inactive and non-plastic lanes).
struct Out {
    float* v[kOutputs];
};

template <class F>
void run(const In& in, Out& out) {
    constexpr int W = kLaneWidth<F>;
    using M = MaskT<F>;
    alignas(64) bool act[W], pla[W];
    for (int o = 0; o < in.n; o += W) {
        auto L = [&](const float* a) { return lane::load_as<F>(a + o); };
        for (int i = 0; i < W; ++i) act[i] = in.active[o + i], pla[i] = in.plastic[o + i];
        const M where = lane::load_mask_as<M>(pla);
        const M shown = lane::load_mask_as<M>(act) && where;
        const RoughPlasticT<F, GGXT<F>> plastic = plastic_lanes<F>(where, [&](int k) { return L(in.q[k]); }, in.tables);
        const V3<F> wo(L(in.wo[0]), L(in.wo[1]), L(in.wo[2])), wi(L(in.wi[0]), L(in.wi[1]), L(in.wi[2]));
        const V2<F> u{L(in.u[1]), L(in.u[2])};
        int k = 0;
        auto put = [&](const F& x) { lane::store(out.v[k++] + o, lane::select(shown, x, F(0.f))); };
        for (int c = 0; c < kContexts; ++c) {
            const BxDFContext ctx{TransportMode::Radiance, kAllowed[c]};
            const RGB<F> f = plastic.eval(ctx, wo, wi);
            put(f.r), put(f.g), put(f.b), put(plastic.pdf(ctx, wo, wi));
            const BxDFSampleT<F> s = plastic.sample(ctx, wo, L(in.u[0]), u);
            put(lane::select(s.valid, F(1.f), F(0.f)));
            put(s.wi.x), put(s.wi.y), put(s.wi.z), put(s.weight.r), put(s.weight.g), put(s.weight.b), put(s.pdf);
            put(lane::to_float(s.lobe));
        }
    }
}
}  // namespace pellucid::plastic_probe
