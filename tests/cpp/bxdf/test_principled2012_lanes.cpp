// Lanes equal scalars for the Burley 2012 principled BRDF's packet form (bxdf/principled2012_probe.h):
// on every lane of every SIMD target, eval, pdf and sample give exactly the bits the float
// instantiation gives for that lane's inputs (a bound of 0 ulp: the library and the probes are built
// without contraction; the clear coat's GTR1 normal is the float function's own, called a lane at a
// time, and the rest uses only IEEE-exact lane operations). The float instantiation, built from
// packet parameters as the path tracer builds it, in turn gives the bits of the scalar BxDF API
// (Principled).
//
// Cases: the property suite's 2012 principled BRDFs (bxdf_cases.h) and a grid over metallic,
// roughness, anisotropic, sheen, sheen_tint, clearcoat, clearcoat_gloss, specular, specular_tint
// and the base colour (black included), one material per lane at random so every packet mixes
// materials; lanes of other models and partially masked packets; directions on, near and below the
// horizon, at the normal, in the mirror direction and straight through; u at 0, 1/2 and 1 − 2⁻²⁴;
// both transport modes and glossy-only, diffuse-only and transmission-only contexts.
//
// Renders: bench/suite/no_twin.json, whose two 2012 principled materials are packet forms, gives
// the scalar target's image bit for bit on every SIMD target (SimdTargetRender.*, test_simd_targets.cpp).
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "bxdf/bxdf_cases.h"
#include "bxdf/principled2012_probe.h"
#include "pellucid/api.h"
#include "pellucid/integrator/path_services.h"
#include "pellucid/integrator/simd_target.h"
#include "pellucid/scene/json_io.h"
#include "pellucid/sampling/rng.h"
#include "pellucid/sampling/warp.h"
#include "support/probe_outputs.h"

using namespace pellucid;

namespace pellucid::principled2012_probe {
#ifdef PELLUCID_PRINCIPLED2012_PROBE_AVX512
void run_avx512(const In& in, Out& out);
#endif
#ifdef PELLUCID_PRINCIPLED2012_PROBE_AVX2
void run_avx2(const In& in, Out& out);
#endif
#ifdef PELLUCID_PRINCIPLED2012_PROBE_SSE4
void run_sse4(const In& in, Out& out);
#endif
}  // namespace pellucid::principled2012_probe

namespace {
constexpr int kP = kPrincipled2012Params;
namespace probe = principled2012_probe;

/// The property suite's 2012 principled BRDFs and a parameter grid.
std::vector<Principled> materials() {
    std::vector<Principled> m;
    using test::BxDFCases;
    for (const auto& c : BxDFCases<Principled>::cases()) m.push_back(c.bxdf);
    for (const auto& b : BxDFCases<Principled>::sweep()) m.push_back(b);
    const Spectrum bases[] = {Spectrum(0.8f, 0.2f, 0.2f), Spectrum(0.9f, 0.8f, 0.5f), Spectrum(0.f),
                              Spectrum(0.1f, 0.5f, 0.9f)};
    int n = 0;
    for (float metallic : {0.f, 0.5f, 1.f})
        for (float roughness : {0.f, 0.3f, 1.f})
            for (float anisotropic : {0.f, 0.8f})
                for (float sheen : {0.f, 0.7f})
                    for (float clearcoat : {0.f, 0.6f})
                        for (float specular : {0.f, 0.5f, 1.f})
                            for (float specular_tint : {0.f, 0.7f}) {
                                PrincipledInputs p;
                                p.base_color = bases[n % 4];
                                p.metallic = metallic;
                                p.roughness = roughness;
                                p.anisotropic = anisotropic;
                                p.sheen = sheen;
                                p.sheen_tint = (n / 4) % 2 ? 0.6f : 0.f;
                                p.clearcoat = clearcoat;
                                p.clearcoat_gloss = float(n % 3) * 0.5f;  // α_c 0.1, 0.0505, 0.001
                                p.specular = specular;
                                p.specular_tint = specular_tint;
                                m.emplace_back(p);
                                ++n;
                            }
    return m;
}

struct Cases {
    static constexpr int kN = 16384;
    std::vector<Principled> mats = materials();
    std::vector<float> params;  // kP per material
    std::vector<float> q[kP], a[9];
    std::vector<int> mat;  // -1: a lane of another model
    std::vector<int32_t> kind;
    std::unique_ptr<bool[]> active{new bool[kN]};
    probe::In in;

    Cases() {
        params.resize(mats.size() * kP);
        for (size_t m = 0; m < mats.size(); ++m) principled2012_packet_params(mats[m].lanes(), &params[m * kP]);
        PCG32 rng(12, 2012);
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

using Outputs = test::ProbeOutputs<probe::Out, probe::kOutputs, Cases::kN>;
using test::same_bits;
}  // namespace

TEST(Principled2012Lanes, TheGridIsCovered) {
    const Cases cases;
    EXPECT_GE(cases.mats.size(), 400u);
    // Every lobe of the model is present in some material, and materials without a diffuse lobe.
    bool metal = false, coat = false, sheen = false, aniso = false, no_diffuse = false;
    for (const auto& m : cases.mats) {
        const Principled2012T<float>& l = m.lanes();
        metal = metal || (l.metallic > 0.f && l.metallic < 1.f);
        coat = coat || l.clearcoat > 0.f;
        sheen = sheen || (l.sheen > 0.f && l.csheen.r != l.csheen.b);
        aniso = aniso || l.spec.ax != l.spec.ay;
        no_diffuse = no_diffuse || l.w_diffuse == 0.f;
    }
    EXPECT_TRUE(metal && coat && sheen && aniso && no_diffuse);
}

TEST(Principled2012Lanes, FloatInstantiationIsTheScalarBxDF) {
    // The float instantiation from packet parameters gives the scalar API's bits: eval, pdf and
    // sample in each context, case by case; many cases sample each lobe.
    const Cases cases;
    Outputs scalar;
    probe::run<float>(cases.in, scalar.out);
    size_t compared = 0, differ = 0, diffuse = 0, glossy = 0, nonzero = 0;
    auto check = [&](float x, float y, int k, int i) {
        ++compared;
        if (!same_bits(x, y) && ++differ <= 5)
            ADD_FAILURE() << "output " << k << " case " << i << ": packet form " << x << ", BxDF " << y;
    };
    for (int i = 0; i < Cases::kN; ++i) {
        if (cases.mat[size_t(i)] < 0 || !cases.active[i]) continue;
        const Principled& b = cases.mats[size_t(cases.mat[size_t(i)])];
        const Vec3f wo = cases.wo(i), wi = cases.wi(i);
        const Vec2f u(cases.a[7][size_t(i)], cases.a[8][size_t(i)]);
        for (int c = 0; c < probe::kContexts; ++c) {
            const BxDFContext ctx{probe::kMode[c], probe::kAllowed[c]};
            const int k0 = c * probe::kPerContext;
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

TEST(Principled2012Lanes, EveryTargetEveryLane) {
    const Cases cases;
    Outputs scalar;
    probe::run<float>(cases.in, scalar.out);
    int targets = 0;
    for (SimdTarget t : available_simd_targets()) {
        Outputs packet;
        switch (t) {
#ifdef PELLUCID_PRINCIPLED2012_PROBE_AVX512
            case SimdTarget::AVX512: probe::run_avx512(cases.in, packet.out); break;
#endif
#ifdef PELLUCID_PRINCIPLED2012_PROBE_AVX2
            case SimdTarget::AVX2: probe::run_avx2(cases.in, packet.out); break;
#endif
#ifdef PELLUCID_PRINCIPLED2012_PROBE_SSE4
            case SimdTarget::SSE4: probe::run_sse4(cases.in, packet.out); break;
#endif
            default: continue;
        }
        ++targets;
        EXPECT_EQ(test::count_differing(scalar, packet, to_string(t).c_str()), 0u) << to_string(t);
    }
    RecordProperty("targets", targets);
}

TEST(Principled2012Lanes, ACaseChangedInOneLaneIsSeen) {
    // The comparison itself: another clear coat in one lane must change that lane's outputs only.
    Cases cases;
    Outputs a, b;
    probe::run<float>(cases.in, a.out);
    int lane = 0;
    while (!(cases.kind[size_t(lane)] == 1 && cases.active[lane] && cases.wo(lane).z > 0.1f && cases.wi(lane).z > 0.1f &&
             cases.q[12][size_t(lane)] > 0.f))
        ++lane;
    const_cast<float*>(cases.in.q[12])[lane] *= 0.5f;
    probe::run<float>(cases.in, b.out);
    const std::vector<int> changed = test::differing_cases(a, b);
    EXPECT_FALSE(changed.empty());
    for (int i : changed) EXPECT_EQ(i, lane);
}

TEST(SimdTargetRenderPrincipled2012, SuiteSceneMaterialsArePacketForms) {
    // no_twin.json's two 2012 principled materials (a dielectric with sheen, a clear-coated metal)
    // run as kPacketPrincipled2012, with the parameters of their float instantiation.
    auto scene = load_desc(read_json_file(std::string(PELLUCID_SOURCE_DIR) + "/bench/suite/no_twin.json"));
    const PathSetup ps = make_path_setup(*scene, 8, 5, true, true, SamplerType::Independent);
    int n = 0;
    for (size_t m = 0; m < scene->material_bxdfs.size(); ++m) {
        const auto* b = std::get_if<Principled>(&scene->material_bxdfs[m]);
        if (!b) continue;
        ++n;
        EXPECT_EQ(ps.packet_kind[m], int32_t(kPacketPrincipled2012)) << m;
        EXPECT_EQ(ps.packet_count[m], kPrincipled2012Params) << m;
        float q[kP];
        principled2012_packet_params(b->lanes(), q);
        for (int k = 0; k < kP; ++k)
            EXPECT_TRUE(same_bits(ps.packet_params[kPacketParams * m + size_t(k)], q[k])) << m << " " << k;
    }
    EXPECT_EQ(n, 2);
}
