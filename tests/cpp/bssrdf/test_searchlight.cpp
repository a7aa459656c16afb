// The searchlight random walk against what can be proved (Beer–Lambert, single scattering, energy
// bookkeeping), its determinism and input checks; then the diffusion profiles against it: totals
// and R(r) over albedo, and the thin-slab error law. The bounds and their measurements are in
// docs/subsurface.md ("Accuracy against the random walk", "Thin slabs").
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "pellucid/bssrdf/profile.h"
#include "pellucid/bssrdf/searchlight.h"
#include "pellucid/bxdf/fresnel.h"
#include "pellucid/util/error.h"
#include "support/chi2.h"

using namespace pellucid;
using namespace pellucid::bssrdf;

namespace {
/// Two-sided standard normal quantile for tail probability p (bisection on erfc).
double z_crit(double p) {
    double lo = 0.0, hi = 40.0;
    for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi);
        (std::erfc(mid / std::sqrt(2.0)) > p ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}
/// z score of a binomial count against its expected probability.
double z_binomial(double count, double n, double p) { return (count - n * p) / std::sqrt(n * p * (1.0 - p)); }

/// The profile's mean exitance per unit area over the ring [a, b) (Gauss–Legendre in r).
double ring_mean(const Profile& p, double a, double b) {
    std::vector<double> x, w;
    test::gauss_legendre(24, x, w);
    double s = 0.0;
    for (size_t j = 0; j < x.size(); ++j) {
        const double r = 0.5 * (a + b) + 0.5 * (b - a) * x[j];
        s += 0.5 * (b - a) * w[j] * 2.0 * M_PI * r * p.eval(float(r));
    }
    return s / (M_PI * (b * b - a * a));
}

/// Single-scattered exitance of a half-space with η = 1 (no boundary reflection), normal beam, HG(g),
/// σt = 1, albedo a, integrated over the ring [r0, r1): the photon's first collision is at depth z
/// (density e^(−z)); it scatters toward the surface point at distance d = sqrt(r² + z²) with
/// probability a·p(cos θ) dω, cos θ = −z/d, dω = (z/d) dA/d², and crosses the path d unabsorbed with
/// e^(−d). With d dd = r dr the ring integral is ∫ dz e^(−z) ∫_{d0}^{d1} 2π a z p(−z/d) e^(−d)/d² dd.
double single_scatter_ring(double a, double g, double r0, double r1) {
    std::vector<double> x, w;
    test::gauss_legendre(16, x, w);
    auto hg = [g](double c) { return (1.0 - g * g) / (4.0 * M_PI * std::pow(1.0 + g * g - 2.0 * g * c, 1.5)); };
    auto gl = [&](auto&& f, double lo, double hi, int panels) {
        double s = 0.0, h = (hi - lo) / panels;
        for (int k = 0; k < panels; ++k)
            for (size_t j = 0; j < x.size(); ++j) s += 0.5 * h * w[j] * f(lo + h * (k + 0.5 + 0.5 * x[j]));
        return s;
    };
    // Geometric panels from lo (the integrands vary on the scale of their lower end: z/d² peaks at d = z).
    auto geometric = [&](auto&& f, double lo, double hi) {
        double s = 0.0, a0 = lo, a1 = std::max(lo * 1.25, 1e-7);
        while (a0 < hi) {
            s += gl(f, a0, std::min(a1, hi), 1);
            a0 = a1;
            a1 *= 1.25;
        }
        return s;
    };
    return geometric(
        [&](double z) {
            const double d0 = std::sqrt(r0 * r0 + z * z), d1 = std::sqrt(r1 * r1 + z * z);
            return std::exp(-z) *
                   geometric([&](double d) { return 2.0 * M_PI * a * z * hg(-z / d) * std::exp(-d) / (d * d); }, d0, d1);
        },
        0.0, 50.0);
}

SearchlightSetup setup(double albedo, double g, double eta, double thickness, int64_t photons, uint64_t seed) {
    SearchlightSetup s;
    s.sigma_a = float(1.0 - albedo);
    s.sigma_s = float(albedo);
    s.g = float(g);
    s.eta = float(eta);
    s.thickness = thickness;
    s.photons = photons;
    s.seed = seed;
    return s;
}
}  // namespace

TEST(Searchlight, BeerLambertSlab) {
    // No scattering, σa = 1, T = 0.5, η = 1.5: the beam bounces between the faces with the normal
    // reflectance F0 = 0.04, so T = (1 − F0) e^(−τ)/(1 − F0² e^(−2τ)) and R = (1 − F0) F0 e^(−2τ)/(1 − F0² e^(−2τ)).
    // z-tests of both counts at α = 0.01 (Šidák over 2).
    const double tau = 0.5, F0 = fresnel_dielectric_d(1.0, 1.0 / 1.5);
    const double den = 1.0 - F0 * F0 * std::exp(-2 * tau);
    const double T = (1 - F0) * std::exp(-tau) / den, R = (1 - F0) * F0 * std::exp(-2 * tau) / den;
    const int64_t n = 200000;
    const auto res = searchlight(setup(0.0, 0.0, 1.5, tau, n, 3));
    const double zc = z_crit(test::sidak_alpha(0.01, 2));
    EXPECT_LT(std::fabs(z_binomial(res.transmittance * n, n, T)), zc) << res.transmittance << " vs " << T;
    EXPECT_LT(std::fabs(z_binomial(res.reflectance * n, n, R)), zc) << res.reflectance << " vs " << R;
    EXPECT_EQ(res.reflectance_single, 0.0);
    // A vacuum slab with η = 1 lets every photon through.
    SearchlightSetup v = setup(0.0, 0.0, 1.0, 2.0, 1000, 1);
    v.sigma_a = 0.f;
    EXPECT_EQ(searchlight(v).transmittance, 1.0);
}

TEST(Searchlight, SingleScatteringPerBin) {
    // η = 1, half-space: the single-scattered exitance per ring has the closed-form integral above;
    // each ring's count is binomial. z-tests at family-wise α = 0.01 (Šidák over 2 cases × 7 rings),
    // plus the total single scattering (a/2)(1 − ln 2) of the isotropic case.
    const std::vector<double> edges = {0.0, 0.1, 0.25, 0.5, 1.0, 2.0, 4.0, 8.0};
    const int64_t n = 200000;
    const double a = 0.7;
    const double zc = z_crit(test::sidak_alpha(0.01, 2 * 7 + 1));
    for (double g : {0.0, 0.7}) {
        SearchlightSetup s = setup(a, g, 1.0, INFINITY, n, 5);
        s.r_edges = edges;
        const auto res = searchlight(s);
        for (size_t k = 0; k + 1 < edges.size(); ++k) {
            const double p = single_scatter_ring(a, g, edges[k], edges[k + 1]);
            const double z = z_binomial(double(res.counts_single[k]), double(n), p);
            EXPECT_LT(std::fabs(z), zc) << "g=" << g << " ring [" << edges[k] << ", " << edges[k + 1] << "): count "
                                        << res.counts_single[k] << " expected " << p * n;
        }
        if (g == 0.0) {
            const double p = 0.5 * a * (1.0 - std::log(2.0));
            EXPECT_LT(std::fabs(z_binomial(res.reflectance_single * n, n, p)), zc) << res.reflectance_single << " vs " << p;
            EXPECT_NEAR(single_scatter_ring(a, 0.0, 0.0, 60.0), p, 1e-6);  // the quadrature itself
        }
    }
}

TEST(Searchlight, EnergyBookkeeping) {
    // Every photon is reflected, transmitted, absorbed or lost; with albedo 1 in a finite slab none
    // is absorbed or lost, so R + T = 1 exactly (analog walk: no weights to drift).
    const auto lossless = searchlight(setup(1.0, 0.6, 1.4, 3.0, 20000, 9));
    EXPECT_EQ(lossless.absorbed, 0.0);
    EXPECT_EQ(lossless.lost, 0.0);
    EXPECT_NEAR(lossless.reflectance + lossless.transmittance, 1.0, 1e-12);
    EXPECT_GT(lossless.transmittance, 0.1);
    const auto lossy = searchlight(setup(0.9, -0.3, 1.33, 5.0, 20000, 9));
    EXPECT_NEAR(lossy.reflectance + lossy.transmittance + lossy.absorbed + lossy.lost, 1.0, 1e-12);
    EXPECT_GT(lossy.absorbed, 0.1);
}

TEST(Searchlight, DeterministicOverThreads) {
    SearchlightSetup s = setup(0.95, 0.3, 1.33, 4.0, 30000, 21);
    s.r_edges = {0.0, 0.5, 1.0, 4.0};
    s.threads = 1;
    const auto one = searchlight(s);
    s.threads = 2;
    const auto two = searchlight(s);
    EXPECT_EQ(one.reflectance, two.reflectance);
    EXPECT_EQ(one.transmittance, two.transmittance);
    EXPECT_EQ(one.counts, two.counts);
    EXPECT_EQ(one.chunk_reflectance, two.chunk_reflectance);
    s.seed = 22;
    EXPECT_NE(searchlight(s).reflectance, one.reflectance);
}

TEST(Searchlight, StabilityGrid) {
    // ../shared/REFERENCE.md §7.2: albedo 0 and 1, σt from 1e-3 to 1e4, g = ±0.99, η = 1 and near 1.
    // Albedo 1 runs in a finite slab (a lossless half-space has walks of unbounded mean length).
    for (double albedo : {0.0, 0.5, 1.0})
        for (double sigma_t : {1e-3, 1.0, 1e4})
            for (double g : {-0.99, 0.99})
                for (double eta : {1.0, 1.0001, 1.33}) {
                    SearchlightSetup s;
                    s.sigma_a = float((1 - albedo) * sigma_t);
                    s.sigma_s = float(albedo * sigma_t);
                    s.g = float(g);
                    s.eta = float(eta);
                    s.thickness = albedo == 1.0 ? 3.0 / sigma_t : INFINITY;
                    s.photons = 500;
                    s.r_edges = {0.0, 1.0 / sigma_t, 10.0 / sigma_t};
                    const auto r = searchlight(s);
                    const std::string where = "albedo=" + std::to_string(albedo) + " sigma_t=" + std::to_string(sigma_t) +
                                              " g=" + std::to_string(g) + " eta=" + std::to_string(eta);
                    for (double v : {r.reflectance, r.transmittance, r.absorbed, r.lost, r.reflectance_single})
                        ASSERT_TRUE(std::isfinite(v) && v >= 0.0 && v <= 1.0) << where;
                    for (double v : r.exitance) ASSERT_TRUE(std::isfinite(v) && v >= 0.0) << where;
                    ASSERT_EQ(r.lost, 0.0) << where;
                    ASSERT_NEAR(r.reflectance + r.transmittance + r.absorbed, 1.0, 1e-12) << where;
                }
}

TEST(Searchlight, BadInputNamesTheParameter) {
    auto message = [](SearchlightSetup s) {
        try {
            searchlight(s);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    SearchlightSetup s;
    s.sigma_a = -1.f;
    EXPECT_NE(message(s).find("sigma_a"), std::string::npos);
    s = SearchlightSetup();
    s.thickness = 0.0;
    EXPECT_NE(message(s).find("thickness"), std::string::npos);
    s = SearchlightSetup();
    s.r_edges = {0.0, 2.0, 1.0};
    EXPECT_NE(message(s).find("r_edges[2]"), std::string::npos);
    s = SearchlightSetup();
    s.g = 1.5f;
    EXPECT_NE(message(s).find("g:"), std::string::npos);
    s = SearchlightSetup();
    s.photons = 0;
    EXPECT_NE(message(s).find("photons"), std::string::npos);
}

TEST(ProfileAccuracy, TotalsAndRingsAgainstRandomWalk) {
    // Half-space, η = 1.33, g = 0, σt = 1 (lengths in mean free paths), 10⁵ photons per albedo.
    // Bounds on |total/R_walk − 1|: the errors measured with 10⁶ photons (docs/subsurface.md) plus
    // about 4 standard errors of this run's R_walk plus 1 percentage point.
    struct Row {
        double albedo, dipole_bound, better_bound;
    };
    const Row rows[] = {{0.5, 0.28, 0.14}, {0.8, 0.15, 0.12}, {0.9, 0.07, 0.095},
                        {0.95, 0.025, 0.065}, {0.99, 0.025, 0.025}, {0.999, 0.015, 0.01}};
    // Rings in the diffusive range, 2 to 16 mfp, where both models hold for albedo ≥ 0.99: measured
    // within 5 % (dipole) and 18 % (better dipole); bounds 7 % and 21 %.
    const std::vector<double> edges = {2.0, 4.0, 8.0, 16.0};
    const int64_t n = 100000;
    for (const Row& row : rows) {
        SearchlightSetup s = setup(row.albedo, 0.0, 1.33, INFINITY, n, 17);
        s.r_edges = edges;
        const auto walk = searchlight(s);
        const Profile d = Profile::make(Diffusion::Dipole, s.sigma_a, s.sigma_s, 0.f, 1.33f);
        const Profile b = Profile::make(Diffusion::BetterDipole, s.sigma_a, s.sigma_s, 0.f, 1.33f);
        const double ed = d.total() / walk.reflectance - 1.0, eb = b.total() / walk.reflectance - 1.0;
        EXPECT_LT(std::fabs(ed), row.dipole_bound) << "albedo " << row.albedo << ": dipole " << d.total() << " walk " << walk.reflectance;
        EXPECT_LT(std::fabs(eb), row.better_bound) << "albedo " << row.albedo << ": better dipole " << b.total() << " walk "
                                                   << walk.reflectance;
        if (row.albedo < 0.99) continue;
        for (size_t k = 0; k + 1 < edges.size(); ++k) {
            const double w = walk.exitance[k];
            EXPECT_LT(std::fabs(ring_mean(d, edges[k], edges[k + 1]) / w - 1.0), 0.07) << "albedo " << row.albedo << " ring " << k;
            EXPECT_LT(std::fabs(ring_mean(b, edges[k], edges[k + 1]) / w - 1.0), 0.21) << "albedo " << row.albedo << " ring " << k;
        }
    }
}

TEST(ProfileAccuracy, ThinSlabErrorDecaysAsExpMinus2T) {
    // Albedo 0.99, η = 1.33, g = 0: the semi-infinite model's extra error in a slab of thickness T is
    // R(∞) − R(T) (the dipole's error against the slab minus its error against the half-space). Each
    // slab runs with the seed of the half-space run, so paths agree until they first reach depth T
    // and the paired difference per chunk of photons has a small variance (batch means over chunks).
    // A weighted least-squares fit of ln(R(∞) − R(T)) = ln C − k T/ℓd over T/ℓd ∈ [0.5, 2.5]
    // (ℓd = the dipole's 1/σtr) measured k = 2.13 with 2·10⁶ photons per slab; this run (4·10⁵) must
    // find k in [1.85, 2.45], i.e. the e^(−2T/ℓd) law of ../shared/REFERENCE.md §5.5 within its fit
    // error. The transmittance decays with about half that rate (fit: k_T in [0.8, 1.25]).
    const double albedo = 0.99;
    const int64_t n = 400000;
    SearchlightSetup s = setup(albedo, 0.0, 1.33, INFINITY, n, 11);
    const double ld = Profile::make(Diffusion::Dipole, s.sigma_a, s.sigma_s, 0.f, 1.33f).diffusion_length();
    const auto half = searchlight(s);
    double sw = 0, swx = 0, swy = 0, swxx = 0, swxy = 0;
    double tw = 0, twx = 0, twy = 0, twxx = 0, twxy = 0;
    for (double tau : {0.5, 1.0, 1.5, 2.0, 2.5}) {
        s.thickness = tau * ld;
        const auto slab = searchlight(s);
        const size_t m = slab.chunk_reflectance.size();
        double mean = 0.0, var = 0.0;
        for (size_t c = 0; c < m; ++c) mean += (half.chunk_reflectance[c] - slab.chunk_reflectance[c]) / double(m);
        for (size_t c = 0; c < m; ++c) var += std::pow(half.chunk_reflectance[c] - slab.chunk_reflectance[c] - mean, 2);
        const double se = std::sqrt(var / double(m - 1) / double(m));
        const double diff = half.reflectance - slab.reflectance;
        ASSERT_GT(diff, 2.0 * se) << "T/ld=" << tau;
        const double wgt = (diff / se) * (diff / se), y = std::log(diff);  // 1/var of ln(diff)
        sw += wgt, swx += wgt * tau, swy += wgt * y, swxx += wgt * tau * tau, swxy += wgt * tau * y;
        const double tt = slab.transmittance, tse = std::sqrt(tt * (1 - tt) / double(n));
        const double twg = (tt / tse) * (tt / tse), ty = std::log(tt);
        tw += twg, twx += twg * tau, twy += twg * ty, twxx += twg * tau * tau, twxy += twg * tau * ty;
    }
    const double k = -(sw * swxy - swx * swy) / (sw * swxx - swx * swx);
    const double k_se = std::sqrt(sw / (sw * swxx - swx * swx));
    const double kt = -(tw * twxy - twx * twy) / (tw * twxx - twx * twx);
    EXPECT_GT(k, 1.85) << "fit error " << k_se;
    EXPECT_LT(k, 2.45) << "fit error " << k_se;
    EXPECT_GT(kt, 0.8);
    EXPECT_LT(kt, 1.25);
    RecordProperty("k", std::to_string(k));
    std::printf("thin slab: k = %.3f ± %.3f, transmittance rate %.3f\n", k, k_se, kt);
}
