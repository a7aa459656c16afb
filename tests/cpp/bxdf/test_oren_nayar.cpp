// Oren–Nayar / EON: Lambertian limit, EON analytic albedo, classic known value.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include "pellucid/bxdf/lambertian.h"
#include "pellucid/bxdf/oren_nayar.h"
#include "pellucid/sampling/rng.h"
#include "pellucid/sampling/warp.h"

namespace pellucid {
namespace {

TEST(OrenNayar, ZeroRoughnessIsExactlyLambertian) {
    const Spectrum rho(0.7f, 0.4f, 0.2f);
    Lambertian lam(rho);
    PCG32 rng(1, 2);
    for (auto v : {OrenNayarVariant::Classic, OrenNayarVariant::EON}) {
        OrenNayar on(rho, 0.f, v);
        for (int k = 0; k < 10000; ++k) {
            Vec3f wo = square_to_uniform_sphere(rng.next_2d()), wi = square_to_uniform_sphere(rng.next_2d());
            ASSERT_EQ(on.eval({}, wo, wi), lam.eval({}, wo, wi));
            ASSERT_EQ(on.pdf({}, wo, wi), lam.pdf({}, wo, wi));
            Vec2f u = rng.next_2d();
            auto a = on.sample({}, wo, 0.5f, u), b = lam.sample({}, wo, 0.5f, u);
            ASSERT_EQ(bool(a), bool(b));
            if (a) {
                ASSERT_EQ(a->wi, b->wi);
                ASSERT_EQ(a->weight, b->weight);
                ASSERT_EQ(a->pdf, b->pdf);
            }
        }
    }
}

TEST(OrenNayar, ClassicKnownValue) {
    // At normal incidence and exitance the B term vanishes: f = ρ/π · A, A = 1 − 0.5σ²/(σ² + 0.33).
    float s = 0.5f, A = 1.f - 0.5f * s * s / (s * s + 0.33f);
    OrenNayar on(Spectrum(1.f), s, OrenNayarVariant::Classic);
    EXPECT_NEAR(on.eval({}, Vec3f(0, 0, 1), Vec3f(0, 0, 1)).r, A / kPi, 1e-6f);
    // Grazing: finite (no tan θ blow-up).
    Spectrum f = on.eval({}, Vec3f(1e-7f, 0, 1).operator*=(1.f), Vec3f(std::sqrt(1 - 1e-14f), 0, 1e-7f));
    EXPECT_TRUE(f.is_finite());
}

TEST(OrenNayar, EonAnalyticAlbedoMatchesQuadrature) {
    // E_F(μ) and Ē_F of the FON lobe (EON §3) against brute-force quadrature of eval() with the
    // multiple-scattering part removed (r chosen so that we can separate: use ρ = 1 and compare
    // the FULL lobe's albedo to 1, and the single-scattering closed form separately).
    for (float r : {0.3f, 1.f})
        for (float mu : {0.05f, 0.4f, 0.9f}) {
            Vec3f wo(std::sqrt(1 - mu * mu), 0.f, mu);
            const float c1 = 0.5f - 2.f / (3.f * kPi), A = 1.f / (1.f + c1 * r), B = r * A;
            double e_ss = 0.0, e_full = 0.0;
            const int n = 400;
            OrenNayar on(Spectrum(1.f), r, OrenNayarVariant::EON);
            for (int i = 0; i < n; ++i)
                for (int j = 0; j < 2 * n; ++j) {
                    double th = (i + 0.5) / n * M_PI / 2, ph = (j + 0.5) / (2 * n) * 2 * M_PI;
                    Vec3f wi(float(std::sin(th) * std::cos(ph)), float(std::sin(th) * std::sin(ph)), float(std::cos(th)));
                    double s = dot(wo, wi) - wo.z * wi.z, t = s > 0 ? std::max(wo.z, wi.z) : 1.0;
                    double dw = std::sin(th) * (M_PI / 2 / n) * (M_PI / n);
                    e_ss += (A + B * s / t) / M_PI * wi.z * dw;
                    e_full += on.eval({}, wo, wi).r * dw;
                }
            EXPECT_NEAR(OrenNayar::eon_albedo(mu, r), e_ss, 2e-4) << "r=" << r << " mu=" << mu;
            EXPECT_NEAR(e_full, 1.0, 2e-4) << "EON white furnace r=" << r << " mu=" << mu;
        }
    for (float r : {0.3f, 1.f}) {
        double s = 0.0;
        for (int i = 0; i < 20000; ++i) {
            double mu = (i + 0.5) / 20000;
            s += OrenNayar::eon_albedo(float(mu), r) * mu;
        }
        EXPECT_NEAR(OrenNayar::eon_average_albedo(r), 2.0 * s / 20000, 1e-4) << r;
    }
}
}  // namespace
}  // namespace pellucid
