// The integrator contract of medium/medium.h against analytic answers: Beer–Lambert, unbiased
// distance sampling (transmittance and single scattering along a segment, with chromatic σt and
// the channel MIS), and delta tracking, ratio tracking and the homogeneous case agreeing.
// Statistical checks are z-tests with fixed seeds: |z| < kZ = 4.5 per quantity (two-sided
// α ≈ 7e-6 each; the file makes about 150 such tests, so the family-wise α is ≈ 1e-3).
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "pellucid/medium/medium.h"
#include "pellucid/sampling/rng.h"

namespace pellucid::test {
namespace {
constexpr double kZ = 4.5;

/// Mean and standard error per channel of n estimates.
struct Stats {
    double s[3] = {0, 0, 0}, s2[3] = {0, 0, 0};
    int n = 0;
    void add(const Spectrum& v) {
        for (int c = 0; c < 3; ++c) {
            s[c] += v[c];
            s2[c] += double(v[c]) * v[c];
        }
        ++n;
    }
    double mean(int c) const { return s[c] / n; }
    double se(int c) const { return std::sqrt(std::max(s2[c] / n - mean(c) * mean(c), 0.0) / n); }
};
/// |mean − expected| ≤ kZ·SE (+ a float-rounding floor) for every channel.
void expect_unbiased(const Stats& st, const Spectrum& expected, const std::string& what) {
    for (int c = 0; c < 3; ++c) {
        const double tol = kZ * st.se(c) + 1e-6 * std::fabs(expected[c]) + 1e-9;
        EXPECT_NEAR(st.mean(c), expected[c], tol) << what << " channel " << c << " (SE " << st.se(c) << ")";
    }
}

HomogeneousMedium homogeneous(const Spectrum& sa, const Spectrum& ss, const Spectrum& le = Spectrum(0.f)) {
    HomogeneousMedium m;
    m.sigma_a = sa;
    m.sigma_s = ss;
    m.le = le;
    return m;
}
/// A grid of constant density `d` filling the box [lo, lo + size]³.
GridMedium constant_grid(float d, const Spectrum& sigma_t, const Spectrum& albedo, const Vec3f& lo, float size,
                         Tracking tr = Tracking::Ratio, int res = 40) {
    GridMedium m;
    m.grid = std::make_shared<DensityGrid>(DensityGrid::constant(res, d));
    m.sigma_t = sigma_t;
    m.albedo = albedo;
    m.world_to_grid = (Transform::translate(lo) * Transform::scale(Vec3f(size))).inverse_matrix();
    m.tracking = tr;
    return m;
}

const Spectrum kChromaticSt(0.3f, 1.1f, 2.4f);
const Spectrum kAlbedo(0.9f, 0.5f, 0.2f);
const Spectrum kBeta(0.6f, 0.3f, 0.1f);  // throughput: channel probabilities 0.6, 0.3, 0.1

TEST(Medium, Log1pOfLaneMath) {
    // lane_math::log1p_t on (−1, 0], the distance sampling's −ln(1 − u): within three float ulps of
    // double-precision log1p (log_t's two and the correction factor's rounding), small |x| (where
    // ln(1 + x) computed as ln of the rounded 1 + x loses every digit) included. Measured: 2.9e-7.
    double worst = 0.0;
    PCG32 rng(11, 2);
    auto check = [&](float x) {
        const double ref = std::log1p(double(x));
        const double err = ref == 0.0 ? std::fabs(double(lane_math::log1p_t(x))) : std::fabs(lane_math::log1p_t(x) / ref - 1.0);
        worst = std::max(worst, err);
    };
    for (int i = 0; i < 2000000; ++i) check(-rng.next_float());
    for (int i = 0; i < 200000; ++i) check(-float(std::exp(-40.0 * rng.next_double())));  // |x| down to 4e-18
    for (float x : {0.f, -0x1p-24f, -0x1p-25f, -0x1p-26f, -0.5f, -0.75f, -(1.f - 0x1p-24f)}) check(x);
    EXPECT_EQ(lane_math::log1p_t(-0.f), -0.f);
    EXPECT_LT(worst, 3.6e-7);
}

TEST(Medium, HomogeneousStepIsItsFormulasInDouble) {
    // homogeneous_step (sample_distance's step, the path kernel's packets) against the same
    // formulas in double precision with libm's log1p and exp: the same choice of collision or
    // passing, and t, weight and emitted to float accuracy, over random σt (zero channels included),
    // throughputs (black and negative ones included), tmax finite and infinite.
    PCG32 rng(5, 9);
    int scattered = 0, passed = 0;
    for (int i = 0; i < 200000; ++i) {
        float st[3], ss[3], le[3], beta[3];
        for (int c = 0; c < 3; ++c) {
            st[c] = rng.next_float() < 0.1f ? 0.f : 5.f * rng.next_float();
            ss[c] = st[c] * rng.next_float();
            le[c] = rng.next_float();
            beta[c] = rng.next_float();
        }
        const float kind = rng.next_float();
        if (kind < 0.05f) beta[0] = beta[1] = beta[2] = 0.f;
        else if (kind < 0.1f) beta[1] = -0.5f;
        const float uc = rng.next_float(), ut = rng.next_float();
        const float tmax = rng.next_float() < 0.3f ? kInfinity : 3.f * rng.next_float();
        const HomogeneousStepT<float> h = homogeneous_step<float>(st, ss, le, beta, uc, ut, tmax);
        // The reference, in double.
        const double s = double(beta[0]) + beta[1] + beta[2];
        double pmf[3];
        const bool uniform = !(s > 0.0) || beta[0] < 0.f || beta[1] < 0.f || beta[2] < 0.f;
        for (int c = 0; c < 3; ++c) pmf[c] = uniform ? 1.0 / 3.0 : beta[c] / s;
        // (The channel as the float pmf picks it: the same comparisons.)
        const float pf0 = uniform ? 1.f / 3.f : beta[0] / float((beta[0] + beta[1]) + beta[2]);
        const float pf1 = uniform ? 1.f / 3.f : beta[1] / float((beta[0] + beta[1]) + beta[2]);
        const int c = uc < pf0 ? 0 : uc < pf0 + pf1 ? 1 : 2;
        const double t = st[c] > 0.f ? -std::log1p(-double(ut)) / st[c] : INFINITY;
        const bool scat = t < tmax;
        // Decisions within float rounding of the boundary may go either way.
        if (std::isfinite(t) && std::fabs(t - tmax) < 1e-5 * t) continue;
        ASSERT_EQ(bool(h.scattered), scat) << i;
        const double d = scat ? t : tmax;
        double tr[3], p[3], m[3], sum = 0.0;
        for (int k = 0; k < 3; ++k) {
            tr[k] = st[k] > 0.f ? std::exp(-double(st[k]) * d) : 1.0;
            p[k] = scat ? st[k] * tr[k] : tr[k];
            m[k] = pmf[k] * p[k];
            sum += m[k];
        }
        const double q = pmf[c] * p[c], k = q > 0.0 && sum > 0.0 ? (m[c] / sum) / q : 0.0;
        auto near = [&](double got, double want, const char* what) {
            // Relative 1e-5 (exponents up to σt·t ≈ 100 amplify float rounding of their argument).
            EXPECT_NEAR(got, want, 1e-5 * std::fabs(want) + 1e-30) << what << " case " << i;
        };
        if (scat) {
            ++scattered;
            near(h.t, t, "t");
            for (int k2 = 0; k2 < 3; ++k2) {
                near(h.weight[k2], ss[k2] * tr[k2] * k, "weight");
                near(h.emitted[k2], double(st[k2]) * le[k2] * tr[k2] * k, "emitted");
            }
        } else {
            ++passed;
            for (int k2 = 0; k2 < 3; ++k2) {
                near(h.weight[k2], tr[k2] * k, "weight");
                EXPECT_EQ(h.emitted[k2], 0.f);
            }
        }
        if (::testing::Test::HasFailure()) break;
    }
    // Both branches are well covered (measured: about 150000 and 47000 cases).
    EXPECT_GT(scattered, 30000);
    EXPECT_GT(passed, 30000);
}

TEST(Medium, HomogeneousTransmittanceIsBeerLambert) {
    const HomogeneousMedium m = homogeneous(Spectrum(0.2f, 0.5f, 1.f), Spectrum(0.1f, 0.f, 2.f));
    PCG32 rng;
    auto u = [&] { return rng.next_float(); };
    for (float d : {0.f, 0.5f, 1.f, 3.f}) {
        Ray r{Point3f(1.f, 2.f, 3.f), Vec3f(0.f, 0.f, 2.f), d / 2.f};  // |d| = 2: the segment is d long
        const Spectrum t = transmittance(Medium(m), r, kBeta, u);
        EXPECT_FLOAT_EQ(t.r, std::exp(-0.3f * d));
        EXPECT_FLOAT_EQ(t.g, std::exp(-0.5f * d));
        EXPECT_FLOAT_EQ(t.b, std::exp(-3.f * d));
    }
    Ray inf{Point3f(0.f), Vec3f(1.f, 0.f, 0.f), kInfinity};
    EXPECT_EQ(transmittance(Medium(homogeneous(Spectrum(0.f, 1.f, 0.f), Spectrum(0.f))), inf, kBeta, u),
              Spectrum(1.f, 0.f, 1.f));
}

TEST(Medium, ChannelMisWeightsSumToOne) {
    PCG32 rng(1, 2);
    for (int k = 0; k < 1000; ++k) {
        Spectrum beta(rng.next_float(), rng.next_float(), rng.next_float());
        if (k % 5 == 0) beta.g = 0.f;
        const Spectrum pmf = channel_pmf(beta);
        EXPECT_NEAR(pmf.r + pmf.g + pmf.b, 1.f, 1e-6f);
        const Spectrum pdfs(rng.next_float() * 3.f, rng.next_float(), rng.next_float() * 0.1f);
        const Spectrum w = channel_mis_weights(pmf, pdfs);
        EXPECT_NEAR(w.r + w.g + w.b, 1.f, 1e-6f);
        for (int c = 0; c < 3; ++c) EXPECT_GE(w[c], 0.f);
    }
    EXPECT_EQ(channel_pmf(Spectrum(0.f)), Spectrum(1.f / 3.f));
    EXPECT_EQ(channel_pmf(Spectrum(NAN, 1.f, 1.f)), Spectrum(1.f / 3.f));
    EXPECT_EQ(channel_mis_weights(Spectrum(1.f / 3.f), Spectrum(0.f)), Spectrum(0.f));
    // sample_channel follows the pmf, and never picks a channel of probability 0.
    int counts[3] = {0, 0, 0};
    for (int k = 0; k < 100000; ++k) ++counts[sample_channel(Spectrum(0.5f, 0.f, 0.5f), rng.next_float())];
    EXPECT_EQ(counts[1], 0);
    EXPECT_NEAR(counts[0] / 1e5, 0.5, 0.01);
}

/// The segment estimators of one medium along one ray, against the analytic answers of a
/// homogeneous medium with coefficients (st, albedo) along a segment of length L (from a in the
/// medium to b; L = b − a): passing, E[weight·1{pass}] = T(L); single scattering with the
/// in-scattered radiance Ls(t) = 1 + t, E[weight·Ls(t)·1{collision}] = ∫ σs T(t)(1 + t) dt; and
/// emission E[emitted] = ∫ σt Le T dt = Le (1 − T(L)).
void check_segment(const Medium& m, const Ray& ray, const Spectrum& st, const Spectrum& albedo, float a, float b,
                   const Spectrum& le, const std::string& what, uint64_t seed) {
    PCG32 rng(seed, 17);
    auto u = [&] { return rng.next_float(); };
    Stats pass, scat, emit, tr;
    const int n = 400000;
    for (int i = 0; i < n; ++i) {
        const MediumEvent e = sample_distance(m, ray, kBeta, u);
        ASSERT_TRUE(e.weight.is_finite() && !e.weight.has_negative()) << what;
        pass.add(e.scattered ? Spectrum(0.f) : e.weight);
        // t relative to the medium's entry point a.
        scat.add(e.scattered ? e.weight * (1.f + (e.t - a)) : Spectrum(0.f));
        emit.add(e.emitted);
        tr.add(transmittance(m, ray, kBeta, u));
        if (e.scattered) {
            ASSERT_TRUE(e.t >= a && e.t < b) << what << " t=" << e.t;
        }
    }
    Spectrum t_l, single, emitted;
    const float L = b - a;
    for (int c = 0; c < 3; ++c) {
        const double s = st[c], T = std::exp(-s * L), ss = s * albedo[c];
        t_l[c] = float(T);
        // ∫₀^L σs e^{−σt t}(1 + t) dt = σs [(1 − T)/σt + (1 − T(1 + σt L))/σt²]
        single[c] = float(ss * ((1.0 - T) / s + (1.0 - T * (1.0 + s * L)) / (s * s)));
        emitted[c] = float(le[c] * (1.0 - T));
    }
    expect_unbiased(pass, t_l, what + ": pass weight");
    expect_unbiased(scat, single, what + ": single scattering");
    expect_unbiased(emit, emitted, what + ": emission");
    expect_unbiased(tr, t_l, what + ": transmittance");
}

TEST(Medium, HomogeneousDistanceSamplingIsUnbiased) {
    const Spectrum sa = kChromaticSt * (Spectrum(1.f) - kAlbedo), ss = kChromaticSt * kAlbedo;
    const Spectrum le(0.5f, 1.f, 2.f);
    const Medium m = homogeneous(sa, ss, le);
    // A direction of length 2: t runs over half the distance.
    check_segment(m, Ray{Point3f(0.f), Vec3f(0.f, 2.f, 0.f), 0.75f}, kChromaticSt * 2.f, kAlbedo, 0.f, 0.75f,
                  le, "homogeneous", 1);
    check_segment(m, Ray{Point3f(0.f), Vec3f(1.f, 0.f, 0.f), 0.2f}, kChromaticSt, kAlbedo, 0.f, 0.2f, le,
                  "homogeneous, thin", 2);
}

// Tracking only red (beta = (1, 0, 0)): red is sampled exactly, and green and blue stay unbiased
// through the MIS weight T_c / T_red.
TEST(Medium, ChannelChoiceFollowsTheThroughput) {
    const Medium m = homogeneous(kChromaticSt * 0.5f, kChromaticSt * 0.5f);
    PCG32 rng(4, 4);
    auto u = [&] { return rng.next_float(); };
    Ray r{Point3f(0.f), Vec3f(0.f, 0.f, 1.f), 1.f};
    Stats pass;
    for (int i = 0; i < 200000; ++i) {
        MediumEvent e = sample_distance(m, r, Spectrum(1.f, 0.f, 0.f), u);
        pass.add(e.scattered ? Spectrum(0.f) : e.weight);
    }
    EXPECT_NEAR(pass.mean(0), std::exp(-0.3), kZ * pass.se(0));
    EXPECT_NEAR(pass.mean(1), std::exp(-1.1), kZ * pass.se(1));
    EXPECT_NEAR(pass.mean(2), std::exp(-2.4), kZ * pass.se(2));
}

TEST(Medium, ConstantGridAgreesWithHomogeneous) {
    // Density 0.5 and σt (per density) = 2·kChromaticSt: the same σt as the homogeneous medium.
    for (Tracking tr : {Tracking::Ratio, Tracking::Delta}) {
        const std::string name = tr == Tracking::Ratio ? "grid (ratio)" : "grid (delta)";
        const Medium m = constant_grid(0.5f, kChromaticSt * 2.f, kAlbedo, Vec3f(-1.f), 2.f, tr);
        // Inside the box for the whole segment.
        check_segment(m, Ray{Point3f(-0.9f, 0.1f, 0.f), Vec3f(1.f, 0.f, 0.f), 1.5f}, kChromaticSt, kAlbedo, 0.f, 1.5f,
                      Spectrum(0.f), name, 3);
        // From outside: the ray enters the box at t = 1 and leaves it at t = 3 before tmax = 5.
        check_segment(m, Ray{Point3f(-2.f, 0.3f, 0.2f), Vec3f(1.f, 0.f, 0.f), 5.f}, kChromaticSt, kAlbedo, 1.f, 3.f,
                      Spectrum(0.f), name + " entering", 4);
        // Diagonally through several majorant blocks, with a non-unit direction.
        const Vec3f d = Vec3f(0.8f, 0.5f, -0.6f) * 1.5f;
        const float tmax = 1.1f;
        check_segment(m, Ray{Point3f(-0.8f, -0.6f, 0.7f), d, tmax}, kChromaticSt * length(d), kAlbedo, 0.f, tmax,
                      Spectrum(0.f), name + " diagonal", 5);
    }
}

TEST(Medium, GridEmissionAndGreyAlbedo) {
    GridMedium g = constant_grid(1.f, Spectrum(0.7f), kAlbedo, Vec3f(0.f), 1.f);
    g.le = Spectrum(1.f, 2.f, 3.f);
    check_segment(Medium(g), Ray{Point3f(0.1f, 0.5f, 0.5f), Vec3f(1.f, 0.f, 0.f), 0.8f}, Spectrum(0.7f), kAlbedo,
                  0.f, 0.8f, g.le, "grid, grey σt, emission", 6);
    // Grey σt: the pass weight is exactly 1, a collision's weight exactly the albedo.
    PCG32 rng(8, 8);
    auto u = [&] { return rng.next_float(); };
    for (int i = 0; i < 1000; ++i) {
        MediumEvent e = sample_distance(Medium(g), Ray{Point3f(0.1f, 0.5f, 0.5f), Vec3f(1.f, 0.f, 0.f), 0.8f}, kBeta, u);
        if (e.scattered) {
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(e.weight[c], kAlbedo[c], 1e-6f);
        } else {
            EXPECT_EQ(e.weight, Spectrum(1.f));
        }
    }
}

/// ∫ σt ds along the ray through a grid, by a fine midpoint rule on the density (double).
Spectrum optical_depth(const GridMedium& m, const Ray& ray, int steps = 200000) {
    double sum = 0.0;
    const double h = double(ray.tmax) / steps;
    for (int i = 0; i < steps; ++i) {
        const Point3f p = ray.o + ray.d * float((i + 0.5) * h);
        sum += m.grid->density(Vec3f(m.world_to_grid * Vec4f(p, 1.f)));
    }
    return m.sigma_t * float(sum * h * length(ray.d));
}

TEST(Medium, RatioAndDeltaTrackingMatchQuadratureOnSmoke) {
    GridMedium m;
    m.grid = std::make_shared<DensityGrid>(DensityGrid::smoke(48, 3));
    m.sigma_t = Spectrum(3.f, 5.f, 8.f);
    m.albedo = Spectrum(0.8f);
    m.world_to_grid = Transform::translate(Vec3f(-0.5f, 0.f, -0.5f)).inverse_matrix();
    const Ray rays[] = {{Point3f(-1.f, 0.3f, 0.05f), Vec3f(1.f, 0.05f, -0.02f), 2.f},
                        {Point3f(0.03f, -0.2f, 0.f), Vec3f(0.f, 1.f, 0.f), 1.5f},
                        {Point3f(-0.4f, 0.9f, -0.3f), normalize(Vec3f(0.6f, -0.7f, 0.4f)), 1.2f}};
    for (const Ray& ray : rays) {
        Spectrum expected = optical_depth(m, ray);
        for (int c = 0; c < 3; ++c) expected[c] = std::exp(-expected[c]);
        EXPECT_LT(expected.r, 0.98f) << "the ray should cross smoke";
        for (Tracking tr : {Tracking::Ratio, Tracking::Delta}) {
            m.tracking = tr;
            PCG32 rng(21, uint64_t(tr) + 1);
            auto u = [&] { return rng.next_float(); };
            Stats st;
            for (int i = 0; i < 200000; ++i) st.add(transmittance(Medium(m), ray, kBeta, u));
            expect_unbiased(st, expected, tr == Tracking::Ratio ? "ratio tracking" : "delta tracking");
        }
        // Distance sampling's pass weight estimates the same transmittance.
        PCG32 rng(22, 1);
        auto u = [&] { return rng.next_float(); };
        Stats pass;
        for (int i = 0; i < 200000; ++i) {
            MediumEvent e = sample_distance(Medium(m), ray, kBeta, u);
            pass.add(e.scattered ? Spectrum(0.f) : e.weight);
        }
        expect_unbiased(pass, expected, "delta tracking pass weight");
    }
}

TEST(Medium, MajorantsBoundTheDensity) {
    const DensityGrid g = DensityGrid::smoke(40, 9);  // 40 = 16 + 16 + 8: a partial last block
    PCG32 rng(2, 2);
    const float B = DensityGrid::kMajorantBlock;
    for (int k = 0; k < 200000; ++k) {
        const Vec3f p(rng.next_float(), rng.next_float(), rng.next_float());
        const float maj = g.majorant(int(p.x * 40 / B), int(p.y * 40 / B), int(p.z * 40 / B));
        ASSERT_LE(g.density(p), maj) << to_string(p);
    }
    EXPECT_EQ(g.coarse(0), 3);
    EXPECT_GT(g.max_value(), 0.5f);
    EXPECT_EQ(g.density(Vec3f(1.5f, 0.5f, 0.5f)), 0.f);
}
}  // namespace
}  // namespace pellucid::test
