// Lanes equal scalars for the thin-sheet principled BSDF's packet form
// (bxdf/principled_thin_probe.h): on every lane of every SIMD target, eval, pdf and sample give
// exactly the bits the float instantiation gives for that lane's inputs (a bound of 0 ulp: the
// library and the probes are built without contraction, and the form uses only IEEE-exact lane
// operations). The float instantiation, built from packet parameters as the path tracer builds it,
// in turn gives the bits of the scalar BxDF API (PrincipledBSDF where thin()).
//
// Cases: the property suite's thin principled BSDFs (bxdf_cases.h: its cases and its sweep over
// roughness, η, specular and diffuse transmission and the tints) and a few more (η = 1, a sheet all
// diffuse transmission, a tinted specular sheet), one material per lane at random so every packet
// mixes materials; lanes of other models and partially masked packets; directions on, near and
// below the horizon, at the normal, in the mirror direction and straight through; u at 0, 1/2 and
// 1 − 2⁻²⁴; both transport modes and glossy-only, diffuse-only and transmission-only contexts.
//
// Renders: bench/suite/principled.json's thin sheet (`leaf`) is a packet form, and the scene gives
// the scalar target's image bit for bit on every SIMD target (test_principled_lanes.cpp).
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

#include "bxdf/bxdf_cases.h"
#include "bxdf/principled_thin_probe.h"
#include "pellucid/api.h"
#include "pellucid/integrator/path_services.h"
#include "pellucid/integrator/simd_target.h"
#include "pellucid/scene/json_io.h"
#include "pellucid/sampling/rng.h"
#include "pellucid/sampling/warp.h"
#include "support/probe_outputs.h"

using namespace pellucid;

namespace pellucid::principled_thin_probe {
#ifdef PELLUCID_PRINCIPLED_THIN_PROBE_AVX512
void run_avx512(const In& in, Out& out);
#endif
#ifdef PELLUCID_PRINCIPLED_THIN_PROBE_AVX2
void run_avx2(const In& in, Out& out);
#endif
#ifdef PELLUCID_PRINCIPLED_THIN_PROBE_SSE4
void run_sse4(const In& in, Out& out);
#endif
}  // namespace pellucid::principled_probe

namespace {
constexpr int kP = kPrincipledThinParams;

/// The property suite's thin principled BSDFs, and a few more.
std::vector<PrincipledBSDF> materials() {
    std::vector<PrincipledBSDF> m;
    using test::BxDFCases;
    auto add = [&](const PrincipledBSDF& b) {
        if (b.thin()) m.push_back(b);
    };
    for (const auto& c : BxDFCases<PrincipledBSDF>::cases()) add(c.bxdf);
    for (const auto& b : BxDFCases<PrincipledBSDF>::sweep()) add(b);
    PrincipledInputs p;
    p.variant = PrincipledVariant::Burley2015;
    p.thin = true;
    p.base_color = Spectrum(0.2f, 0.5f, 0.9f);
    p.roughness = 0.35f;
    p.anisotropic = 0.6f;
    p.sheen = 0.8f;
    p.sheen_tint = 0.7f;
    p.specular_tint = 0.6f;
    p.specular_transmission = 0.4f;
    p.diffuse_transmission = 0.7f;
    add(PrincipledBSDF(p));
    p.eta = 1.f;  // F_η = 0: no specular reflection value, but its lobe is still sampled
    add(PrincipledBSDF(p));
    p.eta = 0.f;
    p.specular_transmission = 0.f;
    p.diffuse_transmission = 2.f;  // all diffuse transmission
    add(PrincipledBSDF(p));
    p.specular_transmission = 1.f;  // all specular
    p.roughness = 0.05f;
    add(PrincipledBSDF(p));
    return m;
}

struct Cases {
    static constexpr int kN = 16384;
    std::vector<PrincipledBSDF> mats = materials();
    std::vector<float> params;  // kP per material
    std::vector<float> q[kP], a[9];
    std::vector<int> mat;  // -1: a lane of another model
    std::vector<int32_t> kind;
    std::unique_ptr<bool[]> active{new bool[kN]};
    principled_thin_probe::In in;

    Cases() {
        params.resize(mats.size() * kP);
        for (size_t m = 0; m < mats.size(); ++m) principled_thin_packet_params(mats[m].thin_lanes(), &params[m * kP]);
        PCG32 rng(9, 31);
        for (auto& v : q) v.resize(kN);
        for (auto& v : a) v.resize(kN);
        mat.resize(kN);
        kind.resize(kN);
        auto dir = [&](int i, int at) {
            const Vec3f w = square_to_uniform_sphere(Vec2f(rng.next_float(), rng.next_float()));
            for (int c = 0; c < 3; ++c) a[at + c][size_t(i)] = w[c];
        };
        const float us[] = {0.f, 0.5f, kOneMinusEpsilon, 1e-7f};
        for (int i = 0; i < kN; ++i) {
            const size_t k = size_t(i);
            mat[k] = i % 13 == 5 ? -1 : int(rng.next_u32() % uint32_t(mats.size()));
            dir(i, 0), dir(i, 3);
            float *wo[3] = {&a[0][k], &a[1][k], &a[2][k]}, *wi[3] = {&a[3][k], &a[4][k], &a[5][k]};
            switch (i % 11) {  // edge cases
                case 1: *wo[2] = 0.f; break;                                             // wo on the horizon
                case 2: *wi[2] = 1e-7f; break;                                           // wi grazing
                case 3: *wo[0] = -*wi[0], *wo[1] = -*wi[1], *wo[2] = *wi[2]; break;      // the mirror direction
                case 4: *wo[0] = *wo[1] = 0.f, *wo[2] = 1.f; break;                      // wo at the normal
                case 5: *wi[2] = -std::fabs(*wi[2]), *wo[2] = std::fabs(*wo[2]); break;  // a transmission pair
                case 6: *wo[2] = -std::fabs(*wo[2]), *wi[2] = -std::fabs(*wi[2]); break; // from behind
                case 7: *wo[2] = 1e-7f; break;                                           // wo grazing
                case 8: *wi[0] = -*wo[0], *wi[1] = -*wo[1], *wi[2] = -*wo[2]; break;     // straight through
                case 9: *wo[2] = -1e-6f, *wi[2] = -std::fabs(*wi[2]); break;             // grazing from behind
                default: break;
            }
            for (int c = 0; c < 3; ++c) a[6 + c][k] = i % 7 < 4 ? us[(i / 7 + c) % 4] : rng.next_float();
            for (int p = 0; p < kP; ++p) q[p][k] = mat[k] >= 0 ? params[size_t(mat[k]) * kP + size_t(p)] : 1e6f + float(p);
            kind[k] = mat[k] < 0 ? 0 : 1;
            active[i] = (i / 16) % 3 != 1 || i % 5 != 0;  // every third packet partially masked
        }
        in.n = kN;
        for (int p = 0; p < kP; ++p) in.q[p] = q[p].data();
        for (int c = 0; c < 3; ++c) in.wo[c] = a[c].data(), in.wi[c] = a[3 + c].data(), in.u[c] = a[6 + c].data();
        in.kind = kind.data();
        in.active = active.get();
    }
    Vec3f wo(int i) const { return Vec3f(a[0][size_t(i)], a[1][size_t(i)], a[2][size_t(i)]); }
    Vec3f wi(int i) const { return Vec3f(a[3][size_t(i)], a[4][size_t(i)], a[5][size_t(i)]); }
};

using Outputs = test::ProbeOutputs<principled_thin_probe::Out, principled_thin_probe::kOutputs, Cases::kN>;
using test::same_bits;

void expect_equal(const Outputs& scalar, const Outputs& packet, const char* target) {
    EXPECT_EQ(test::count_differing(scalar, packet, target), 0u) << target;
}
}  // namespace

TEST(PrincipledThinLanes, TheGridIsCovered) {
    const Cases cases;
    EXPECT_GE(cases.mats.size(), 30u);
    // Every lobe of the model is present in some material.
    bool spec = false, diff_t = false, diff_r = false, tint = false, sheen = false;
    for (const auto& m : cases.mats) {
        const PrincipledThinT<float> l = m.thin_lanes();
        spec = spec || l.st > 0.f;
        diff_t = diff_t || (l.st < 1.f && l.dt > 0.f);
        diff_r = diff_r || (l.st < 1.f && l.dt < 1.f);
        tint = tint || l.spec_tint > 0.f;
        sheen = sheen || (l.sheen > 0.f && l.sheen_tint > 0.f);
    }
    EXPECT_TRUE(spec && diff_t && diff_r && tint && sheen);
}

TEST(PrincipledThinLanes, FloatInstantiationIsTheScalarBxDF) {
    // The float instantiation from packet parameters gives the scalar API's bits: eval, pdf and
    // sample in each context, case by case; many cases sample each lobe.
    const Cases cases;
    Outputs scalar;
    principled_thin_probe::run<float>(cases.in, scalar.out);
    size_t compared = 0, differ = 0, diffuse = 0, glossy = 0, nonzero = 0;
    auto check = [&](float x, float y, int k, int i) {
        ++compared;
        if (!same_bits(x, y) && ++differ <= 5)
            ADD_FAILURE() << "output " << k << " case " << i << ": packet form " << x << ", BxDF " << y;
    };
    for (int i = 0; i < Cases::kN; ++i) {
        if (cases.mat[size_t(i)] < 0 || !cases.active[i]) continue;
        const PrincipledBSDF& b = cases.mats[size_t(cases.mat[size_t(i)])];
        const Vec3f wo = cases.wo(i), wi = cases.wi(i);
        const Vec2f u(cases.a[7][size_t(i)], cases.a[8][size_t(i)]);
        for (int c = 0; c < principled_thin_probe::kContexts; ++c) {
            const BxDFContext ctx{principled_thin_probe::kMode[c], principled_thin_probe::kAllowed[c]};
            const int k0 = c * principled_thin_probe::kPerContext;
            const Spectrum f = b.eval(ctx, wo, wi);
            nonzero += !f.is_black();
            for (int ch = 0; ch < 3; ++ch) check(scalar.at(k0 + ch, i), f[ch], k0 + ch, i);
            check(scalar.at(k0 + 3, i), b.pdf(ctx, wo, wi), k0 + 3, i);
            const auto s = b.sample(ctx, wo, cases.a[6][size_t(i)], u);
            check(scalar.at(k0 + 4, i), s ? 1.f : 0.f, k0 + 4, i);
            if (!s) continue;
            (has_flag(s->lobe, BxDFFlags::Diffuse) ? diffuse : glossy) += 1;
            for (int ch = 0; ch < 3; ++ch) check(scalar.at(k0 + 5 + ch, i), s->wi[ch], k0 + 5 + ch, i);
            for (int ch = 0; ch < 3; ++ch) check(scalar.at(k0 + 8 + ch, i), s->weight[ch], k0 + 8 + ch, i);
            check(scalar.at(k0 + 11, i), s->pdf, k0 + 11, i);
            check(scalar.at(k0 + 12, i), s->eta, k0 + 12, i);
            check(scalar.at(k0 + 13, i), float(uint32_t(s->lobe)), k0 + 13, i);
        }
    }
    EXPECT_EQ(differ, 0u) << "of " << compared;
    EXPECT_GT(diffuse, size_t(Cases::kN) / 4);
    EXPECT_GT(glossy, size_t(Cases::kN));
    EXPECT_GT(nonzero, size_t(Cases::kN));
}

TEST(PrincipledThinLanes, EveryTargetEveryLane) {
    const Cases cases;
    Outputs scalar;
    principled_thin_probe::run<float>(cases.in, scalar.out);
    int targets = 0;
    for (SimdTarget t : available_simd_targets()) {
        Outputs packet;
        switch (t) {
#ifdef PELLUCID_PRINCIPLED_THIN_PROBE_AVX512
            case SimdTarget::AVX512: principled_thin_probe::run_avx512(cases.in, packet.out); break;
#endif
#ifdef PELLUCID_PRINCIPLED_THIN_PROBE_AVX2
            case SimdTarget::AVX2: principled_thin_probe::run_avx2(cases.in, packet.out); break;
#endif
#ifdef PELLUCID_PRINCIPLED_THIN_PROBE_SSE4
            case SimdTarget::SSE4: principled_thin_probe::run_sse4(cases.in, packet.out); break;
#endif
            default: continue;
        }
        ++targets;
        expect_equal(scalar, packet, to_string(t).c_str());
    }
    RecordProperty("targets", targets);
}

TEST(PrincipledThinLanes, ACaseChangedInOneLaneIsSeen) {
    // The comparison itself: another specular transmission in one lane must change that lane's
    // outputs only.
    Cases cases;
    Outputs a, b;
    principled_thin_probe::run<float>(cases.in, a.out);
    int lane = 0;
    while (!(cases.kind[size_t(lane)] == 1 && cases.active[lane] && cases.wo(lane).z > 0.1f && cases.wi(lane).z > 0.1f &&
             cases.q[12][size_t(lane)] > 0.f))
        ++lane;
    const_cast<float*>(cases.in.q[12])[lane] *= 0.5f;
    principled_thin_probe::run<float>(cases.in, b.out);
    const std::vector<int> changed = test::differing_cases(a, b);
    EXPECT_FALSE(changed.empty());
    for (int i : changed) EXPECT_EQ(i, lane);
}

