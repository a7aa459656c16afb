// The BxDF property suite (STYLE.md §6.9, REFERENCE.md §2): one typed test per property, over every
// alternative of `pellucid::BxDF`, with the parameter sets of bxdf_cases.h and fixed seeds.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <iomanip>

#include "bxdf/bxdf_cases.h"
#include "pellucid/sampling/rng.h"
#include "support/sphere_chi2.h"

namespace pellucid::test {
namespace {

/// Number of χ² runs in the whole suite (for the Šidák correction).
int chi2_runs() {
    return VariantTypes<BxDF>::sum_over_cases([](const auto& cases) {
        int n = 0;
        for (const auto& c : cases)
            if (c.chi2) n += int(c.wos.size());
        return n;
    });
}
using AllBxDFs = VariantTypes<BxDF>::type;

/// χ² of sample() against pdf() and the delta probabilities, on the sphere around the local z axis
/// (support/sphere_chi2.h: 32 × 64 equal-area cells, 10⁶ samples).
template <class T>
Chi2Result run_chi2(const T& b, TransportMode mode, const Vec3f& wo, uint64_t seed) {
    BxDFContext ctx{mode, BxDFFlags::All};
    return sphere_chi2([&](float ul, const Vec2f& u) { return b.sample(ctx, wo, ul, u); },
                       [&](const Vec3f& wi) { return b.pdf(ctx, wo, wi); }, seed);
}

template <class T>
class BxDFProperties : public ::testing::Test {};
TYPED_TEST_SUITE(BxDFProperties, AllBxDFs);

bool rel_close(double a, double b, double rel) {
    return std::fabs(a - b) <= rel * std::max(std::fabs(a), std::fabs(b)) || std::fabs(a - b) < 1e-30;
}
bool finite_nonneg(const Spectrum& s) { return s.is_finite() && !s.has_negative(); }

// 1. χ² of sample() against pdf() (and delta probabilities), α = 0.01 Šidák-corrected over the suite.
TYPED_TEST(BxDFProperties, Chi2SampleMatchesPdf) {
    static const double alpha = sidak_alpha(0.01, chi2_runs());
    uint64_t seed = 1;
    for (const auto& c : BxDFCases<TypeParam>::cases()) {
        if (!c.chi2) continue;
        for (const Vec3f& wo : c.wos) {
            Chi2Result r = run_chi2(c.bxdf, c.mode, wo, seed++);
            EXPECT_GE(r.p_value, alpha) << c.name << " wo=" << to_string(wo) << ": " << r.message << "\n"
                                        << c.bxdf.to_string();
        }
    }
}

// 2. weight == eval/pdf on non-delta samples; sample's pdf == pdf().
TYPED_TEST(BxDFProperties, WeightEqualsEvalOverPdf) {
    PCG32 rng(7, 3);
    for (const auto& c : BxDFCases<TypeParam>::cases())
        for (const Vec3f& wo : c.wos) {
            BxDFContext ctx{c.mode, BxDFFlags::All};
            int bad = 0;
            for (int k = 0; k < 20000 && bad < 5; ++k) {
                float ul = rng.next_float();
                auto s = c.bxdf.sample(ctx, wo, ul, rng.next_2d());
                if (!s || s->is_specular()) continue;
                float p = c.bxdf.pdf(ctx, wo, s->wi);
                Spectrum f = c.bxdf.eval(ctx, wo, s->wi);
                bool ok = rel_close(p, s->pdf, 1e-3);
                for (int ch = 0; ch < 3; ++ch) ok &= rel_close(f[ch] / p, s->weight[ch], 1e-3);
                if (!ok) {
                    ++bad;
                    ADD_FAILURE() << c.name << " wo=" << to_string(wo) << " wi=" << to_string(s->wi)
                                  << " pdf()=" << p << " s.pdf=" << s->pdf << " eval/pdf=" << (f / p).to_string()
                                  << " weight=" << s->weight.to_string();
                }
            }
        }
}

// 3. Reciprocity f(wo,wi) = f(wi,wo) for reflection; for refraction in radiance mode
//    f(wi,wo) = η'² f(wo,wi) with η' = η(wi side)/η(wo side), and the adjoint identity
//    f_importance(wi,wo) = f_radiance(wo,wi) (Veach 1997, eqs. 5.12–5.14). Cases without
//    symmetric_support are checked where both values are non-zero.
TYPED_TEST(BxDFProperties, Reciprocity) {
    PCG32 rng(11, 5);
    const BxDFContext rad{TransportMode::Radiance, BxDFFlags::All}, imp{TransportMode::Importance, BxDFFlags::All};
    for (const auto& c : BxDFCases<TypeParam>::cases()) {
        int bad = 0;
        for (int k = 0; k < 20000 && bad < 5; ++k) {
            Vec3f wo = square_to_uniform_sphere(rng.next_2d()), wi = square_to_uniform_sphere(rng.next_2d());
            if (std::fabs(wo.z) < 1e-3f || std::fabs(wi.z) < 1e-3f) continue;
            Spectrum a = c.bxdf.eval(rad, wo, wi) / std::fabs(wi.z);
            Spectrum b = c.bxdf.eval(rad, wi, wo) / std::fabs(wo.z);
            Spectrum bi = c.bxdf.eval(imp, wi, wo) / std::fabs(wo.z);
            if (!c.symmetric_support && (a.is_black() || (same_hemisphere(wo, wi) ? b : bi).is_black())) continue;
            bool ok = true;
            for (int ch = 0; ch < 3; ++ch)
                ok &= same_hemisphere(wo, wi) ? rel_close(a[ch], b[ch], 1e-3) : rel_close(bi[ch], a[ch], 1e-3);
            if (!ok) {
                ++bad;
                ADD_FAILURE() << std::setprecision(9) << c.name << " wo=" << to_string(wo) << " wi=" << to_string(wi)
                              << " f(wo,wi)=" << a.to_string() << " f(wi,wo)=" << b.to_string()
                              << " f_imp(wi,wo)=" << bi.to_string();
            }
        }
    }
}

// 4. White furnace: E[weight] ≤ 1 + 5 SE for every wo; lossless configurations = 1 ± (tol + 5 SE).
//    Run in Importance mode: in Radiance mode refraction into a less dense medium legitimately
//    multiplies throughput by 1/η'² > 1 (bxdf_types.h), so only importance obeys E ≤ 1.
TYPED_TEST(BxDFProperties, WhiteFurnace) {
    constexpr int kN = 100000;
    for (const auto& c : BxDFCases<TypeParam>::cases()) {
        BxDFContext ctx{TransportMode::Importance, BxDFFlags::All};
        std::vector<Vec3f> wos = c.wos;
        for (float ct : {1.f, 0.5f, 0.05f}) wos.push_back(dir(ct, 0.7f));
        for (const Vec3f& wo : wos)
            for (int ch = 0; ch < 3; ++ch) {
                double sum = 0.0, sum2 = 0.0;
                PCG32 r2(17 + ch, 9);
                for (int k = 0; k < kN; ++k) {
                    float ul = r2.next_float();
                    auto s = c.bxdf.sample(ctx, wo, ul, r2.next_2d());
                    double w = s ? s->weight[ch] : 0.0;
                    sum += w;
                    sum2 += w * w;
                }
                double mean = sum / kN, se = std::sqrt(std::max(0.0, sum2 / kN - mean * mean) / kN);
                EXPECT_LE(mean, 1.0 + 5.0 * se + 1e-5) << c.name << " wo=" << to_string(wo) << " ch=" << ch;
                if (c.lossless) {
                    EXPECT_NEAR(mean, 1.0, c.furnace_tol + 5.0 * se) << c.name << " wo=" << to_string(wo);
                }
            }
    }
}

// 5. Stability: no NaN/Inf/negative anywhere in the parameter sweep, at grazing and normal incidence.
TYPED_TEST(BxDFProperties, StabilitySweep) {
    PCG32 rng(19, 11);
    const float cosines[] = {1e-7f, 1e-4f, 0.01f, 0.5f, 1.f};
    const float us[] = {0.f, 0.5f, kOneMinusEpsilon};
    for (const auto& b : BxDFCases<TypeParam>::sweep()) {
        int bad = 0;
        for (float ct : cosines)
            for (float sign : {1.f, -1.f}) {
                Vec3f wo = dir(sign * ct, 0.4f);
                wo = normalize(wo);
                for (auto mode : {TransportMode::Radiance, TransportMode::Importance}) {
                    BxDFContext ctx{mode, BxDFFlags::All};
                    auto check = [&](float ul, Vec2f u) {
                        auto s = b.sample(ctx, wo, ul, u);
                        if (s && !(finite_nonneg(s->weight) && std::isfinite(s->pdf) && s->pdf > 0.f &&
                                   is_finite(s->wi))) {
                            if (++bad < 4)
                                ADD_FAILURE() << b.to_string() << " wo=" << to_string(wo) << " sample weight="
                                              << s->weight.to_string() << " pdf=" << s->pdf;
                        }
                    };
                    for (float a : us)
                        for (float bb : us)
                            for (float c2 : us) check(a, Vec2f(bb, c2));
                    for (int k = 0; k < 32; ++k) {
                        float ul = rng.next_float();
                        check(ul, rng.next_2d());
                    }
                    for (int k = 0; k < 32; ++k) {
                        Vec3f wi = square_to_uniform_sphere(rng.next_2d());
                        if (k < 4) wi = dir((k % 2 ? 1.f : -1.f) * cosines[k], 2.f);
                        Spectrum f = b.eval(ctx, wo, wi);
                        float p = b.pdf(ctx, wo, wi);
                        if (!(finite_nonneg(f) && std::isfinite(p) && p >= 0.f) && ++bad < 4)
                            ADD_FAILURE() << b.to_string() << " wo=" << to_string(wo) << " wi=" << to_string(wi)
                                          << " eval=" << f.to_string() << " pdf=" << p;
                    }
                }
            }
    }
}

// 6. flags() matches the lobes sample() returns: every sampled lobe is in flags(), and over the
//    test directions every flagged lobe kind is sampled.
TYPED_TEST(BxDFProperties, FlagsMatchSampledLobes) {
    PCG32 rng(23, 13);
    for (const auto& c : BxDFCases<TypeParam>::cases()) {
        BxDFFlags seen = BxDFFlags::None;
        BxDFContext ctx{c.mode, BxDFFlags::All};
        for (const Vec3f& wo : wo_both())
            for (int k = 0; k < 20000; ++k) {
                float ul = rng.next_float();
                auto s = c.bxdf.sample(ctx, wo, ul, rng.next_2d());
                if (s) seen |= s->lobe;
            }
        EXPECT_EQ(to_string(seen), to_string(c.bxdf.flags())) << c.name;
    }
    for (const auto& b : BxDFCases<TypeParam>::sweep())
        for (const Vec3f& wo : wo_both())
            for (int k = 0; k < 64; ++k) {
                float ul = rng.next_float();
                auto s = b.sample(BxDFContext{}, wo, ul, rng.next_2d());
                if (s && !s->weight.is_black()) {
                    EXPECT_EQ(uint32_t(s->lobe & b.flags()), uint32_t(s->lobe)) << b.to_string();
                }
            }
}

// The refraction η² rule, separately, with η' known per case: only RoughDielectric has a
// non-delta transmission lobe.
TEST(BxDFProperties, RefractionEtaSquaredRule) {
    PCG32 rng(29, 15);
    const BxDFContext rad{TransportMode::Radiance, BxDFFlags::All};
    for (float eta : {1.5f, 1.333f, 1.f / 1.5f}) {
        RoughDielectric<GGX> b(GGX(0.3f, 0.2f), eta);
        int checked = 0;
        for (int k = 0; k < 20000; ++k) {
            Vec3f wo = square_to_uniform_sphere(rng.next_2d()), wi = square_to_uniform_sphere(rng.next_2d());
            if (same_hemisphere(wo, wi) || std::fabs(wo.z) < 1e-3f || std::fabs(wi.z) < 1e-3f) continue;
            float etap = wo.z > 0.f ? eta : 1.f / eta;  // η(wi side)/η(wo side)
            Spectrum a = b.eval(rad, wo, wi) / std::fabs(wi.z), r = b.eval(rad, wi, wo) / std::fabs(wo.z);
            if (a.is_black() && r.is_black()) continue;
            ++checked;
            ASSERT_TRUE(rel_close(r.r, etap * etap * a.r, 1e-3))
                << "eta=" << eta << " wo=" << to_string(wo) << " wi=" << to_string(wi) << " " << r.r << " vs "
                << etap * etap * a.r;
        }
        EXPECT_GT(checked, 1000);
    }
}
}  // namespace
}  // namespace pellucid::test
