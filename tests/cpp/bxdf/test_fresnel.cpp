// Known answers for Fresnel, Snell, mirror reflection and the named IOR tables.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cstring>

#include "pellucid/bxdf/dielectric.h"
#include "pellucid/bxdf/fresnel.h"
#include "pellucid/bxdf/ior.h"
#include "pellucid/util/error.h"

namespace pellucid {
namespace {

TEST(Fresnel, SnellAirToWaterAt45Degrees) {
    Vec3f wi(std::sin(radians(45.f)), 0.f, std::cos(radians(45.f))), wt;
    float etap;
    ASSERT_TRUE(refract(wi, Vec3f(0, 0, 1), 1.33f, &etap, &wt));
    EXPECT_NEAR(degrees(std::acos(-wt.z)), 32.1f, 0.05f);  // asin(sin 45°/1.33) = 32.12°
    EXPECT_FLOAT_EQ(etap, 1.33f);
    EXPECT_NEAR(length(wt), 1.f, 1e-6f);
}

TEST(Fresnel, CriticalAngleWaterToAir) {
    // θc = asin(1/1.33) = 48.75°: total internal reflection beyond, partial below.
    const float eta = 1.33f, theta_c = degrees(std::asin(1.f / eta));
    EXPECT_NEAR(theta_c, 48.8f, 0.06f);
    EXPECT_EQ(fresnel_dielectric(-std::cos(radians(theta_c + 0.05f)), eta), 1.f);
    EXPECT_LT(fresnel_dielectric(-std::cos(radians(theta_c - 0.05f)), eta), 1.f);
    Vec3f wt, inside(std::sin(radians(theta_c + 0.05f)), 0.f, -std::cos(radians(theta_c + 0.05f)));
    EXPECT_FALSE(refract(inside, Vec3f(0, 0, 1), eta, nullptr, &wt));
}

TEST(Fresnel, MirrorReflection) {
    Vec3f r = reflect(Vec3f(1, 1, 0), Vec3f(0, 1, 0));
    EXPECT_FLOAT_EQ(r.x, -1.f);
    EXPECT_FLOAT_EQ(r.y, 1.f);
    EXPECT_FLOAT_EQ(r.z, 0.f);
}

TEST(Fresnel, DielectricKnownValues) {
    EXPECT_NEAR(fresnel_dielectric(1.f, 1.5f), 0.04f, 1e-6f);
    EXPECT_EQ(fresnel_dielectric(0.3f, 1.f), 0.f);  // index-matched: exactly 0
    EXPECT_NEAR(fresnel_dielectric(0.f, 1.5f), 1.f, 1e-6f);
    // Flipping: arriving from inside with cos < 0 equals the interface seen with 1/η.
    EXPECT_FLOAT_EQ(fresnel_dielectric(-0.7f, 1.5f), fresnel_dielectric(0.7f, 1.f / 1.5f));
    // Mitsuba 3 test_dielectric spot check: η = 1.5 at 80°: R = 0.387704354691473, θt = 41.0364°.
    EXPECT_NEAR(fresnel_dielectric(std::cos(radians(80.f)), 1.5f), 0.387704354691473, 2e-6);
    EXPECT_NEAR(fresnel_dielectric_d(std::cos(80.0 * M_PI / 180.0), 1.5), 0.387704354691473, 1e-12);
    float cos_t = 0.f;
    fresnel_dielectric(std::cos(radians(80.f)), 1.5f, &cos_t);
    EXPECT_NEAR(degrees(std::acos(cos_t)), 41.03641052520335, 1e-3);
    // Fresnel symmetry across the interface: R(θi, η) = R(θt, 1/η).
    fresnel_dielectric(0.6f, 1.5f, &cos_t);
    EXPECT_NEAR(fresnel_dielectric(0.6f, 1.5f), fresnel_dielectric(cos_t, 1.f / 1.5f), 1e-6f);
}

TEST(Fresnel, ConductorLimits) {
    // k = 0 reduces to the dielectric formula; huge k and grazing incidence reflect everything.
    for (float c : {0.05f, 0.3f, 0.7f, 1.f})
        EXPECT_NEAR(fresnel_conductor_1(c, 1.5, 0.0), fresnel_dielectric(c, 1.5f), 1e-6) << c;
    EXPECT_NEAR(fresnel_conductor_1(0.5, 1.5, 1e4), 1.0, 1e-3);
    EXPECT_NEAR(fresnel_conductor_1(0.0, 0.2, 3.0), 1.0, 1e-9);
    // Normal incidence: ((n − 1)² + k²)/((n + 1)² + k²) (Born & Wolf §14.2).
    double n = 0.2, k = 3.9;
    EXPECT_NEAR(fresnel_conductor_1(1.0, n, k), ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k), 1e-12);
    EXPECT_NEAR(fresnel_conductor_1(0.4, 0.0, 1.0), 1.0, 1e-12);  // "none": ideal mirror
}

TEST(Fresnel, RealConductorFormulaMatchesComplexDouble) {
    // The render-time real-arithmetic form against the complex double formula, at the float inputs
    // it receives: every named metal of ior.h over cos θ in [0, 1], and a log grid of η and k. The
    // bounds are the measured accuracy stated in fresnel.h (relative to max(R, 1e-3)): 8e-7 for
    // metals; 2e-4 over the whole grid, whose worst cases are unphysical (η < 0.1, k < 1e-4).
    auto rel = [](float c, float eta, float k) {
        const double r = fresnel_conductor_1(c, eta, k);
        return std::fabs(double(fresnel_conductor<float>(c, eta, k)) - r) / std::max(r, 1e-3);
    };
    double worst_metal = 0.0, worst_grid = 0.0;
    for (const std::string& name : conductor_names()) {
        const ConductorIOR m = conductor_ior(name);
        for (int ch = 0; ch < 3; ++ch)
            for (int i = 0; i <= 1000; ++i) worst_metal = std::max(worst_metal, rel(i / 1000.f, m.eta[ch], m.k[ch]));
    }
    for (int ie = -30; ie <= 20; ++ie)
        for (int ik = -60; ik <= 20; ++ik)
            for (int i = 0; i <= 64; ++i) {
                const float eta = std::pow(10.f, ie / 10.f), k = ik == -60 ? 0.f : std::pow(10.f, ik / 10.f);
                worst_grid = std::max(worst_grid, rel(i / 64.f, eta, k));
            }
    EXPECT_LT(worst_metal, 8e-7);
    EXPECT_LT(worst_grid, 2e-4);
    // Limits: grazing reflects everything, η = k = 0 is a perfect mirror, η = 1 with k = 0 is
    // index-matched.
    EXPECT_EQ(fresnel_conductor<float>(0.f, 0.2f, 3.f), 1.f);
    EXPECT_EQ(fresnel_conductor<float>(0.4f, 0.f, 0.f), 1.f);
    EXPECT_LT(fresnel_conductor<float>(1e-6f, 1.f, 0.f), 1e-9f);
}

TEST(Fresnel, SchlickR0AndMeasuredBound) {
    const float n1 = 1.f, n2 = 1.5f;
    EXPECT_NEAR(schlick_r0(n2 / n1), sqr((n1 - n2) / (n1 + n2)), 1e-7f);
    EXPECT_NEAR(fresnel_schlick(1.f, 0.04f), 0.04f, 1e-7f);
    EXPECT_NEAR(fresnel_schlick(0.f, 0.04f), 1.f, 1e-7f);
    // Measured max |Schlick − exact| over cos θ ∈ [0, 1] (external incidence): 0.0357 at η = 1.5
    // (θ ≈ 85°), ≤ 0.060 for η ∈ [1.33, 2.0]; over θ ≤ 60° ≤ 0.023 for η ∈ [1.33, 2.42].
    auto max_err = [](float eta, float cmin) {
        double m = 0.0;
        for (int i = 0; i <= 20000; ++i) {
            float c = cmin + (1.f - cmin) * i / 20000.f;
            m = std::max(m, double(std::fabs(fresnel_schlick(c, schlick_r0(eta)) - fresnel_dielectric(c, eta))));
        }
        return m;
    };
    EXPECT_NEAR(max_err(1.5f, 0.f), 0.0357, 5e-4);
    for (float eta : {1.333f, 1.5f, 1.7f, 2.f}) EXPECT_LE(max_err(eta, 0.f), 0.060) << eta;
    for (float eta : {1.333f, 1.5f, 2.f, 2.42f}) EXPECT_LE(max_err(eta, 0.5f), 0.023) << eta;
}

TEST(Fresnel, HemisphericalAverages) {
    // Independent midpoint estimate of 2∫F μ dμ.
    for (float eta : {1.f / 1.5f, 1.333f, 1.5f, 2.42f}) {
        double s = 0.0;
        const int n = 200000;
        for (int i = 0; i < n; ++i) {
            double mu = (i + 0.5) / n;
            s += fresnel_dielectric_d(mu, eta) * mu;
        }
        EXPECT_NEAR(fresnel_dielectric_average(eta), 2.0 * s / n, 2e-6) << eta;
    }
    // Reciprocity of the interface: η² (1 − F_avg(1/η)) = 1 − F_avg(η).
    EXPECT_NEAR(1.5f * 1.5f * (1.f - fresnel_dielectric_average(1.f / 1.5f)), 1.f - fresnel_dielectric_average(1.5f),
                1e-5f);
    SchlickFresnel s{Spectrum(0.04f)};
    EXPECT_NEAR(s.average().r, 0.04f + 0.96f / 21.f, 1e-7f);
}

TEST(Fresnel, PrecomputedAveragesAnswerOnlyForTheirInputs) {
    // A precomputed average (computed once at material load) gives its value for the inputs it was
    // computed from and the quadrature's for any other, bit for bit the function's result either way.
    auto bits = [](float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; };
    const DielectricFresnelAverage d = DielectricFresnelAverage::of(1.5f);
    for (float eta : {1.5f, 1.333f, 1.f / 1.5f, 1.f, 1.5000001f})
        EXPECT_TRUE(bits(d.get(eta), fresnel_dielectric_average(eta))) << eta;
    EXPECT_TRUE(bits(DielectricFresnelAverage{}.get(2.f), fresnel_dielectric_average(2.f)));
    EXPECT_TRUE(bits(fresnel_average(1.333f, &d), fresnel_dielectric_average(1.333f)));
    EXPECT_TRUE(bits(fresnel_average(1.333f, nullptr), fresnel_dielectric_average(1.333f)));

    const ConductorFresnel au{Spectrum(0.2f, 0.9f, 1.1f), Spectrum(3.9f, 2.4f, 2.1f)};
    const ConductorFresnelAverage c = ConductorFresnelAverage::of(au);
    ConductorFresnel other_k = au, schlick = ConductorFresnel::schlick_from(au.eta, au.k);
    other_k.k.g = 2.5f;
    for (const ConductorFresnel& f : {au, other_k, schlick}) {
        const Spectrum got = c.get(f), want = f.average();
        for (int i = 0; i < 3; ++i) EXPECT_TRUE(bits(got[i], want[i])) << f.to_string() << " " << i;
    }
    const Spectrum none = ConductorFresnelAverage{}.get(other_k), want = other_k.average();
    for (int i = 0; i < 3; ++i) EXPECT_TRUE(bits(none[i], want[i])) << i;
}

TEST(Fresnel, NamedIors) {
    ConductorIOR au = conductor_ior("Au");
    EXPECT_GT(au.k.r, au.k.b);  // gold: red reflects most
    EXPECT_GT(fresnel_conductor(1.f, au.eta, au.k).r, fresnel_conductor(1.f, au.eta, au.k).b);
    // The table also holds Mitsuba's non-metals (oxides, CsI, diamond, ...): every reflectance is in
    // (0, 1], the metals' above 0.3.
    for (const auto& n : conductor_names()) {
        ConductorIOR c = conductor_ior(n);
        Spectrum f = fresnel_conductor(1.f, c.eta, c.k);
        EXPECT_TRUE(f.is_finite() && f.min_component() > 0.f && f.max_component() <= 1.f) << n;
    }
    for (const char* n : {"Ag", "Al", "Au", "Cr", "Cu", "Fe", "Ir", "Mo", "Ni", "Ni_palik", "Rh", "Ti", "W"}) {
        ConductorIOR c = conductor_ior(n);
        EXPECT_GT(fresnel_conductor(1.f, c.eta, c.k).min_component(), 0.3f) << n;
    }
    try {
        conductor_ior("xyz");
        FAIL() << "no throw";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("unknown metal 'xyz'; known: a-C, Ag, Al, AlAs"), std::string::npos)
            << e.what();
    }
    EXPECT_FLOAT_EQ(dielectric_ior("water"), 1.333f);
    EXPECT_FLOAT_EQ(dielectric_ior("bk7"), 1.5046f);
    EXPECT_FLOAT_EQ(dielectric_ior("diamond"), 2.419f);
    EXPECT_THROW(dielectric_ior("unobtainium"), Error);
}
}  // namespace
}  // namespace pellucid
