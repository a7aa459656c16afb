// Lanes equal scalars for the plastics' packet form (bxdf/plastic_probe.h): on every lane of every
// SIMD target, eval, pdf and sample give exactly the bits the float instantiation gives for that
// lane's inputs (a bound of 0 ulp: the library and the probes are built without contraction, and
// the models use only IEEE-exact lane operations, with no libm call on a lane type). The float
// instantiation, built from packet parameters as the path tracer builds it, in turn gives the
// bits of the scalar BxDF API (SmoothPlastic, RoughPlastic<GGX>), so the packet parameters lose
// nothing.
//
// Cases: the property suite's plastics (bxdf_cases.h: its cases and parameter sweeps, i.e. every
// variant, η on both sides of 1 and at 1, Kd and Ks at 0 and 1, α from 0 to 1 with smooth and rough
// coat transmittance and both shadowing forms) plus anisotropic coats, one material per lane at
// random so every packet mixes materials, smooth and rough coats and several rough tables; lanes of
// other models (parameters that are not a plastic's, with a wild table offset) and partially masked
// packets; directions on and below the horizon, grazing, at the normal and in the mirror direction;
// u at 0, 1/2 and 1 − 2⁻²⁴.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

#include "bxdf/bxdf_cases.h"
#include "bxdf/plastic_probe.h"
#include "pellucid/integrator/simd_target.h"
#include "pellucid/sampling/rng.h"
#include "pellucid/sampling/warp.h"
#include "support/probe_outputs.h"

using namespace pellucid;

namespace pellucid::plastic_probe {
#ifdef PELLUCID_PLASTIC_PROBE_AVX512
void run_avx512(const In& in, Out& out);
#endif
#ifdef PELLUCID_PLASTIC_PROBE_AVX2
void run_avx2(const In& in, Out& out);
#endif
#ifdef PELLUCID_PLASTIC_PROBE_SSE4
void run_sse4(const In& in, Out& out);
#endif
}  // namespace pellucid::plastic_probe

namespace {
/// The materials: the property suite's plastics and anisotropic GGX coats.
std::vector<BxDF> materials() {
    std::vector<BxDF> m;
    using test::BxDFCases;
    for (const auto& c : BxDFCases<SmoothPlastic>::cases()) m.emplace_back(c.bxdf);
    for (const auto& b : BxDFCases<SmoothPlastic>::sweep()) m.emplace_back(b);
    for (const auto& c : BxDFCases<RoughPlastic<GGX>>::cases()) m.emplace_back(c.bxdf);
    for (const auto& b : BxDFCases<RoughPlastic<GGX>>::sweep()) m.emplace_back(b);
    const auto sep = SmithShadowing::Separable, hc = SmithShadowing::HeightCorrelated;
    for (auto v : {PlasticVariant::Coupled, PlasticVariant::Linear, PlasticVariant::Sum})
        for (auto c : {CoatTransmittance::Smooth, CoatTransmittance::Rough}) {
            m.emplace_back(RoughPlastic<GGX>(GGX(0.3f, 0.05f, hc), 1.49f, Spectrum(0.7f, 0.3f, 0.1f), Spectrum(0.9f), v, c));
            m.emplace_back(RoughPlastic<GGX>(GGX(0.02f, 0.6f, sep), 1.33f, Spectrum(0.2f, 0.4f, 0.8f), Spectrum(1.f), v, c));
        }
    return m;
}

struct Cases {
    static constexpr int kN = 16384;
    std::vector<BxDF> mats = materials();
    std::vector<float> params;  // kPlasticParams per material
    std::vector<float> tables;
    std::vector<float> q[kPlasticParams], a[9];
    std::vector<int> mat;  // -1: a lane of another model
    std::unique_ptr<bool[]> plastic{new bool[kN]}, active{new bool[kN]};
    int rough_tables = 0;
    plastic_probe::In in;

    Cases() {
        params.resize(mats.size() * kPlasticParams);
        for (size_t m = 0; m < mats.size(); ++m) {
            float* p = &params[m * kPlasticParams];
            if (const auto* s = std::get_if<SmoothPlastic>(&mats[m])) {
                plastic_packet_params(s->base(), nullptr, &tables, p);
            } else {
                const auto& r = std::get<RoughPlastic<GGX>>(mats[m]);
                const GGXT<float> d = r.distribution().lanes();
                plastic_packet_params(r.base(), &d, &tables, p);
            }
        }
        rough_tables = int(tables.size()) / kCoatTableSize;
        PCG32 rng(3, 17);
        for (auto& v : q) v.resize(kN);
        for (auto& v : a) v.resize(kN);
        mat.resize(kN);
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
            switch (i % 10) {  // edge cases
                case 1: *wo[2] = 0.f; break;                                 // wo on the horizon
                case 2: *wi[2] = 1e-7f; break;                               // wi grazing
                case 3: *wo[0] = -*wi[0], *wo[1] = -*wi[1], *wo[2] = *wi[2]; break;  // the mirror direction
                case 4: *wo[0] = *wo[1] = 0.f, *wo[2] = 1.f; break;          // wo at the normal
                case 5: *wi[2] = -std::fabs(*wi[2]), *wo[2] = std::fabs(*wo[2]); break;  // wi below, wo above
                case 6: *wo[2] = -std::fabs(*wo[2]), *wi[2] = -std::fabs(*wi[2]); break;  // both below
                case 7: *wo[2] = 1e-7f; break;                               // wo grazing
                default: break;
            }
            for (int c = 0; c < 3; ++c) a[6 + c][k] = i % 7 < 4 ? us[(i / 7 + c) % 4] : rng.next_float();
            for (int p = 0; p < kPlasticParams; ++p)
                q[p][k] = mat[k] >= 0 ? params[size_t(mat[k]) * kPlasticParams + size_t(p)] : 1e6f + float(p);
            plastic[i] = mat[k] >= 0;
            active[i] = (i / 16) % 3 != 1 || i % 5 != 0;  // every third packet partially masked
        }
        in.n = kN;
        for (int p = 0; p < kPlasticParams; ++p) in.q[p] = q[p].data();
        for (int c = 0; c < 3; ++c) in.wo[c] = a[c].data(), in.wi[c] = a[3 + c].data(), in.u[c] = a[6 + c].data();
        in.plastic = plastic.get();
        in.active = active.get();
        in.tables = tables.data();
    }
    Vec3f wo(int i) const { return Vec3f(a[0][size_t(i)], a[1][size_t(i)], a[2][size_t(i)]); }
    Vec3f wi(int i) const { return Vec3f(a[3][size_t(i)], a[4][size_t(i)], a[5][size_t(i)]); }
};

using Outputs = test::ProbeOutputs<plastic_probe::Out, plastic_probe::kOutputs, Cases::kN>;
using test::same_bits;

void expect_equal(const Outputs& scalar, const Outputs& packet, const char* target) {
    EXPECT_EQ(test::count_differing(scalar, packet, target), 0u) << target;
}
}  // namespace

TEST(PlasticLanes, TheGridIsCovered) {
    const Cases cases;
    // Several rough tables, so lanes read tables at different offsets.
    EXPECT_GE(cases.rough_tables, 8);
    EXPECT_GE(cases.mats.size(), 150u);
}

TEST(PlasticLanes, FloatInstantiationIsTheScalarBxDF) {
    // The float instantiation from packet parameters gives the scalar API's bits: eval, pdf and
    // sample (under each set of allowed lobes), case by case.
    const Cases cases;
    Outputs scalar;
    plastic_probe::run<float>(cases.in, scalar.out);
    size_t compared = 0, differ = 0, valid = 0;
    auto check = [&](float x, float y, int k, int i) {
        ++compared;
        if (!same_bits(x, y) && ++differ <= 5)
            ADD_FAILURE() << "output " << k << " case " << i << ": packet form " << x << ", BxDF " << y;
    };
    for (int i = 0; i < Cases::kN; ++i) {
        if (!cases.plastic[i] || !cases.active[i]) continue;
        const BxDF& b = cases.mats[size_t(cases.mat[size_t(i)])];
        const Vec3f wo = cases.wo(i), wi = cases.wi(i);
        const Vec2f u(cases.a[7][size_t(i)], cases.a[8][size_t(i)]);
        for (int c = 0; c < plastic_probe::kContexts; ++c) {
            const BxDFContext ctx{TransportMode::Radiance, plastic_probe::kAllowed[c]};
            const int k0 = c * plastic_probe::kPerContext;
            const Spectrum f = eval(b, ctx, wo, wi);
            for (int ch = 0; ch < 3; ++ch) check(scalar.at(k0 + ch, i), f[ch], k0 + ch, i);
            check(scalar.at(k0 + 3, i), pdf(b, ctx, wo, wi), k0 + 3, i);
            const auto s = sample(b, ctx, wo, cases.a[6][size_t(i)], u);
            check(scalar.at(k0 + 4, i), s ? 1.f : 0.f, k0 + 4, i);
            if (!s) continue;
            ++valid;
            for (int ch = 0; ch < 3; ++ch) check(scalar.at(k0 + 5 + ch, i), s->wi[ch], k0 + 5 + ch, i);
            for (int ch = 0; ch < 3; ++ch) check(scalar.at(k0 + 8 + ch, i), s->weight[ch], k0 + 8 + ch, i);
            check(scalar.at(k0 + 11, i), s->pdf, k0 + 11, i);
            check(scalar.at(k0 + 12, i), float(uint32_t(s->lobe)), k0 + 12, i);
        }
    }
    EXPECT_EQ(differ, 0u) << "of " << compared;
    // Most cases sample something, in every lobe.
    EXPECT_GT(valid, size_t(Cases::kN));
}

TEST(PlasticLanes, EveryTargetEveryLane) {
    const Cases cases;
    Outputs scalar;
    plastic_probe::run<float>(cases.in, scalar.out);
    int targets = 0;
    for (SimdTarget t : available_simd_targets()) {
        Outputs packet;
        switch (t) {
#ifdef PELLUCID_PLASTIC_PROBE_AVX512
            case SimdTarget::AVX512: plastic_probe::run_avx512(cases.in, packet.out); break;
#endif
#ifdef PELLUCID_PLASTIC_PROBE_AVX2
            case SimdTarget::AVX2: plastic_probe::run_avx2(cases.in, packet.out); break;
#endif
#ifdef PELLUCID_PLASTIC_PROBE_SSE4
            case SimdTarget::SSE4: plastic_probe::run_sse4(cases.in, packet.out); break;
#endif
            default: continue;
        }
        ++targets;
        expect_equal(scalar, packet, to_string(t).c_str());
    }
    RecordProperty("targets", targets);
}

TEST(PlasticLanes, ACaseChangedInOneLaneIsSeen) {
    // The comparison itself: another α in one lane must change that lane's outputs only.
    Cases cases;
    Outputs a, b;
    plastic_probe::run<float>(cases.in, a.out);
    int lane = 0;
    while (!(cases.plastic[lane] && cases.active[lane] && cases.q[9][size_t(lane)] > 0.01f && cases.wo(lane).z > 0.1f))
        ++lane;
    const_cast<float*>(cases.in.q[9])[lane] *= 1.5f;
    plastic_probe::run<float>(cases.in, b.out);
    const std::vector<int> changed = test::differing_cases(a, b);
    EXPECT_FALSE(changed.empty());
    for (int i : changed) EXPECT_EQ(i, lane);
}
