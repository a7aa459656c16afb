// χ² tests of every warp against its pdf, and pdf normalisation.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "pellucid/math/constants.h"
#include "pellucid/sampling/distribution_1d.h"
#include "pellucid/sampling/rng.h"
#include "pellucid/sampling/warp.h"
#include "support/chi2.h"

using namespace pellucid;
using test::chi2_test;

namespace {
constexpr int kSamples = 1000000;
constexpr int kWarpTests = 8;  // the number of χ² tests in this file (Šidák correction)
const double kAlpha = test::sidak_alpha(0.01, kWarpTests);

// Directions binned on an equal-area (cos θ, φ) grid over the sphere.
void chi2_directions(const std::function<Vec3f(Vec2f)>& warp, const std::function<float(const Vec3f&)>& pdf,
                     uint64_t seed) {
    const int nz = 40, nphi = 80;
    std::vector<double> obs(nz * nphi, 0.0), expct(nz * nphi, 0.0);
    PCG32 rng(seed, 7);
    for (int i = 0; i < kSamples; ++i) {
        Vec3f w = warp(rng.next_2d());
        ASSERT_NEAR(length(w), 1.f, 1e-4f);
        double z = clamp(double(w.z), -1.0, 1.0), phi = std::atan2(w.y, w.x);
        if (phi < 0) phi += 2 * M_PI;
        int iz = std::min(nz - 1, int((z + 1) / 2 * nz)), ip = std::min(nphi - 1, int(phi / (2 * M_PI) * nphi));
        obs[iz * nphi + ip] += 1;
    }
    double total = 0;
    for (int iz = 0; iz < nz; ++iz)
        for (int ip = 0; ip < nphi; ++ip) {
            double z0 = -1 + 2.0 * iz / nz, z1 = -1 + 2.0 * (iz + 1) / nz;
            double p0 = 2 * M_PI * ip / nphi, p1 = 2 * M_PI * (ip + 1) / nphi;
            // dω = dz dφ on the sphere.
            double v = test::integrate_2d([&](double z, double p) {
                double s = std::sqrt(std::max(0.0, 1 - z * z));
                return double(pdf(Vec3f(float(s * std::cos(p)), float(s * std::sin(p)), float(z))));
            }, z0, z1, p0, p1, 6);
            expct[iz * nphi + ip] = v * kSamples;
            total += v;
        }
    EXPECT_NEAR(total, 1.0, 2e-3) << "pdf must integrate to 1";
    auto r = chi2_test(obs, expct);
    EXPECT_GT(r.p_value, kAlpha) << r.message;
}
}  // namespace

TEST(WarpChi2, CosineHemisphere) {
    chi2_directions([](Vec2f u) { return square_to_cosine_hemisphere(u); },
                    [](const Vec3f& w) { return square_to_cosine_hemisphere_pdf(w); }, 1);
}
TEST(WarpChi2, UniformHemisphere) {
    chi2_directions(square_to_uniform_hemisphere, square_to_uniform_hemisphere_pdf, 2);
}
TEST(WarpChi2, UniformSphere) {
    chi2_directions(square_to_uniform_sphere, square_to_uniform_sphere_pdf, 3);
}
TEST(WarpChi2, UniformCone) {
    const float cm = 0.6f;
    chi2_directions([&](Vec2f u) { return square_to_uniform_cone(u, cm); },
                    [&](const Vec3f& w) { return square_to_uniform_cone_pdf(w, cm); }, 4);
}

TEST(WarpChi2, ConcentricDisk) {
    const int n = 60;
    std::vector<double> obs(n * n, 0.0), expct(n * n, 0.0);
    PCG32 rng(5, 1);
    for (int i = 0; i < kSamples; ++i) {
        Vec2f p = square_to_uniform_disk_concentric(rng.next_2d());
        ASSERT_LE(p.x * p.x + p.y * p.y, 1.0001f);
        int ix = std::min(n - 1, int((p.x + 1) / 2 * n)), iy = std::min(n - 1, int((p.y + 1) / 2 * n));
        obs[iy * n + ix] += 1;
    }
    for (int iy = 0; iy < n; ++iy)
        for (int ix = 0; ix < n; ++ix)
            expct[iy * n + ix] = kSamples * test::integrate_2d([](double x, double y) {
                return double(square_to_uniform_disk_concentric_pdf(Vec2f(float(x), float(y))));
            }, -1 + 2.0 * ix / n, -1 + 2.0 * (ix + 1) / n, -1 + 2.0 * iy / n, -1 + 2.0 * (iy + 1) / n, 8);
    auto r = chi2_test(obs, expct);
    EXPECT_GT(r.p_value, kAlpha) << r.message;
}

TEST(WarpChi2, UniformTriangle) {
    // Barycentrics (b0, b1) must be uniform over the triangle b0, b1 ≥ 0, b0 + b1 ≤ 1 (density 2).
    const int n = 50;
    std::vector<double> obs(n * n, 0.0), expct(n * n, 0.0);
    PCG32 rng(6, 1);
    for (int i = 0; i < kSamples; ++i) {
        Vec2f b = square_to_uniform_triangle(rng.next_2d());
        ASSERT_GE(b.x, 0.f);
        ASSERT_GE(b.y, 0.f);
        ASSERT_LE(b.x + b.y, 1.0001f);
        obs[std::min(n - 1, int(b.y * n)) * n + std::min(n - 1, int(b.x * n))] += 1;
    }
    for (int iy = 0; iy < n; ++iy)
        for (int ix = 0; ix < n; ++ix)
            expct[iy * n + ix] = kSamples * test::integrate_2d([](double x, double y) { return x + y <= 1 ? 2.0 : 0.0; },
                                                              double(ix) / n, double(ix + 1) / n, double(iy) / n,
                                                              double(iy + 1) / n, 16);
    auto r = chi2_test(obs, expct);
    EXPECT_GT(r.p_value, kAlpha) << r.message;
}

TEST(WarpChi2, FilterTentAndGaussian) {
    const int n = 64;
    for (int which = 0; which < 2; ++which) {
        std::vector<double> obs(n, 0.0), expct(n, 0.0);
        PCG32 rng(7 + which, 1);
        const float r = which == 0 ? 1.5f : 2.f, sigma = 0.5f;
        for (int i = 0; i < kSamples; ++i) {
            float u = rng.next_float();
            float x = which == 0 ? sample_tent(u, r) : sample_truncated_gaussian(u, sigma, r);
            ASSERT_LE(std::fabs(x), r * 1.0001f);
            obs[std::min(n - 1, int((x + r) / (2 * r) * n))] += 1;
        }
        double total = 0;
        for (int i = 0; i < n; ++i) {
            double x0 = -r + 2.0 * r * i / n, x1 = -r + 2.0 * r * (i + 1) / n, s = 0;
            for (int k = 0; k < 64; ++k) {
                double x = x0 + (k + 0.5) * (x1 - x0) / 64;
                s += which == 0 ? tent_pdf(float(x), r) : truncated_gaussian_pdf(float(x), sigma, r);
            }
            expct[i] = kSamples * s * (x1 - x0) / 64;
            total += s * (x1 - x0) / 64;
        }
        EXPECT_NEAR(total, 1.0, 1e-3);
        auto res = chi2_test(obs, expct);
        EXPECT_GT(res.p_value, kAlpha) << (which ? "gaussian " : "tent ") << res.message;
    }
}

TEST(Distribution1D, DiscreteMatchesWeights) {
    Distribution1D d({1.f, 0.f, 3.f, 4.f});
    EXPECT_FLOAT_EQ(d.pmf(0), 0.125f);
    EXPECT_FLOAT_EQ(d.pmf(1), 0.f);
    std::vector<double> obs(4, 0.0), expct = {0.125 * kSamples, 0, 0.375 * kSamples, 0.5 * kSamples};
    PCG32 rng(9, 3);
    for (int i = 0; i < kSamples; ++i) obs[d.sample_discrete(rng.next_float())] += 1;
    EXPECT_EQ(obs[1], 0.0) << "a zero-weight cell must never be chosen";
    auto r = chi2_test(obs, expct);
    EXPECT_GT(r.p_value, kAlpha) << r.message;
}

TEST(PCG32, SeedsAreIndependentOfSplit) {
    // The stream for (pixel, sample, seed) is a pure function of its inputs.
    PCG32 a = PCG32::for_sample(12, 3, 0), b = PCG32::for_sample(12, 3, 0), c = PCG32::for_sample(12, 4, 0);
    EXPECT_EQ(a.next_u32(), b.next_u32());
    EXPECT_NE(PCG32::for_sample(12, 3, 0).next_u32(), c.next_u32());
    PCG32 r(1, 1);
    for (int i = 0; i < 1000; ++i) {
        float f = r.next_float();
        ASSERT_GE(f, 0.f);
        ASSERT_LT(f, 1.f);
    }
}
