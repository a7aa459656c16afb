// Lanes equal scalars for the packet forms of Oren–Nayar (classic and EON) and of the thin
// dielectric (bxdf/oren_thin_probe.h): on every lane of every SIMD target, eval, pdf and sample give
// exactly the bits the float instantiation gives for that lane's inputs (a bound of 0 ulp: the
// library and the probes are built without contraction, EON's albedo is the float function's own,
// called a lane at a time, and the rest uses only IEEE-exact lane operations, std::max included as
// a select). The float instantiation, built from packet parameters as the path tracer builds it, in
// turn gives the bits of the scalar BxDF API (OrenNayar, ThinDielectric).
//
// Cases: the property suite's Oren–Nayar and thin dielectric materials (bxdf_cases.h: its cases and
// sweeps over σ or r, ρ and η, both sides of 1) and coloured ones, one material per lane at random so
// every packet mixes the two models and both variants; lanes of other models and partially masked
// packets; directions on, near and below the horizon (+0 and −0), at the normal, in the mirror
// direction, back along wo and straight through; u at 0, 1/2 and 1 − 2⁻²⁴; both transport modes and
// reflection-only and transmission-only contexts.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

#include "bxdf/bxdf_cases.h"
#include "bxdf/oren_thin_probe.h"
#include "pellucid/integrator/simd_target.h"
#include "pellucid/sampling/rng.h"
#include "pellucid/sampling/warp.h"
#include "support/probe_outputs.h"

using namespace pellucid;

namespace pellucid::oren_thin_probe {
#ifdef PELLUCID_OREN_THIN_PROBE_AVX512
void run_avx512(const In& in, Out& out);
#endif
#ifdef PELLUCID_OREN_THIN_PROBE_AVX2
void run_avx2(const In& in, Out& out);
#endif
#ifdef PELLUCID_OREN_THIN_PROBE_SSE4
void run_sse4(const In& in, Out& out);
#endif
}  // namespace pellucid::oren_thin_probe

namespace {
namespace probe = oren_thin_probe;

/// The property suite's Oren–Nayar and thin dielectric materials, and coloured ones.
std::vector<BxDF> materials() {
    std::vector<BxDF> m;
    using test::BxDFCases;
    for (const auto& c : BxDFCases<OrenNayar>::cases()) m.emplace_back(c.bxdf);
    for (const auto& b : BxDFCases<OrenNayar>::sweep()) m.emplace_back(b);
    for (const auto& c : BxDFCases<ThinDielectric>::cases()) m.emplace_back(c.bxdf);
    for (const auto& b : BxDFCases<ThinDielectric>::sweep()) m.emplace_back(b);
    m.emplace_back(OrenNayar(Spectrum(0.9f, 0.5f, 0.2f), 0.35f, OrenNayarVariant::Classic));
    m.emplace_back(OrenNayar(Spectrum(0.2f, 0.7f, 0.95f), 0.2f, OrenNayarVariant::EON));
    m.emplace_back(ThinDielectric(1.f / 1.6f, Spectrum(0.9f, 0.5f, 0.f), Spectrum(0.3f, 0.6f, 1.f)));
    m.emplace_back(ThinDielectric(1.7f, Spectrum(0.f), Spectrum(0.8f)));
    return m;
}

struct Cases {
    static constexpr int kN = 16384;
    std::vector<BxDF> mats = materials();
    std::vector<float> params;  // probe::kParams per material
    std::vector<float> q[probe::kParams], a[9];
    std::vector<int> mat;  // -1: a lane of another model
    std::vector<int32_t> kind;
    std::unique_ptr<bool[]> active{new bool[kN]};
    int thin = 0, classic = 0, eon = 0;
    probe::In in;

    Cases() {
        params.assign(mats.size() * probe::kParams, 0.f);
        for (size_t m = 0; m < mats.size(); ++m) {
            float* p = &params[m * probe::kParams];
            if (const auto* o = std::get_if<OrenNayar>(&mats[m])) {
                oren_nayar_packet_params(o->lanes(), p);
                ++(o->lanes().classic ? classic : eon);
            } else {
                const ThinDielectricT<float> t = std::get<ThinDielectric>(mats[m]).lanes();
                p[0] = t.eta;
                for (int c = 0; c < 3; ++c) p[1 + c] = t.r[c], p[4 + c] = t.t[c];
                ++thin;
            }
        }
        PCG32 rng(11, 29);
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
            switch (i % 14) {  // edge cases
                case 1: *wo[2] = 0.f; break;                                                // wo on the horizon
                case 2: *wi[2] = 1e-7f, *wo[2] = std::fabs(*wo[2]); break;                  // wi grazing
                case 3: *wo[0] = -*wi[0], *wo[1] = -*wi[1], *wo[2] = *wi[2]; break;         // the mirror direction
                case 4: *wo[0] = *wo[1] = 0.f, *wo[2] = 1.f; break;                         // wo at the normal
                case 5: *wi[0] = *wi[1] = 0.f, *wi[2] = std::copysign(1.f, *wo[2]); break;  // wi at the normal
                case 6: *wo[2] = -std::fabs(*wo[2]), *wi[2] = -std::fabs(*wi[2]); break;    // both below
                case 7: *wo[2] = 1e-7f; break;                                              // wo grazing
                case 8: *wi[0] = -*wo[0], *wi[1] = -*wo[1], *wi[2] = -*wo[2]; break;        // straight through
                case 9: *wi[0] = *wo[0], *wi[1] = *wo[1], *wi[2] = *wo[2]; break;           // back along wo
                case 10: *wi[2] = 0.f; break;                                               // wi on the horizon
                case 11: *wo[2] = -0.f, *wi[2] = -0.f; break;                               // both on it, −0
                case 12: *wo[2] = -1e-6f, *wi[2] = -1e-7f; break;                           // grazing below
                default: break;
            }
            for (int c = 0; c < 3; ++c) a[6 + c][k] = i % 7 < 4 ? us[(i / 7 + c) % 4] : rng.next_float();
            for (int p = 0; p < probe::kParams; ++p)
                q[p][k] = mat[k] >= 0 ? params[size_t(mat[k]) * probe::kParams + size_t(p)] : 1e6f + float(p);
            kind[k] = mat[k] < 0 ? 0 : std::holds_alternative<ThinDielectric>(mats[size_t(mat[k])]) ? 1 : 2;
            active[i] = (i / 16) % 3 != 1 || i % 5 != 0;  // every third packet partially masked
        }
        in.n = kN;
        for (int p = 0; p < probe::kParams; ++p) in.q[p] = q[p].data();
        for (int c = 0; c < 3; ++c) in.wo[c] = a[c].data(), in.wi[c] = a[3 + c].data(), in.u[c] = a[6 + c].data();
        in.kind = kind.data();
        in.active = active.get();
    }
    Vec3f wo(int i) const { return Vec3f(a[0][size_t(i)], a[1][size_t(i)], a[2][size_t(i)]); }
    Vec3f wi(int i) const { return Vec3f(a[3][size_t(i)], a[4][size_t(i)], a[5][size_t(i)]); }
};

using Outputs = test::ProbeOutputs<probe::Out, probe::kOutputs, Cases::kN>;
using test::same_bits;

void expect_equal(const Outputs& scalar, const Outputs& packet, const char* target) {
    EXPECT_EQ(test::count_differing(scalar, packet, target), 0u) << target;
}
}  // namespace

TEST(OrenThinLanes, TheGridIsCovered) {
    const Cases cases;
    EXPECT_GE(cases.thin, 8);
    EXPECT_GE(cases.classic, 10);
    EXPECT_GE(cases.eon, 10);
}

TEST(OrenThinLanes, FloatInstantiationIsTheScalarBxDF) {
    // The float instantiation from packet parameters gives the scalar API's bits: eval, pdf and
    // sample in each context, case by case; the thin dielectric both reflects and transmits, and
    // EON's multiple-scattering lobe is reached.
    const Cases cases;
    Outputs scalar;
    probe::run<float>(cases.in, scalar.out);
    size_t compared = 0, differ = 0, reflected = 0, transmitted = 0, diffuse = 0, eon_ms = 0;
    auto check = [&](float x, float y, int k, int i) {
        ++compared;
        if (!same_bits(x, y) && ++differ <= 5)
            ADD_FAILURE() << "output " << k << " case " << i << ": packet form " << x << ", BxDF " << y;
    };
    for (int i = 0; i < Cases::kN; ++i) {
        if (cases.mat[size_t(i)] < 0 || !cases.active[i]) continue;
        const BxDF& b = cases.mats[size_t(cases.mat[size_t(i)])];
        const Vec3f wo = cases.wo(i), wi = cases.wi(i);
        const Vec2f u(cases.a[7][size_t(i)], cases.a[8][size_t(i)]);
        for (int c = 0; c < probe::kContexts; ++c) {
            const BxDFContext ctx{probe::kMode[c], probe::kAllowed[c]};
            const int k0 = c * probe::kPerContext;
            const Spectrum f = eval(b, ctx, wo, wi);
            for (int ch = 0; ch < 3; ++ch) check(scalar.at(k0 + ch, i), f[ch], k0 + ch, i);
            check(scalar.at(k0 + 3, i), pdf(b, ctx, wo, wi), k0 + 3, i);
            if (const auto* o = std::get_if<OrenNayar>(&b); o && !o->lanes().classic && o->lanes().rough > 0.f && f.g > 0.f)
                ++eon_ms;
            const auto s = sample(b, ctx, wo, cases.a[6][size_t(i)], u);
            check(scalar.at(k0 + 4, i), s ? 1.f : 0.f, k0 + 4, i);
            if (!s) continue;
            if (has_flag(s->lobe, BxDFFlags::Diffuse)) ++diffuse;
            else (has_flag(s->lobe, BxDFFlags::Transmission) ? transmitted : reflected) += 1;
            for (int ch = 0; ch < 3; ++ch) check(scalar.at(k0 + 5 + ch, i), s->wi[ch], k0 + 5 + ch, i);
            for (int ch = 0; ch < 3; ++ch) check(scalar.at(k0 + 8 + ch, i), s->weight[ch], k0 + 8 + ch, i);
            check(scalar.at(k0 + 11, i), s->pdf, k0 + 11, i);
            check(scalar.at(k0 + 12, i), s->eta, k0 + 12, i);
            check(scalar.at(k0 + 13, i), float(uint32_t(s->lobe)), k0 + 13, i);
        }
    }
    EXPECT_EQ(differ, 0u) << "of " << compared;
    EXPECT_GT(reflected, size_t(Cases::kN) / 20);
    EXPECT_GT(transmitted, size_t(Cases::kN) / 4);
    EXPECT_GT(diffuse, size_t(Cases::kN));
    EXPECT_GT(eon_ms, size_t(Cases::kN) / 10);
}

TEST(OrenThinLanes, EveryTargetEveryLane) {
    const Cases cases;
    Outputs scalar;
    probe::run<float>(cases.in, scalar.out);
    int targets = 0;
    for (SimdTarget t : available_simd_targets()) {
        Outputs packet;
        switch (t) {
#ifdef PELLUCID_OREN_THIN_PROBE_AVX512
            case SimdTarget::AVX512: probe::run_avx512(cases.in, packet.out); break;
#endif
#ifdef PELLUCID_OREN_THIN_PROBE_AVX2
            case SimdTarget::AVX2: probe::run_avx2(cases.in, packet.out); break;
#endif
#ifdef PELLUCID_OREN_THIN_PROBE_SSE4
            case SimdTarget::SSE4: probe::run_sse4(cases.in, packet.out); break;
#endif
            default: continue;
        }
        ++targets;
        expect_equal(scalar, packet, to_string(t).c_str());
    }
    RecordProperty("targets", targets);
}

TEST(OrenThinLanes, ACaseChangedInOneLaneIsSeen) {
    // The comparison itself: another B in one EON lane, and another η in one thin-dielectric lane,
    // must change those lanes' outputs only.
    Cases cases;
    Outputs a, b;
    probe::run<float>(cases.in, a.out);
    auto find = [&](int kind, bool eon) {
        int lane = 0;
        while (!(cases.kind[size_t(lane)] == kind && cases.active[lane] && cases.wo(lane).z > 0.1f &&
                 cases.wi(lane).z > 0.1f && cases.q[1][size_t(lane)] > 0.f &&
                 (!eon || (cases.q[10][size_t(lane)] == 0.f && cases.q[4][size_t(lane)] > 0.f))))
            ++lane;
        return lane;
    };
    const int on = find(2, true), thin = find(1, false);
    const_cast<float*>(cases.in.q[4])[on] *= 1.5f;
    const_cast<float*>(cases.in.q[0])[thin] *= 1.5f;
    probe::run<float>(cases.in, b.out);
    size_t differ = 0;
    bool seen_on = false, seen_thin = false;
    for (int k = 0; k < probe::kOutputs; ++k)
        for (int i = 0; i < Cases::kN; ++i) {
            const bool d = !same_bits(a.at(k, i), b.at(k, i));
            differ += d;
            seen_on = seen_on || (d && i == on);
            seen_thin = seen_thin || (d && i == thin);
            if (d) {
                EXPECT_TRUE(i == on || i == thin) << i;
            }
        }
    EXPECT_TRUE(seen_on);
    EXPECT_TRUE(seen_thin);
}

TEST(OrenThinLanes, TheThinSlabIsTheSameFromBothSides) {
    // The slab's two faces are alike: from below, the sample is the mirror image of the one from
    // above (same weight, pdf and lobe), and at normal incidence the reflected fraction is
    // R' = 2R/(1 + R), R = ((η − 1)/(η + 1))², for η and 1/η alike.
    for (float eta : {1.5f, 1.f / 1.5f, 2.42f}) {
        const ThinDielectric slab(eta, Spectrum(0.9f, 0.5f, 0.2f), Spectrum(0.3f, 0.6f, 1.f));
        const float R = ((eta - 1.f) / (eta + 1.f)) * ((eta - 1.f) / (eta + 1.f));
        const auto n = slab.sample({}, Vec3f(0.f, 0.f, 1.f), 0.f, Vec2f(0.5f));
        ASSERT_TRUE(n);
        EXPECT_NEAR(n->pdf, 2.f * R / (1.f + R), 1e-6f) << eta;
        PCG32 rng(3, 4);
        int differ = 0, samples = 0;
        for (int i = 0; i < 2000; ++i) {
            Vec3f wo = square_to_uniform_sphere(rng.next_2d());
            wo.z = std::fabs(wo.z);
            const float u = rng.next_float();
            const auto up = slab.sample({}, wo, u, Vec2f(0.5f)), down = slab.sample({}, Vec3f(wo.x, wo.y, -wo.z), u, Vec2f(0.5f));
            ASSERT_EQ(bool(up), bool(down));
            if (!up) continue;
            ++samples;
            differ += up->lobe != down->lobe || up->pdf != down->pdf || up->weight != down->weight ||
                      up->wi != Vec3f(down->wi.x, down->wi.y, -down->wi.z);
        }
        EXPECT_EQ(differ, 0) << "η " << eta << ", of " << samples;
        EXPECT_GT(samples, 1900);
    }
}
