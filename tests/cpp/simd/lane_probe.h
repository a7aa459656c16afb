// What tests/cpp/simd/test_lanes_equal_scalars.cpp compares across lane types: the packet code of
// the path tracer (Lambertian, Fresnel terms, the conductors on GGX and Beckmann, warps, frames, ray
// offsets, the power heuristic, the bump terminator factors, emitter sampling, the packet lights:
// spheres and constant environments, rows read by lane::gather_rows, the homogeneous media's
// distance sampling)
// evaluated over arrays of inputs, kLaneWidth<F> lanes at a time. It is instantiated on float in
// the test and on each SIMD target's packet in probe_<target>.cpp (built with that target's flags,
// exporting only its entry point, as the renderer's kernels do).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>

#include "pellucid/bxdf/bsdf.h"
#include "pellucid/bxdf/conductor.h"
#include "pellucid/bxdf/fresnel.h"
#include "pellucid/bxdf/lambertian.h"
#include "pellucid/light/area.h"
#include "pellucid/light/light_table.h"
#include "pellucid/math/frame.h"
#include "pellucid/math/ray.h"
#include "pellucid/medium/medium.h"
#include "pellucid/sampling/mis.h"
#include "pellucid/sampling/warp.h"

namespace pellucid::probe {

/// Inputs, one array entry per case; n is a multiple of 16. Plain pointers: the probes touch no
/// container code, so they instantiate nothing shared with other objects.
struct In {
    int n = 0;
    const float *wo[3], *wi[3], *n_[3], *albedo[3], *u[3], *p[3], *err[3], *pdf_a, *pdf_b;
    const bool* active;
    const EmitterTable* emitters = nullptr;
    const LightTable* lights = nullptr;
    const int32_t* light = nullptr;  ///< per case, a row of `lights`
};
/// Outputs, one array of n floats per quantity (masks as 0/1), zeroed by the caller.
constexpr int kOutputs = 144;
struct Out {
    float* v[kOutputs];
};

/// The Beckmann rough conductor (RoughConductorBeckmannT) and its distribution's pieces, with α from
/// the inputs (0 included, clamped as Beckmann's constructor does; anisotropic), separable shadowing
/// on half of the cases; and its transcendental functions over their whole ranges: e^x for
/// x ∈ [−100, 100] (both clamps), ln on (0, 1), erfc on [0, 10], erf⁻¹ on [−1, 1).
template <class F, class Load, class Put, class PutM>
void beckmann(const In& in, const Load& L, const V3<F>& wo, const V3<F>& wi, const V3<F>& nrm,
              const SmoothConductorT<F>& metal, const Put& put, const PutM& putm) {
    using namespace microfacet_detail;
    const BxDFContext ctx{};
    const F ax = lane::max(F(1.5f) * L(in.albedo[0]) * L(in.albedo[0]), F(1e-4f)), ay = lane::max(L(in.albedo[2]), F(1e-4f));
    const RoughConductorBeckmannT<F> b{BeckmannT<F>{ax, ay, L(in.u[1]) < F(0.5f)}, metal};
    const RGB<F> f = b.eval(ctx, wo, wi);
    put(f.r), put(f.g), put(f.b), put(b.pdf(ctx, wo, wi));
    const BxDFSampleT<F> s = b.sample(ctx, wo, L(in.u[0]), V2<F>{L(in.u[1]), L(in.u[2])});
    putm(s.valid), put(s.wi.x), put(s.wi.y), put(s.wi.z), put(s.weight.r), put(s.weight.b), put(s.pdf);
    const V3<F> m = b.d.sample_visible(wo, V2<F>{L(in.u[2]), L(in.u[0])});
    put(m.x), put(m.y), put(m.z), put(b.d.G(wo, wi)), put(b.d.lambda(wi)), put(b.d.D(normalize(nrm)));
    put(b.d.pdf_visible(wo, normalize(nrm)));
    const F u0 = L(in.u[0]), u1 = L(in.u[1]), u2 = L(in.u[2]);
    put(exp_t(F(200.f) * (u0 - F(0.5f))));
    put(log_t(lane::max(u1, F(1e-30f))));
    put(erfc_t(F(10.f) * u2));
    put(erfinv_t(F(2.f) * u0 - F(1.f), F(4.f) * u0 * (F(1.f) - u0)));
}

template <class F>
void run(const In& in, Out& out) {
    constexpr int W = kLaneWidth<F>;
    using M = MaskT<F>;
    alignas(64) bool act[W];
    for (int o = 0; o < in.n; o += W) {
        auto L = [&](const float* a) { return lane::load_as<F>(a + o); };
        auto V = [&](const float* const* a) { return V3<F>(L(a[0]), L(a[1]), L(a[2])); };
        for (int i = 0; i < W; ++i) act[i] = in.active[o + i];
        const M active = lane::load_mask_as<M>(act);
        int k = 0;
        auto put = [&](const F& x) { lane::store(out.v[k++] + o, lane::select(active, x, F(0.f))); };
        auto putm = [&](const M& m) { put(lane::select(m, F(1.f), F(0.f))); };
        const V3<F> wo = V(in.wo), wi = V(in.wi), nrm = V(in.n_);
        const LambertianT<F> lam{RGB<F>(L(in.albedo[0]), L(in.albedo[1]), L(in.albedo[2]))};
        const BxDFContext ctx{};
        const RGB<F> f = lam.eval(ctx, wo, wi);
        put(f.r), put(f.g), put(f.b), put(lam.pdf(ctx, wo, wi));
        const BxDFSampleT<F> s = lam.sample(ctx, wo, L(in.u[0]), V2<F>{L(in.u[1]), L(in.u[2])});
        putm(s.valid), put(s.wi.x), put(s.wi.y), put(s.wi.z), put(s.weight.r), put(s.weight.g), put(s.pdf);
        const V2<F> d = square_to_uniform_disk_concentric<F>(V2<F>{L(in.u[0]), L(in.u[1])});
        put(d.x), put(d.y);
        const V2<F> t = square_to_uniform_triangle<F>(V2<F>{L(in.u[1]), L(in.u[2])});
        put(t.x), put(t.y);
        put(power_heuristic<F>(L(in.pdf_a), L(in.pdf_b)));
        const V3<F> po = offset_ray_origin<F>(V(in.p), abs(V(in.err)), normalize(nrm), wi);
        put(po.x), put(po.y), put(po.z);
        const FrameT<F> fr = FrameT<F>::from_xz(wo, normalize(nrm));
        const V3<F> loc = fr.to_local(wi);
        put(loc.x), put(loc.y), put(loc.z);
        putm(shading_leaks<F>(normalize(nrm), wo, wi, fr.to_local(wo), loc));
        // The bump terminator factors of the light wi: Estevez's with the unperturbed normal equal to
        // the shading one, then Estevez's or Chiang's (by u0) about an unperturbed normal tilted
        // toward wi.
        put(terminator_factor<F>(M(true), fr.to_local(wo), loc, wi, fr.n, fr.n));
        put(terminator_factor<F>(L(in.u[0]) < F(0.5f), fr.to_local(wo), loc, wi, normalize(fr.n + F(0.4f) * wi), fr.n));
        // Fresnel: a conductor (η, k from the albedo inputs, which include 0) and a dielectric
        // seen from both sides.
        put(fresnel_conductor<F>(lane::abs(wo.z), F(4.f) * L(in.albedo[0]), F(5.f) * L(in.albedo[1])));
        put(fresnel_dielectric<F>(wo.z, F(1.f) + L(in.albedo[2])));
        // Conductors: the mirror, and GGX rough reflection with anisotropic α from the inputs
        // (clamped as GGX's constructor does), separable shadowing on half of the cases.
        const SmoothConductorT<F> metal{RGB<F>(F(0.2f), F(0.9f), F(1.1f)), RGB<F>(F(3.9f), F(2.4f), F(2.1f)),
                                        RGB<F>(L(in.albedo[0]), F(1.f), L(in.albedo[2]))};
        const BxDFSampleT<F> ms = metal.sample(ctx, wo, L(in.u[0]), V2<F>{L(in.u[1]), L(in.u[2])});
        putm(ms.valid), put(ms.wi.x), put(ms.wi.z), put(ms.weight.r), put(ms.weight.g);
        const F ax = lane::max(L(in.albedo[1]), F(1e-4f)), ay = lane::max(L(in.albedo[2]) * F(0.5f), F(1e-4f));
        const RoughConductorGGXT<F> rough{GGXT<F>{ax, ay, L(in.u[2]) < F(0.5f)}, metal};
        const RGB<F> rf = rough.eval(ctx, wo, wi);
        put(rf.r), put(rf.g), put(rf.b), put(rough.pdf(ctx, wo, wi));
        const BxDFSampleT<F> rs = rough.sample(ctx, wo, L(in.u[0]), V2<F>{L(in.u[1]), L(in.u[2])});
        putm(rs.valid), put(rs.wi.x), put(rs.wi.y), put(rs.wi.z), put(rs.weight.r), put(rs.weight.b), put(rs.pdf);
        const V3<F> vm = rough.d.sample_visible(wo, V2<F>{L(in.u[1]), L(in.u[0])});
        put(vm.x), put(vm.y), put(vm.z), put(rough.d.G(wo, wi)), put(rough.d.D(normalize(nrm)));
        F cphi, sphi;
        detail::sincos_two_pi<F>(L(in.u[1]), &cphi, &sphi);
        put(cphi), put(sphi);
        beckmann<F>(in, L, wo, wi, nrm, metal, put, putm);
        {
            // Homogeneous media (medium/medium.h): ln(1 + x) on (−1, 0], and a distance-sampling
            // step with σt (one channel 0 in a tenth of the cases), σs, Le and the throughput
            // (black in a tenth, negative in a tenth) from the inputs, tmax finite or +∞.
            const F u0 = L(in.u[0]), u1 = L(in.u[1]), u2 = L(in.u[2]);
            put(lane_math::log1p_t(lane::neg(u2)));
            const F st[3] = {F(4.f) * L(in.albedo[0]), lane::select(u2 < F(0.1f), F(0.f), F(3.f) * L(in.albedo[1])),
                             F(0.5f) + L(in.albedo[2])};
            const F ss[3] = {F(0.9f) * st[0], F(0.5f) * st[1], F(0.75f) * st[2]};
            const F le[3] = {L(in.albedo[2]), F(0.f), F(2.f) * u2};
            const F b0 = lane::select(u2 > F(0.9f), F(0.f), lane::select(u2 > F(0.8f), F(-0.5f), u1));
            const F beta[3] = {b0, lane::select(u2 > F(0.9f), F(0.f), u0), lane::select(u2 > F(0.9f), F(0.f), F(0.25f))};
            const F tmax = lane::select(u1 < F(0.3f), F(kInfinity), F(2.f) * u2);
            const HomogeneousStepT<F> h = homogeneous_step<F>(st, ss, le, beta, u0, u1, tmax);
            putm(h.scattered), put(lane::select(h.scattered, h.t, F(0.f)));
            for (int c = 0; c < 3; ++c) put(h.weight[c]), put(h.emitted[c]);
        }
        {
            // Rows read and transposed (lane::gather_rows): 16 and then 8 consecutive inputs from
            // each lane's own offset into the u[0] inputs.
            const IntT<F> off = detail::whole_to_int<F>(lane::floor(L(in.u[1]) * F(float(in.n - 24))));
            F rows[24];
            lane::gather_rows<16>(in.u[0], off, rows);
            lane::gather_rows<8>(in.u[0], off + IntT<F>(16), rows + 16);
            for (const F& r : rows) put(r);
        }
        if (in.emitters) {
            const EmitterSample<F> es = sample_emitter<F>(*in.emitters, L(in.u[0]), V2<F>{L(in.u[1]), L(in.u[2])}, V(in.p));
            putm(es.valid), put(es.p.x), put(es.p.y), put(es.p.z), put(es.wi.x), put(es.pdf), put(es.L.r);
        }
        if (in.lights) {
            const LightTableSample<F> ls = sample_light_table<F>(*in.lights, lane::load_int_as<IntT<F>>(in.light + o), V(in.p),
                                                                 V2<F>{L(in.u[1]), L(in.u[0])});
            putm(ls.valid), putm(ls.infinite), put(ls.p.x), put(ls.p.y), put(ls.p.z), put(ls.n.x), put(ls.n.z);
            put(ls.err.x), put(ls.wi.x), put(ls.wi.y), put(ls.wi.z), put(ls.L.r), put(ls.pdf);
            const V3<F> w = square_to_uniform_sphere_lanes<F>(V2<F>{L(in.u[2]), L(in.u[1])});
            put(w.x), put(w.y), put(w.z);
        }
    }
}
}  // namespace pellucid::probe
