// What tests/cpp/bxdf/test_oren_thin_lanes.cpp compares across lane types: the packet forms of
// Oren–Nayar (OrenNayarT, classic and EON, built from packet parameters by oren_nayar_lanes) and of
// the thin dielectric (ThinDielectricT, from the smooth dielectric's parameter layout), as the path
// tracer builds them, evaluated over arrays of cases, kLaneWidth<F> lanes at a time: eval, pdf and
// sample in both transport modes under three sets of allowed lobes. It is instantiated on float in
// the test and on each SIMD target's packet in oren_thin_probe_<target>.cpp (built with that
// target's flags, exporting only its entry point, as the renderer's kernels do).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include "pellucid/bxdf/dielectric.h"
#include "pellucid/bxdf/oren_nayar.h"

namespace pellucid::oren_thin_probe {

/// Packet parameters per case (the larger of the two layouts).
constexpr int kParams = kOrenNayarParams;
/// Inputs, one array entry per case; n is a multiple of 16. q[k] holds each case's packet parameter
/// k (oren_nayar_packet_params, or η, reflectance and transmittance of a thin dielectric); kind is
/// 1 for a thin dielectric, 2 for Oren–Nayar and 0 for a lane of another model, whose parameters are
/// neither's.
struct In {
    int n = 0;
    const float* q[kParams];
    const float *wo[3], *wi[3], *u[3];
    const int32_t* kind;
    const bool* active;
};
/// The contexts: both modes with every lobe, then reflection only and transmission only.
constexpr int kContexts = 4;
constexpr TransportMode kMode[kContexts] = {TransportMode::Radiance, TransportMode::Importance, TransportMode::Radiance,
                                            TransportMode::Radiance};
constexpr BxDFFlags kAllowed[kContexts] = {BxDFFlags::All, BxDFFlags::All, BxDFFlags::Reflection | BxDFFlags::Specular,
                                           BxDFFlags::Transmission | BxDFFlags::Glossy};
/// Per context: eval (3), pdf, and the sample's valid, wi (3), weight (3), pdf, η and lobe.
constexpr int kPerContext = 14;
constexpr int kOutputs = kContexts * kPerContext;
/// Outputs, one array of n floats per quantity (masks as 0/1; 0 on inactive and other lanes; eval
/// and pdf of a thin dielectric, a delta form, are 0).
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
        const M thin = lane::float_mask(kind == IntT<F>(1)), on = lane::float_mask(kind == IntT<F>(2));
        const M shown = lane::load_mask_as<M>(act) && (thin || on);
        auto q = [&](int k) { return L(in.q[k]); };
        const OrenNayarT<F> rough = oren_nayar_lanes<F>(on, q);
        const ThinDielectricT<F> slab{q(0), RGB<F>(q(1), q(2), q(3)), RGB<F>(q(4), q(5), q(6))};
        const V3<F> wo(L(in.wo[0]), L(in.wo[1]), L(in.wo[2])), wi(L(in.wi[0]), L(in.wi[1]), L(in.wi[2]));
        const V2<F> u{L(in.u[1]), L(in.u[2])};
        int k = 0;
        auto put = [&](const F& x) { lane::store(out.v[k++] + o, lane::select(shown, x, F(0.f))); };
        for (int c = 0; c < kContexts; ++c) {
            const BxDFContext ctx{kMode[c], kAllowed[c]};
            const RGB<F> f = lane::select(on, rough.eval(ctx, wo, wi), RGB<F>(F(0.f)));
            put(f.r), put(f.g), put(f.b), put(lane::select(on, rough.pdf(ctx, wo, wi), F(0.f)));
            const BxDFSampleT<F> so = rough.sample(ctx, wo, L(in.u[0]), u), st = slab.sample(ctx, wo, L(in.u[0]), u);
            put(lane::select(lane::select(on, so.valid, st.valid), F(1.f), F(0.f)));
            const V3<F> w = lane::select(on, so.wi, st.wi);
            const RGB<F> wt = lane::select(on, so.weight, st.weight);
            put(w.x), put(w.y), put(w.z), put(wt.r), put(wt.g), put(wt.b), put(lane::select(on, so.pdf, st.pdf));
            put(lane::select(on, so.eta, st.eta));
            put(lane::to_float(lane::select(lane::int_mask(on), so.lobe, st.lobe)));
        }
    }
}
}  // namespace pellucid::oren_thin_probe
