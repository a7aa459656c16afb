// The common part of the lanes-equal-scalars probes of the principled models' packet forms
// (principled_probe.h, principled2012_probe.h): a form with eval_pdf and a masked sample, built from
// packet parameters as the path tracer builds it, evaluated over arrays of cases, kLaneWidth<F>
// lanes at a time, in both transport modes and under three sets of allowed lobes.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include "pellucid/bxdf/bxdf.h"
#include "pellucid/math/lane_types.h"

namespace pellucid::form_probe {

/// Inputs, one array entry per case; n is a multiple of 16. q[k] holds each case's packet parameter
/// k (of K); kind is 1 for a lane of the form and 0 for a lane of another model, whose parameters
/// are not the form's.
template <int K>
struct In {
    int n = 0;
    const float* q[K];
    const float *wo[3], *wi[3], *u[3];
    const int32_t* kind;
    const bool* active;
};
/// The contexts: both modes with every lobe, then glossy reflection only, diffuse reflection only,
/// and glossy transmission only.
constexpr int kContexts = 5;
constexpr TransportMode kMode[kContexts] = {TransportMode::Radiance, TransportMode::Importance, TransportMode::Radiance,
                                            TransportMode::Radiance, TransportMode::Radiance};
constexpr BxDFFlags kAllowed[kContexts] = {BxDFFlags::All, BxDFFlags::All, BxDFFlags::GlossyReflection,
                                           BxDFFlags::DiffuseReflection, BxDFFlags::Transmission | BxDFFlags::Glossy};
/// Per context: eval (3), pdf, and the sample's valid, wi (3), weight (3), pdf, η and lobe.
constexpr int kPerContext = 14;
constexpr int kOutputs = kContexts * kPerContext;
/// Outputs, one array of n floats per quantity (masks as 0/1; 0 on inactive and other lanes).
struct Out {
    float* v[kOutputs];
};

/// build(mine, q) makes the form from the parameters q(k) on the lanes `mine`.
template <class F, int K, class Build>
void run(const In<K>& in, Out& out, Build&& build) {
    constexpr int W = kLaneWidth<F>;
    using M = MaskT<F>;
    alignas(64) bool act[W];
    for (int o = 0; o < in.n; o += W) {
        auto L = [&](const float* a) { return lane::load_as<F>(a + o); };
        for (int i = 0; i < W; ++i) act[i] = in.active[o + i];
        const IntT<F> kind = lane::load_int_as<IntT<F>>(in.kind + o);
        const M mine = lane::float_mask(kind == IntT<F>(1));
        const M shown = lane::load_mask_as<M>(act) && mine;
        const auto b = build(mine, [&](int k) { return L(in.q[k]); });
        const V3<F> wo(L(in.wo[0]), L(in.wo[1]), L(in.wo[2])), wi(L(in.wi[0]), L(in.wi[1]), L(in.wi[2]));
        const V2<F> u{L(in.u[1]), L(in.u[2])};
        int k = 0;
        auto put = [&](const F& x) { lane::store(out.v[k++] + o, lane::select(shown, x, F(0.f))); };
        for (int c = 0; c < kContexts; ++c) {
            const BxDFContext ctx{kMode[c], kAllowed[c]};
            const auto ep = b.eval_pdf(ctx, wo, wi, shown);
            put(ep.f.r), put(ep.f.g), put(ep.f.b), put(ep.pdf);
            const BxDFSampleT<F> s = b.sample(ctx, wo, L(in.u[0]), u, shown);
            put(lane::select(s.valid, F(1.f), F(0.f)));
            put(s.wi.x), put(s.wi.y), put(s.wi.z), put(s.weight.r), put(s.weight.g), put(s.weight.b), put(s.pdf);
            put(s.eta);
            put(lane::to_float(s.lobe));
        }
    }
}
}  // namespace pellucid::form_probe
