// What tests/cpp/bxdf/test_dielectric_lanes.cpp compares across lane types: the rough dielectrics'
// packet forms (RoughDielectricT over GGXT and over BeckmannT) built from packet parameters by
// rough_dielectric_lanes, as the path tracer builds them, evaluated over arrays of cases,
// kLaneWidth<F> lanes at a time: eval_pdf and sample in both transport modes under three sets of
// allowed lobes; and the half-vector step itself (dielectric_half_lanes: every field, on the active
// lanes, the masked lanes' defaults included) and the Fresnel pair (dielectric_fresnel_pair_lanes)
// at a cosine of its own. It is instantiated on float in the test and on each SIMD target's packet in
// dielectric_probe_<target>.cpp (built with that target's flags, exporting only its entry point,
// as the renderer's kernels do).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include "pellucid/bxdf/dielectric.h"

namespace pellucid::dielectric_probe {

/// Inputs, one array entry per case; n is a multiple of 16. q[k] holds each case's packet parameter
/// k (rough_dielectric_packet_params); kind is 1 for GGX, 2 for Beckmann and 0 for a lane of another
/// model, whose parameters are not a dielectric's.
struct In {
    int n = 0;
    const float* q[kRoughDielectricParams];
    const float *wo[3], *wi[3], *u[3];
    const float* cos_i;  ///< the Fresnel pair's cosine
    const int32_t* kind;
    const bool* active;
};
/// The contexts: both modes with every lobe, then reflection only and transmission only.
constexpr int kContexts = 4;
constexpr TransportMode kMode[kContexts] = {TransportMode::Radiance, TransportMode::Importance, TransportMode::Radiance,
                                            TransportMode::Radiance};
constexpr BxDFFlags kAllowed[kContexts] = {BxDFFlags::All, BxDFFlags::All, BxDFFlags::Reflection | BxDFFlags::Glossy,
                                           BxDFFlags::Transmission | BxDFFlags::Glossy};
/// Per context: eval (3), pdf, and the sample's valid, wi (3), weight (3), pdf, η and lobe.
constexpr int kPerContext = 14;
/// Then the half-vector step: wm (3), dot_o, dot_i, R, T, denom, η'², ok; and the Fresnel pair R, T.
constexpr int kHalf = kContexts * kPerContext;
constexpr int kFresnelPair = kHalf + 10;
constexpr int kOutputs = kFresnelPair + 2;
/// Outputs, one array of n floats per quantity (masks as 0/1; 0 on inactive and other lanes).
struct Out {
    float* v[kOutputs];
};

template <class F>
void run(const In& in, Out& out) {
    constexpr int W = kLaneWidth<F>;
    using M = MaskT<F>;
    alignas(64) bool act[W];
    for (int o = 0; o < in.n; o += W) {
        auto L = [&](const float* a) { return lane::load_as<F>(a + o); };
        for (int i = 0; i < W; ++i) act[i] = in.active[o + i];
        const IntT<F> kind = lane::load_int_as<IntT<F>>(in.kind + o);
        const M ggx = lane::float_mask(kind == IntT<F>(1)), beckmann = lane::float_mask(kind == IntT<F>(2));
        const M shown = lane::load_mask_as<M>(act) && (ggx || beckmann);
        auto q = [&](int k) { return L(in.q[k]); };
        const RoughDielectricT<GGXT, F> dg = rough_dielectric_lanes<GGXT, F>(ggx || beckmann, q);
        const RoughDielectricT<BeckmannT, F> db = rough_dielectric_lanes<BeckmannT, F>(ggx || beckmann, q);
        const V3<F> wo(L(in.wo[0]), L(in.wo[1]), L(in.wo[2])), wi(L(in.wi[0]), L(in.wi[1]), L(in.wi[2]));
        const V2<F> u{L(in.u[1]), L(in.u[2])};
        int k = 0;
        auto put = [&](const F& x) { lane::store(out.v[k++] + o, lane::select(shown, x, F(0.f))); };
        for (int c = 0; c < kContexts; ++c) {
            const BxDFContext ctx{kMode[c], kAllowed[c]};
            const auto eg = dg.eval_pdf(ctx, wo, wi, ggx), eb = db.eval_pdf(ctx, wo, wi, beckmann);
            const RGB<F> f = lane::select(ggx, eg.f, eb.f);
            put(f.r), put(f.g), put(f.b), put(lane::select(ggx, eg.pdf, eb.pdf));
            const BxDFSampleT<F> sg = dg.sample(ctx, wo, L(in.u[0]), u, ggx), sb = db.sample(ctx, wo, L(in.u[0]), u, beckmann);
            put(lane::select(lane::select(ggx, sg.valid, sb.valid), F(1.f), F(0.f)));
            const V3<F> w = lane::select(ggx, sg.wi, sb.wi);
            const RGB<F> wt = lane::select(ggx, sg.weight, sb.weight);
            put(w.x), put(w.y), put(w.z), put(wt.r), put(wt.g), put(wt.b), put(lane::select(ggx, sg.pdf, sb.pdf));
            put(lane::select(ggx, sg.eta, sb.eta));
            put(lane::to_float(lane::select(lane::int_mask(ggx), sg.lobe, sb.lobe)));
        }
        // The half-vector step and the Fresnel pair on the active lanes (lanes of other models
        // included, at their η of 1.5), as they are: the inactive lanes' defaults are compared too.
        const M on = lane::load_mask_as<M>(act);
        auto raw = [&](const F& x) { lane::store(out.v[k++] + o, x); };
        const DielectricHalfT<F> h = dielectric_half_lanes<F>(wo, wi, dg.eta, on);
        raw(h.wm.x), raw(h.wm.y), raw(h.wm.z), raw(h.dot_o), raw(h.dot_i), raw(h.R), raw(h.T), raw(h.denom);
        raw(h.etap2), raw(lane::select(h.ok, F(1.f), F(0.f)));
        F R, T;
        dielectric_fresnel_pair_lanes<F>(L(in.cos_i), dg.eta, on, &R, &T);
        raw(R), raw(T);
    }
}
}  // namespace pellucid::dielectric_probe
