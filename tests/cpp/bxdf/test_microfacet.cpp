// Microfacet distributions: known values, normalisation, Smith G bounds, VNDF normalisation and χ².
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include "pellucid/bxdf/conductor.h"
#include "pellucid/bxdf/microfacet.h"
#include "pellucid/sampling/rng.h"
#include "pellucid/sampling/warp.h"
#include "support/chi2.h"

namespace pellucid {
namespace {

Vec3f dir_theta(float theta_deg, float phi = 0.37f) {
    float t = radians(theta_deg);
    return Vec3f(std::sin(t) * std::cos(phi), std::sin(t) * std::sin(phi), std::cos(t));
}

// ∫ over the upper hemisphere of f(w) dω by composite Gauss–Legendre in (θ, φ).
template <class F>
double integrate_hemisphere(F&& f) {
    double sum = 0.0;
    const int nt = 200, np = 48;  // D is peaked near θ = 0 for small α; pdf_visible has a φ kink
    for (int i = 0; i < nt; ++i)
        for (int j = 0; j < np; ++j)
            sum += test::integrate_2d_gauss(
                [&](double th, double ph) {
                    Vec3f w(float(std::sin(th) * std::cos(ph)), float(std::sin(th) * std::sin(ph)),
                            float(std::cos(th)));
                    return f(w) * std::sin(th);
                },
                M_PI / 2 * i / nt, M_PI / 2 * (i + 1) / nt, 2 * M_PI * j / np, 2 * M_PI * (j + 1) / np, 5);
    return sum;
}

TEST(Microfacet, CookTorranceKnownValue) {
    EXPECT_FLOAT_EQ(torrance_sparrow(0.8f, 0.9f, 0.5f, 0.8f, 0.8f), 0.140625f);
}

TEST(Microfacet, BeckmannKnownValue) {
    // D = exp(−tan²30°/0.25)/(π 0.25 cos⁴30°) = 0.5967.
    EXPECT_NEAR(Beckmann(0.5f).D(dir_theta(30.f)), 0.597f, 5e-4f);
    // At extreme grazing cos⁴ θm underflows to 0 with the exponential: D is 0, not 0/0.
    EXPECT_EQ(Beckmann(0.5f).D(Vec3f(1.f, 0.f, 1e-13f)), 0.f);
    // GGX at the pole: 1/(π α²).
    EXPECT_NEAR(GGX(0.5f).D(Vec3f(0, 0, 1)), 1.f / (kPi * 0.25f), 1e-6f);
}

template <class D>
void check_normalisation(const D& d) {
    double i = integrate_hemisphere([&](const Vec3f& wm) { return double(d.D(wm)) * wm.z; });
    EXPECT_NEAR(i, 1.0, 2e-3) << d.to_string();
    for (float th : {0.f, 40.f, 75.f, 89.f}) {
        Vec3f wo = dir_theta(th, 1.1f);
        double v = integrate_hemisphere([&](const Vec3f& wm) { return double(d.pdf_visible(wo, wm)); });
        EXPECT_NEAR(v, 1.0, 2e-3) << d.to_string() << " θo=" << th;  // Smith G1 matches D
    }
}

TEST(Microfacet, DistributionsIntegrateToOne) {
    for (float a : {0.1f, 0.5f, 1.f}) {
        check_normalisation(GGX(a));
        check_normalisation(Beckmann(a));
    }
    check_normalisation(GGX(0.15f, 0.6f));
    check_normalisation(Beckmann(0.15f, 0.6f));
}

template <class D>
void check_g_bounds(const D& d) {
    PCG32 rng(3, 1);
    for (int k = 0; k < 20000; ++k) {
        Vec3f wo = square_to_uniform_hemisphere(rng.next_2d()), wi = square_to_uniform_hemisphere(rng.next_2d());
        float g1 = d.G1(wo), g = d.G(wo, wi);
        ASSERT_TRUE(g1 >= 0.f && g1 <= 1.f) << g1;
        ASSERT_TRUE(g >= 0.f && g <= std::min(g1, d.G1(wi)) + 1e-6f) << g;
        ASSERT_GE(d.lambda(wo), 0.f);
    }
    EXPECT_FLOAT_EQ(d.G1(Vec3f(0, 0, 1)), 1.f);
    EXPECT_EQ(d.G1(Vec3f(1, 0, 0)), 0.f);
}

TEST(Microfacet, SmithGBounds) {
    for (float a : {1e-4f, 0.05f, 0.5f, 1.f, 3.f}) {
        check_g_bounds(GGX(a, 0.7f * a));
        check_g_bounds(Beckmann(a, 0.7f * a));
    }
}

// The separable G = G1(wo)·G1(wi) never exceeds the height-correlated 1/(1 + Λo + Λi) (since
// (1 + Λo)(1 + Λi) ≥ 1 + Λo + Λi), with equality when one direction is the normal (Λ = 0); G1, Λ and
// the visible-normal density do not depend on the choice.
template <class D>
void check_separable(float ax, float ay) {
    D hc(ax, ay), sep(ax, ay, SmithShadowing::Separable);
    EXPECT_EQ(hc.shadowing(), SmithShadowing::HeightCorrelated);
    EXPECT_EQ(sep.shadowing(), SmithShadowing::Separable);
    PCG32 rng(5, 9);
    int strictly_below = 0;
    for (int k = 0; k < 20000; ++k) {
        Vec3f wo = square_to_uniform_hemisphere(rng.next_2d()), wi = square_to_uniform_sphere(rng.next_2d());
        float g_sep = sep.G(wo, wi), g_hc = hc.G(wo, wi);
        ASSERT_EQ(g_sep, sep.G1(wo) * sep.G1(wi));
        ASSERT_LE(g_sep, g_hc * (1.f + 1e-6f)) << sep.to_string() << " wo=" << to_string(wo) << " wi=" << to_string(wi);
        strictly_below += g_sep < g_hc * (1.f - 1e-4f);
        ASSERT_EQ(sep.G1(wo), hc.G1(wo));
        Vec3f wm = sep.sample_visible(wo, rng.next_2d());
        ASSERT_EQ(sep.pdf_visible(wo, wm), hc.pdf_visible(wo, wm));
    }
    EXPECT_GT(strictly_below, 50) << sep.to_string();  // Λ > 0 matters (for small α only near grazing)
    Vec3f n(0.f, 0.f, 1.f), w = dir_theta(70.f);
    EXPECT_FLOAT_EQ(sep.G(n, w), hc.G(n, w));
}
TEST(Microfacet, SeparableShadowingIsBelowHeightCorrelated) {
    for (float a : {0.05f, 0.3f, 1.f}) {
        check_separable<GGX>(a, 0.6f * a);
        check_separable<Beckmann>(a, 0.6f * a);
    }
}

// Our Beckmann G1 = 1/(1 + Λ) is exact (erf in double, microfacet.cpp). Mitsuba 3 evaluates the
// rational fit G1 ≈ (3.535a + 2.181a²)/(1 + 2.276a + 2.577a²) for a = 1/(α tan θ) < 1.6 and 1 above
// (Walter et al. 2007, eq. 27). Measured: they differ by at most 0.31 % (a ≈ 1.34), so a product of
// two G1 by at most 0.63 %, which only grazing directions reach (an independent check of our Λ).
TEST(Microfacet, BeckmannG1AgreesWithTheRationalFit) {
    Beckmann d(0.5f);
    double worst = 0.0;
    for (int i = 1; i < 4000; ++i) {
        double a = i * 1e-3;  // a = cot θ / α
        double theta = std::atan(1.0 / (a * 0.5));
        Vec3f w(float(std::sin(theta)), 0.f, float(std::cos(theta)));
        double fit = a >= 1.6 ? 1.0 : (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a);
        worst = std::max(worst, std::fabs(fit / double(d.G1(w)) - 1.0));
    }
    EXPECT_LT(worst, 3.2e-3);
    EXPECT_GT(worst, 3.0e-3);  // the fit's own error, not ours: a wrong Λ would move it
}

TEST(Microfacet, AlphaFromRoughnessAndSmoothness) {
    EXPECT_FLOAT_EQ(GGX::alpha_from_roughness(0.5f), 0.25f);
    EXPECT_TRUE(GGX(0.9e-3f).effectively_smooth());
    EXPECT_FALSE(GGX(1.1e-3f).effectively_smooth());
    EXPECT_FALSE(GGX(1e-4f, 0.01f).effectively_smooth());
    EXPECT_EQ(GGX(0.f).alpha_x(), 1e-4f);  // clamped
}

// χ² of sample_visible against pdf_visible on a (cos θm, φ) grid of the upper hemisphere.
template <class D>
double vndf_chi2_p(const D& d, const Vec3f& wo, uint64_t seed) {
    constexpr int nt = 16, np = 64, n = 1000000;
    std::vector<double> obs(nt * np, 0.0), expd(nt * np, 0.0);
    PCG32 rng(seed, 7);
    for (int k = 0; k < n; ++k) {
        Vec3f wm = d.sample_visible(wo, rng.next_2d());
        float phi = std::atan2(wm.y, wm.x);
        if (phi < 0.f) phi += 2.f * kPi;
        int it = clamp(int(wm.z * nt), 0, nt - 1), ip = clamp(int(phi * kInv2Pi * np), 0, np - 1);
        obs[it * np + ip] += 1;
    }
    for (int it = 0; it < nt; ++it)
        for (int ip = 0; ip < np; ++ip)
            expd[it * np + ip] = n * test::integrate_2d_gauss(
                                         [&](double z, double phi) {
                                             double s = std::sqrt(std::max(0.0, 1.0 - z * z));
                                             return double(d.pdf_visible(
                                                 wo, Vec3f(float(s * std::cos(phi)), float(s * std::sin(phi)), float(z))));
                                         },
                                         double(it) / nt, double(it + 1) / nt, 2 * M_PI * ip / np,
                                         2 * M_PI * (ip + 1) / np, 8);
    test::Chi2Result r = test::chi2_test(obs, expd);
    EXPECT_TRUE(r.message.empty() || r.dof > 0) << r.message;
    return r.p_value;
}

TEST(Microfacet, VisibleNormalSamplingChi2) {
    const double alpha = test::sidak_alpha(0.01, 8);
    uint64_t seed = 1;
    for (float th : {30.f, 80.f}) {
        Vec3f wo = dir_theta(th, 0.9f);
        EXPECT_GE(vndf_chi2_p(GGX(0.5f), wo, seed++), alpha) << "GGX iso θ=" << th;
        EXPECT_GE(vndf_chi2_p(GGX(0.2f, 0.6f), wo, seed++), alpha) << "GGX aniso θ=" << th;
        EXPECT_GE(vndf_chi2_p(Beckmann(0.5f), wo, seed++), alpha) << "Beckmann iso θ=" << th;
        EXPECT_GE(vndf_chi2_p(Beckmann(0.2f, 0.6f), wo, seed++), alpha) << "Beckmann aniso θ=" << th;
    }
}

// ---- The Beckmann model's own transcendental functions (microfacet_detail, over a lane type F) ---
// Measured on their float instantiation against double-precision libm over the ranges the model
// uses; the lanes test (tests/cpp/simd/test_lanes_equal_scalars.cpp) shows every packet gives the
// same bits.
double rel_err(double got, double want) { return std::fabs(got - want) / std::fabs(want); }

TEST(BeckmannMath, ExpAndLog) {
    using namespace microfacet_detail;
    double worst_exp = 0.0, worst_log = 0.0;
    for (int i = 0; i <= 2000000; ++i) {
        const float x = -87.f + 175.f * float(i) / 2000000.f;  // [−87, 88]
        worst_exp = std::max(worst_exp, rel_err(exp_t(x), std::exp(double(x))));
    }
    EXPECT_EQ(exp_t(-87.5f), 0.f);
    EXPECT_EQ(exp_t(0.f), 1.f);
    PCG32 rng(3, 5);
    for (int i = 0; i < 2000000; ++i) {
        const float x = float(std::exp(-86.0 + 172.0 * rng.next_float()));  // normal floats, e^±86
        if (x == 1.f) continue;
        worst_log = std::max(worst_log, rel_err(log_t(x), std::log(double(x))));
    }
    for (float x : {1.f - 0x1p-24f, 1.f + 0x1p-23f, 0.70710677f, 1.4142135f, 0x1p-126f})
        worst_log = std::max(worst_log, rel_err(log_t(x), std::log(double(x))));
    EXPECT_EQ(log_t(1.f), 0.f);
    // Measured: 1.02e-7 and 2.06e-7 (one and two float ulps).
    EXPECT_LT(worst_exp, 1.5e-7);
    EXPECT_LT(worst_log, 2.5e-7);
}

TEST(BeckmannMath, Erfc) {
    using namespace microfacet_detail;
    double worst2 = 0.0, worst4 = 0.0, worst9 = 0.0;
    for (int i = 0; i <= 900000; ++i) {
        const float x = 9.f * float(i) / 900000.f;
        const double e = rel_err(erfc_t(x), std::erfc(double(x)));
        (x <= 2.f ? worst2 : x <= 4.f ? worst4 : worst9) = std::max(x <= 2.f ? worst2 : x <= 4.f ? worst4 : worst9, e);
    }
    // Measured: 4.8e-7 on [0, 2], 8.0e-7 on (2, 4] and 4.1e-6 on (4, 9], where erfc < 1.5e-8 and the
    // float rounding of the argument −x² of e^{−x²} dominates (x² · 2⁻²⁴ ≈ 4.8e-6 at x = 9).
    EXPECT_LT(worst2, 6e-7);
    EXPECT_LT(worst4, 1e-6);
    EXPECT_LT(worst9, 5e-6);
}

TEST(BeckmannMath, Erfinv) {
    using namespace microfacet_detail;
    double worst = 0.0;
    for (int i = 1; i < 1 << 24; i += 7) {
        const float u = float(i) * 0x1p-24f;
        const float x = 2.f * u - 1.f;
        const double want = erfinv(2.0 * double(u) - 1.0);
        if (want == 0.0) continue;
        worst = std::max(worst, rel_err(erfinv_t(x, 4.f * u * (1.f - u)), want));
    }
    EXPECT_LT(worst, 3e-7);  // measured 2.5e-7, u = x/2 + 1/2 on a 2⁻²⁴ grid
}

TEST(BeckmannMath, Lambda) {
    // Λ against eq. 83 in double with libm's erf, over α ∈ [1e-4, 3] (anisotropic) and θ up to the
    // horizon.
    double worst = 0.0;
    for (float ax : {1e-4f, 0.01f, 0.1f, 0.3f, 1.f, 3.f})
        for (float ay : {ax, 0.5f * ax}) {
            const Beckmann d(ax, ay);  // α clamped to ≥ 1e-4
            for (int i = 0; i < 20000; ++i) {
                const double th = 0.5 * M_PI * (i + 0.5) / 20000.0, ph = 0.37 + i * 0.01;
                const Vec3f w(float(std::sin(th) * std::cos(ph)), float(std::sin(th) * std::sin(ph)), float(std::cos(th)));
                const double bx = d.alpha_x(), by = d.alpha_y();
                const double den = std::sqrt(bx * bx * w.x * w.x + by * by * w.y * w.y);
                const double a = std::fabs(double(w.z)) / den;
                const double want = 0.5 * (std::exp(-a * a) / (a * std::sqrt(M_PI)) - std::erfc(a));
                const double got = d.lambda(w);
                worst = std::max(worst, std::fabs(got - want) / std::max(want, 1e-3));
            }
        }
    // Relative where Λ ≥ 1e-3, absolute below (where the two terms of eq. 83 cancel): measured 3.4e-6.
    EXPECT_LT(worst, 4e-6);
}

TEST(BeckmannMath, SampleVisibleInvertsTheSlopeCdf) {
    // The slopes behind each sampled normal, recovered in double (unstretch, rotate back), against
    // the CDFs they should invert: for wo at θ in the stretched configuration, x̃ has the CDF
    // C(x̃) = cos θ (1 + erf x̃)/2 + sin θ e^{−x̃²}/(2√π) up to C(cot θ) = cos θ (1 + Λ), and ỹ that of a
    // Gaussian of variance ½, (1 + erf ỹ)/2 (Heitz & d'Eon 2014, §4).
    double worst_x = 0.0, worst_y = 0.0;
    for (const Beckmann& d : {Beckmann(0.05f), Beckmann(0.3f), Beckmann(1.f), Beckmann(0.1f, 0.6f), Beckmann(2.f, 0.3f)})
        for (int it = 0; it < 60; ++it)
            for (int iu = 0; iu < 60; ++iu) {
                const double th = radians(89.9f) * it / 59.0, ph = 0.3 + 0.7 * it;
                const Vec3f wo(float(std::sin(th) * std::cos(ph)), float(std::sin(th) * std::sin(ph)), float(std::cos(th)));
                const double us[] = {1e-6, 1e-4, 1e-2, 1.0 - 1e-2, 1.0 - 1e-4, 1.0 - 1e-6};
                const Vec2f u(float(iu < 6 ? us[iu] : (iu - 5.5) / 55.0), float(iu < 6 ? us[5 - iu] : (60 - iu - 0.5) / 55.0));
                const Vec3f m = d.sample_visible(wo, u);
                const double ax = d.alpha_x(), ay = d.alpha_y();
                Vec3d ws(ax * wo.x, ay * wo.y, wo.z);
                ws /= glm::length(ws);
                const double sin_t = std::hypot(ws.x, ws.y), cos_t = ws.z;
                const double cp = sin_t > 0.0 ? ws.x / sin_t : 1.0, sp = sin_t > 0.0 ? ws.y / sin_t : 0.0;
                const double tx = -double(m.x) / m.z / ax, ty = -double(m.y) / m.z / ay;
                const double sx = cp * tx + sp * ty, sy = -sp * tx + cp * ty;
                auto cdf = [&](double x) {
                    return cos_t * 0.5 * (1.0 + std::erf(x)) + sin_t * 0.5 / std::sqrt(M_PI) * std::exp(-x * x);
                };
                const double total = sin_t > 0.0 ? cdf(cos_t / sin_t) : 1.0;
                worst_x = std::max(worst_x, std::fabs(cdf(sx) / total - u.x));
                worst_y = std::max(worst_y, std::fabs(0.5 * (1.0 + std::erf(sy)) - u.y));
            }
    // Measured: 2.1e-7 and 8.4e-8, float resolution (a Halley step in erf⁻¹ space and one on the slope;
    // with the start blended by 1 − cos θ instead of sin² θ, the same two steps leave 1.1e-6 in exact
    // arithmetic).
    EXPECT_LT(worst_x, 5e-7);
    EXPECT_LT(worst_y, 5e-7);
}
}  // namespace
}  // namespace pellucid
