// What tests/cpp/integrator/test_form_lanes.cpp checks on the AVX-512 target: packet forms called
// through FormLanesHalf (the lanes that take part moved into the half-width packet) give, on those
// lanes, the bits FormLanesWhole (the whole packet, masked) gives, and leave the other lanes as they
// were. The forms are the rough dielectrics and the rough conductors over GGX and Beckmann, built
// from packet parameters as the path tracer builds them; each call's eval_pdf and sample are
// compared, every field. Built in form_lanes_probe_avx512.cpp with that target's flags, exporting
// only its entry point.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstring>

#include "pellucid/bxdf/conductor.h"
#include "pellucid/bxdf/dielectric.h"
#include "pellucid/integrator/form_lanes.h"

namespace pellucid::form_lanes_probe {

/// One array entry per case, n a multiple of 16: the packet parameters q[0..12) (a rough
/// dielectric's for the dielectric calls; q[0..9) read as a conductor's η, k and reflectance, q[9..12)
/// as α and the shadowing for the conductor calls), wo, wi, the three sample numbers u, and the
/// lanes that take part in each packet's call.
struct In {
    int n = 0;
    const float* q[12];
    const float *wo[3], *wi[3], *u[3];
    const bool* on;
};
struct Result {
    long compared = 0;    ///< lane values compared
    long differing = 0;   ///< of them, those whose bits differ
    long half_calls = 0;  ///< calls whose lanes (at most half) went through FormLanesHalf
};

template <class F>
Result run(const In& in) {
    constexpr int W = kLaneWidth<F>;
    using M = MaskT<F>;
    Result r;
    for (int o = 0; o < in.n; o += W) {
        auto L = [&](const float* a) { return lane::load_as<F>(a + o); };
        const M where = lane::load_mask_as<M>(in.on + o);
        if (!lane::any(where)) continue;
        const FormLanesHalf<F> half(where);
        if (half.move.count() > W / 2) continue;
        ++r.half_calls;
        const FormLanesWhole<F> whole{where};
        const V3<F> wo(L(in.wo[0]), L(in.wo[1]), L(in.wo[2])), wi(L(in.wi[0]), L(in.wi[1]), L(in.wi[2]));
        const F u0 = L(in.u[0]);
        const V2<F> u{L(in.u[1]), L(in.u[2])};
        // Each output starts from the same values off the lanes `where`: -7, and valid on them.
        const F other(-7.f);
        alignas(64) float x[W], y[W];
        auto same = [&](const F& a, const F& b) {
            lane::store(x, a), lane::store(y, b);
            for (int i = 0; i < W; ++i) r.differing += std::memcmp(x + i, y + i, sizeof(float)) != 0;
            r.compared += W;
        };
        // eval_pdf and sample of the form make(c), on both FormLanes.
        auto check = [&](const auto& make, auto call_eval, auto call_sample) {
            RGB<F> f[2] = {RGB<F>(other), RGB<F>(other)};
            F pdf[2] = {other, other};
            BxDFSampleT<F> s[2];
            for (auto& si : s) si = {!where, V3<F>(other), RGB<F>(other), other, other, IntT<F>(-7)};
            auto one = [&](const auto& c, int k) {
                const auto form = make(c);
                const auto ep = call_eval(form, c);
                c.put(f[k], ep.f), c.put(pdf[k], ep.pdf);
                put_sample(c, s[k], call_sample(form, c));
            };
            one(whole, 0), one(half, 1);
            same(f[0].r, f[1].r), same(f[0].g, f[1].g), same(f[0].b, f[1].b), same(pdf[0], pdf[1]);
            same(lane::select(s[0].valid, F(1.f), F(0.f)), lane::select(s[1].valid, F(1.f), F(0.f)));
            same(s[0].wi.x, s[1].wi.x), same(s[0].wi.y, s[1].wi.y), same(s[0].wi.z, s[1].wi.z);
            same(s[0].weight.r, s[1].weight.r), same(s[0].weight.g, s[1].weight.g), same(s[0].weight.b, s[1].weight.b);
            same(s[0].pdf, s[1].pdf), same(s[0].eta, s[1].eta);
            same(lane::to_float(s[0].lobe), lane::to_float(s[1].lobe));
        };
        const BxDFContext ctx{TransportMode::Radiance, BxDFFlags::All};
        auto masked_eval = [&](const auto& form, const auto& c) { return form.eval_pdf(ctx, c.in(wo), c.in(wi), c.in(where)); };
        auto masked_sample = [&](const auto& form, const auto& c) {
            return form.sample(ctx, c.in(wo), c.in(u0), c.in(u), c.in(where));
        };
        auto eval = [&](const auto& form, const auto& c) { return form.eval_pdf(ctx, c.in(wo), c.in(wi)); };
        auto sample = [&](const auto& form, const auto& c) { return form.sample(ctx, c.in(wo), c.in(u0), c.in(u)); };
        auto params = [&](const auto& c) {
            using LT = typename std::decay_t<decltype(c)>::L;
            return [&c, &L, &in](int k) { return LT(c.in(L(in.q[k]))); };
        };
        check([&](const auto& c) { return rough_dielectric_lanes<GGXT, typename std::decay_t<decltype(c)>::L>(c.in(where), params(c)); },
              masked_eval, masked_sample);
        check([&](const auto& c) { return rough_dielectric_lanes<BeckmannT, typename std::decay_t<decltype(c)>::L>(c.in(where), params(c)); },
              masked_eval, masked_sample);
        check([&](const auto& c) { return rough_conductor_lanes<GGXT, typename std::decay_t<decltype(c)>::L>(c.in(where), params(c)); },
              eval, sample);
        check([&](const auto& c) {
                  return rough_conductor_lanes<BeckmannT, typename std::decay_t<decltype(c)>::L>(c.in(where), params(c));
              },
              eval, sample);
    }
    return r;
}

}  // namespace pellucid::form_lanes_probe
