// Diffusion profiles: Fresnel moments, closed-form totals against quadrature, exact-CDF sampling (χ²),
// the diffuse-colour inversion and the stability grid of ../shared/REFERENCE.md §7.2.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "pellucid/bssrdf/profile.h"
#include "pellucid/bxdf/fresnel.h"
#include "pellucid/sampling/rng.h"
#include "support/chi2.h"

using namespace pellucid;
using namespace pellucid::bssrdf;

namespace {
const Diffusion kModels[] = {Diffusion::Dipole, Diffusion::BetterDipole};
const char* name(Diffusion m) { return m == Diffusion::Dipole ? "dipole" : "better_dipole"; }

/// ∫0^1 f(μ) dμ by an n-point midpoint rule (independent of the library's Gauss–Legendre).
template <class F>
double midpoint(F&& f, int n) {
    double s = 0.0;
    for (int k = 0; k < n; ++k) s += f((k + 0.5) / n);
    return s / n;
}

/// ∫0^∞ 2πr R(r) dr by composite Gauss–Legendre in t = ln r over r ∈ [1e-9, 1e9]·mfp (the
/// profile's mass below and above is < 1e-9 of the total).
double radial_integral(const Profile& p) {
    std::vector<double> x, w;
    test::gauss_legendre(16, x, w);
    const double mfp = p.mean_free_path();
    const double t0 = std::log(1e-9 * mfp), t1 = std::log(1e9 * mfp);
    const int panels = 160;
    const double h = (t1 - t0) / panels;
    double sum = 0.0;
    for (int k = 0; k < panels; ++k)
        for (size_t j = 0; j < x.size(); ++j) {
            const double r = std::exp(t0 + h * (k + 0.5 + 0.5 * x[j]));
            sum += 0.5 * h * w[j] * 2.0 * M_PI * r * r * double(p.eval(float(r)));
        }
    return sum;
}

/// Egan & Hilgeman 1979 fit of the internal diffuse Fresnel reflectance, as Jensen et al. 2001 quote it.
double egan_hilgeman_fdr(double eta) { return -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta; }
}  // namespace

TEST(FresnelMoment, IndexMatchedIsZero) {
    for (int i : {0, 1, 2})
        for (bool internal : {false, true}) EXPECT_EQ(fresnel_moment(i, 1.0, internal), 0.0);
    EXPECT_FLOAT_EQ(exit_lobe_norm(1.f), 1.f);
}

TEST(FresnelMoment, MatchesMidpointRule) {
    // An independent 2·10⁵-point midpoint rule of the same integrand (its error is ~1e-7 at the
    // critical-angle kink, so the tolerance is 1e-6).
    for (double eta : {0.7, 1.0001, 1.33, 1.5, 2.4})
        for (bool internal : {false, true})
            for (int i : {1, 2}) {
                const double n = internal ? 1.0 / eta : eta;
                const double ref = midpoint([&](double mu) { return fresnel_dielectric_d(mu, n) * std::pow(mu, i); }, 200000);
                EXPECT_NEAR(fresnel_moment(i, eta, internal), ref, 1e-6) << "eta=" << eta << " i=" << i << " internal=" << internal;
            }
}

TEST(FresnelMoment, ReciprocityOfDiffuseTransmission) {
    // Snell's law gives μo dμo = η² μi dμi and F_ext(μo) = F_int(μi), so the hemispherical
    // transmittances satisfy 1 − 2C1(ext) = η² (1 − 2C1(int)) exactly (η² is the radiance-invariant
    // factor of the n²-law).
    for (double eta : {0.6, 1.0001, 1.2, 1.33, 1.5, 2.0, 3.0}) {
        const double ext = 1.0 - 2.0 * fresnel_moment(1, eta, false);
        const double in = 1.0 - 2.0 * fresnel_moment(1, eta, true);
        EXPECT_NEAR(ext, eta * eta * in, 1e-10) << "eta=" << eta;
    }
}

TEST(FresnelMoment, AgreesWithEganHilgemanFit) {
    // The fit's own accuracy: |2 C1(int) − Fdr_EH| < 0.01 over η ∈ [1.1, 1.6] (measured maximum 0.0011
    // over [1.05, 2]).
    for (double eta : {1.1, 1.2, 1.3, 1.33, 1.4, 1.5, 1.6})
        EXPECT_NEAR(2.0 * fresnel_moment(1, eta, true), egan_hilgeman_fdr(eta), 0.01) << "eta=" << eta;
    // Total internal reflection alone gives 2 C1(int) ≥ 1 − 1/η².
    EXPECT_GT(2.0 * fresnel_moment(1, 1.3, true), 1.0 - 1.0 / (1.3 * 1.3));
}

TEST(FresnelMoment, ExitLobeIntegratesToOne) {
    for (float eta : {1.f, 1.0001f, 1.33f, 1.5f, 2.5f, 0.8f}) {
        const double c = exit_lobe_norm(eta);
        // ∫ (1 − F(cos θ))/(cπ) cos θ dω = 2π ∫0^1 (1 − F(μ)) μ dμ /(cπ).
        const double v = midpoint([&](double mu) { return (1.0 - fresnel_dielectric_d(mu, eta)) * mu; }, 200000) * 2.0 / c;
        EXPECT_NEAR(v, 1.0, 1e-6) << "eta=" << eta;
    }
}

TEST(Profile, RadialIntegralEqualsTotal) {
    for (Diffusion m : kModels)
        for (double alpha : {0.01, 0.3, 0.8, 0.95, 0.999, 1.0})
            for (float eta : {1.f, 1.33f, 1.6f})
                for (float g : {0.f, 0.9f, -0.5f})
                    for (float sigma_t : {1e-2f, 1.f, 1e3f}) {
                        // σ't = sigma_t: σ's = α' σ't, σs = σ's/(1 − g).
                        const float sa = float((1.0 - alpha) * sigma_t), ss = float(alpha * sigma_t / (1.0 - g));
                        const Profile p = Profile::make(m, sa, ss, g, eta);
                        const double q = radial_integral(p);
                        EXPECT_NEAR(q / p.total(), 1.0, 1e-4) << name(m) << " alpha'=" << alpha << " eta=" << eta << " g=" << g
                                                              << " sigma_t=" << sigma_t;
                    }
}

TEST(Profile, DipoleTotalClosedForm) {
    // Jensen et al. 2001, eq. 6 (with A from the exact Fdr = 2 C1(int)).
    for (double alpha : {0.0, 0.2, 0.5, 0.9, 0.99, 1.0})
        for (float eta : {1.f, 1.3f, 1.5f}) {
            const double fdr = 2.0 * fresnel_moment(1, eta, true), A = (1 + fdr) / (1 - fdr);
            const double s = std::sqrt(3.0 * (1.0 - alpha));
            const double ref = 0.5 * alpha * (1.0 + std::exp(-4.0 / 3.0 * A * s)) * std::exp(-s);
            const Profile p = Profile::make(Diffusion::Dipole, float(1.0 - alpha), float(alpha), 0.f, eta);
            EXPECT_NEAR(p.total(), ref, 1e-6 * std::max(ref, 1e-3)) << "alpha'=" << alpha << " eta=" << eta;
        }
}

TEST(Profile, EnergyConservedAtAlbedoOne) {
    // σa = 0: every entered photon leaves, and both models' totals are exactly 1 (the better
    // dipole's only through the right signs of ze and of its fluence term).
    for (Diffusion m : kModels)
        for (float eta : {1.f, 1.2f, 1.33f, 2.f}) {
            EXPECT_NEAR(Profile::make(m, 0.f, 3.f, 0.f, eta).total(), 1.0, 1e-6) << name(m) << " eta=" << eta;
            EXPECT_NEAR(total_of_reduced_albedo(m, 1.0, eta), 1.0, 1e-9) << name(m);
        }
}

TEST(Profile, TotalRisesWithAlbedo) {
    for (Diffusion m : kModels)
        for (double eta : {1.0, 1.33, 2.0}) {
            double prev = -1.0;
            for (int k = 0; k <= 1000; ++k) {
                const double t = total_of_reduced_albedo(m, k / 1000.0, eta);
                EXPECT_GT(t, prev) << name(m) << " alpha'=" << k / 1000.0;
                prev = t;
            }
        }
}

TEST(Profile, SamplingChi2) {
    // 2 models × 4 albedos × 2 indices × 2 anisotropies = 32 χ² tests at family-wise α = 0.01
    // (Šidák), 10⁵ samples each in 48 cells r ∈ r_max·[(k/48)², ((k+1)/48)²]. Expected counts are
    // the Gauss–Legendre integral of 2πr pdf(r) over each cell.
    const int kCells = 48, kSamples = 100000, kTests = 32;
    const double alpha_sidak = test::sidak_alpha(0.01, kTests);
    std::vector<double> x, w;
    test::gauss_legendre(16, x, w);
    uint64_t stream = 1;
    for (Diffusion m : kModels)
        for (double alpha : {0.2, 0.9, 0.99, 1.0})
            for (float eta : {1.f, 1.4f})
                for (float g : {0.f, 0.8f}) {
                    const Profile p = Profile::make(m, float(1.0 - alpha) * 2.f, float(alpha / (1.0 - g)) * 2.f, g, eta);
                    const double rm = p.r_max();
                    auto edge = [&](int k) { return rm * double(k) * k / (double(kCells) * kCells); };
                    std::vector<double> obs(kCells, 0.0), expd(kCells, 0.0);
                    PCG32 rng(0x5eed, stream++);
                    for (int i = 0; i < kSamples; ++i) {
                        const double r = p.sample(rng.next_float());
                        ASSERT_LE(r, rm);
                        const int k = std::min(kCells - 1, int(std::sqrt(r / rm) * kCells));
                        obs[k] += 1.0;
                    }
                    double mass = 0.0;
                    for (int k = 0; k < kCells; ++k) {
                        const double a = edge(k), b = edge(k + 1);
                        double s = 0.0;
                        for (size_t j = 0; j < x.size(); ++j) {
                            const double r = 0.5 * (a + b) + 0.5 * (b - a) * x[j];
                            s += 0.5 * (b - a) * w[j] * 2.0 * M_PI * r * p.pdf(float(r));
                        }
                        expd[k] = s * kSamples;
                        mass += s;
                    }
                    EXPECT_NEAR(mass, 1.0, 1e-4) << "pdf does not integrate to 1";
                    const auto res = test::chi2_test(obs, expd);
                    EXPECT_GT(res.p_value, alpha_sidak) << name(m) << " alpha'=" << alpha << " eta=" << eta << " g=" << g << ": "
                                                        << res.message;
                }
}

TEST(Profile, PdfIsProfileOverCoveredMass) {
    // pdf = R/(0.999·total) inside r_max (the sampling is by the exact CDF), 0 beyond; r_max holds
    // 99.9 % of the profile's mass.
    for (Diffusion m : kModels) {
        const Profile p = Profile::make(m, 0.05f, 4.f, 0.3f, 1.33f);
        for (float r : {0.f, 0.1f, 0.5f, 2.f})
            if (r <= p.r_max()) {
                EXPECT_NEAR(p.pdf(r) * 0.999f * p.total() / p.eval(r), 1.0, 1e-5) << name(m) << " r=" << r;
            }
        EXPECT_EQ(p.pdf(p.r_max() * 1.01f), 0.f);
        EXPECT_EQ(p.sample(0.f), 0.f);
        // The tail mass beyond r_max: 0.1 %.
        const double tail = p.shape_tail(double(p.r_max()) / p.mean_free_path()) / p.shape_tail(0.0);
        EXPECT_NEAR(tail, 1e-3, 1e-7) << name(m);
        EXPECT_NEAR(p.sample(1.f - 1e-7f), p.r_max(), 1e-3 * p.r_max());
    }
}

TEST(Profile, LengthsFollowTheModels) {
    const float sa = 0.1f, ss = 2.f, g = 0.5f;
    const double stp = sa + ss * (1 - g);
    const Profile d = Profile::make(Diffusion::Dipole, sa, ss, g, 1.3f);
    const Profile b = Profile::make(Diffusion::BetterDipole, sa, ss, g, 1.3f);
    EXPECT_FLOAT_EQ(d.mean_free_path(), float(1.0 / stp));
    EXPECT_FLOAT_EQ(d.diffusion_length(), float(1.0 / std::sqrt(3.0 * sa * stp)));
    const double D = (2.0 * sa + ss * (1 - g)) / (3.0 * stp * stp);
    EXPECT_FLOAT_EQ(b.diffusion_length(), float(1.0 / std::sqrt(sa / D)));
    EXPECT_FLOAT_EQ(d.reduced_albedo(), float(ss * (1 - g) / stp));
}

TEST(Profile, FromDiffuseRoundTrip) {
    for (Diffusion m : kModels)
        for (float albedo : {0.f, 0.01f, 0.3f, 0.8f, 0.99f, 0.999f})
            for (float mfp : {1e-3f, 1.f, 100.f})
                for (float g : {0.f, 0.8f, -0.3f})
                    for (float eta : {1.f, 1.4f}) {
                        float sa = -1.f, ss = -1.f;
                        ASSERT_TRUE(from_diffuse(m, albedo, mfp, g, eta, &sa, &ss));
                        const Profile p = Profile::make(m, sa, ss, g, eta);
                        EXPECT_NEAR(p.total(), albedo, 2e-6) << name(m) << " albedo=" << albedo << " mfp=" << mfp << " g=" << g;
                        EXPECT_NEAR(p.mean_free_path() / mfp, 1.0, 1e-5);
                    }
    float sa = 7.f, ss = 8.f;
    for (float bad_albedo : {-0.1f, 1.f, 1.5f, NAN}) EXPECT_FALSE(from_diffuse(Diffusion::Dipole, bad_albedo, 1.f, 0.f, 1.3f, &sa, &ss));
    EXPECT_FALSE(from_diffuse(Diffusion::Dipole, 0.5f, 0.f, 0.f, 1.3f, &sa, &ss));
    EXPECT_FALSE(from_diffuse(Diffusion::Dipole, 0.5f, 1.f, 1.f, 1.3f, &sa, &ss));
    EXPECT_FALSE(from_diffuse(Diffusion::Dipole, 0.5f, 1.f, 0.f, 0.f, &sa, &ss));
    EXPECT_EQ(sa, 7.f);
    EXPECT_EQ(ss, 8.f);
}

TEST(Profile, StabilityGrid) {
    // ../shared/REFERENCE.md §7.2: albedo 0 and 1, σt from 1e-3 to 1e4 per scene unit, g = ±0.99,
    // η = 1 and 1 ± 1e-4: every value finite and ≥ 0, samples within r_max, pdf > 0 at samples.
    int checked = 0;
    for (Diffusion m : kModels)
        for (float albedo : {0.f, 1e-4f, 0.5f, 0.999f, 1.f})
            for (float sigma_t : {1e-3f, 1.f, 1e4f})
                for (float g : {-0.99f, 0.f, 0.99f})
                    for (float eta : {1.f, 1.0001f, 0.9999f, 1.33f, 3.f}) {
                        const Profile p = Profile::make(m, (1.f - albedo) * sigma_t, albedo * sigma_t, g, eta);
                        const std::string where = std::string(name(m)) + " albedo=" + std::to_string(albedo) +
                                                  " sigma_t=" + std::to_string(sigma_t) + " g=" + std::to_string(g) +
                                                  " eta=" + std::to_string(eta);
                        auto ok = [](float v) { return std::isfinite(v) && v >= 0.f; };
                        ASSERT_TRUE(ok(p.total()) && p.total() <= 1.f + 1e-6f) << where;
                        ASSERT_TRUE(ok(p.r_max()) && p.r_max() > 0.f) << where;
                        ASSERT_TRUE(ok(p.mean_free_path())) << where;
                        ASSERT_FALSE(std::isnan(p.diffusion_length())) << where;
                        for (float r : {0.f, 1e-30f, p.mean_free_path(), p.r_max(), 10.f * p.r_max(), 1e30f, INFINITY})
                            ASSERT_TRUE(ok(p.eval(r)) && ok(p.pdf(r))) << where << " r=" << r;
                        for (float u : {0.f, 1e-9f, 0.5f, 0.999f, 0.99999994f}) {
                            const float r = p.sample(u);
                            ASSERT_TRUE(ok(r) && r <= p.r_max()) << where << " u=" << u << " r=" << r;
                            if (u > 0.f) {
                                ASSERT_GT(p.pdf(r), 0.f) << where << " u=" << u;
                            }
                        }
                        ++checked;
                    }
    EXPECT_EQ(checked, 2 * 5 * 3 * 3 * 5);
    // Nonsense input is clamped, never NaN.
    for (const Profile& p : {Profile::make(Diffusion::BetterDipole, NAN, -1.f, 2.f, -1.f),
                             Profile::make(Diffusion::Dipole, 0.f, 0.f, 0.f, 1.3f)}) {
        EXPECT_EQ(p.total(), 0.f);
        EXPECT_EQ(p.eval(1.f), 0.f);
        EXPECT_EQ(p.sample(0.5f), 0.f);
        EXPECT_EQ(p.pdf(0.f), 0.f);
    }
}
