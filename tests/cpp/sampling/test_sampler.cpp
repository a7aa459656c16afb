// The Sampler (sampling/sampler.h): independent = the old PCG32 stream; sobol = stratified (0,2)-nets
// per pixel, uniform across pixels, and faster-converging on smooth and discontinuous integrands.
// Fixed seeds throughout; the χ² tests use α = 0.01 (Šidák-corrected over the tests of one TEST).
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

#include "pellucid/sampling/sampler.h"
#include "support/chi2.h"

using namespace pellucid;

namespace {
/// A point set of 2^k points in [0,1)^2 is a (0,k,2)-net in base 2 iff every elementary interval
/// [i/2^a, (i+1)/2^a) × [j/2^b, (j+1)/2^b) with a + b = k holds exactly one point (Niederreiter
/// 1992, Def. 4.1). Returns the first shape (a) that fails, or -1.
int first_failing_shape(const std::vector<Vec2f>& pts, int k) {
    const int n = 1 << k;
    for (int a = 0; a <= k; ++a) {
        const int b = k - a;
        std::vector<int> count(size_t(n), 0);
        for (const Vec2f& p : pts) {
            int i = int(p.x * float(1 << a)), j = int(p.y * float(1 << b));
            if (i < 0 || j < 0 || i >= (1 << a) || j >= (1 << b)) return a;
            ++count[size_t(i) * size_t(1 << b) + size_t(j)];
        }
        for (int c : count)
            if (c != 1) return a;
    }
    return -1;
}

bool stratified_1d(const std::vector<float>& xs, int k) {
    std::vector<int> count(size_t(1) << k, 0);
    for (float x : xs) {
        if (!(x >= 0.f && x < 1.f)) return false;
        ++count[size_t(x * float(1 << k))];
    }
    for (int c : count)
        if (c != 1) return false;
    return true;
}

/// The 2D points of samples [first, first + 2^k) of one pixel at dimension `dim` (dim 0: the pixel
/// offset through get_pixel_2d).
std::vector<Vec2f> pixel_points_2d(SamplerType t, uint64_t pixel, uint64_t seed, int dim, int first, int k) {
    std::vector<Vec2f> pts;
    for (int s = first; s < first + (1 << k); ++s) {
        Sampler u(t, pixel, uint64_t(s), seed);
        if (dim == 0) {
            pts.push_back(u.get_pixel_2d());
        } else {
            u.set_dimension(dim);
            pts.push_back(u.get_2d());
        }
    }
    return pts;
}
}  // namespace

TEST(Sampler, IndependentIsThePcg32StreamOfTheSample) {
    // The pre-Sampler renderer: PCG32::for_sample, consumed in call order whatever set_dimension says.
    for (uint64_t pixel : {0ull, 5ull, 70000ull})
        for (uint64_t s : {0ull, 3ull, 1000ull}) {
            PCG32 rng = PCG32::for_sample(pixel, s, 9);
            Sampler u(SamplerType::Independent, pixel, s, 9);
            Vec2f a = u.get_pixel_2d(), b = rng.next_2d();
            EXPECT_EQ(a.x, b.x);
            EXPECT_EQ(a.y, b.y);
            u.set_dimension(30);
            EXPECT_EQ(u.get_1d(), rng.next_float());
            Vec2f c = u.get_2d(), d = rng.next_2d();
            EXPECT_EQ(c.x, d.x);
            EXPECT_EQ(c.y, d.y);
        }
}

TEST(Sampler, IndependentFromPartsIsTheSamplerAfterItsPixelOffset) {
    // What the path kernel does for a packet of samples: seed from PCG32's parts, draw the pixel
    // offset itself, then continue in Sampler::independent_after_pixel. Every later number equals
    // the sampler's own.
    for (uint64_t pixel : {0ull, 5ull, 70000ull})
        for (uint64_t s : {0ull, 3ull, 1000ull}) {
            const Sampler::PixelSeed px = Sampler::PixelSeed::of(SamplerType::Independent, pixel, 9);
            Sampler u(SamplerType::Independent, px, s);
            const Vec2f a = u.get_pixel_2d();
            const uint64_t inc = PCG32::increment_of(px.stream);
            uint64_t st = PCG32::seeded_state(PCG32::sample_init(px.stream, s), inc);
            EXPECT_EQ(PCG32::to_float(PCG32::output(st)), a.x);
            st = PCG32::step(st, inc);
            EXPECT_EQ(PCG32::to_float(PCG32::output(st)), a.y);
            st = PCG32::step(st, inc);
            Sampler v = Sampler::independent_after_pixel(PCG32::from_state(st, inc), px, s);
            EXPECT_EQ(v.dimension(), u.dimension());
            for (int k = 0; k < 8; ++k) EXPECT_EQ(v.get_1d(), u.get_1d());
            const Vec2f c = u.get_2d(), d = v.get_2d();
            EXPECT_EQ(c.x, d.x);
            EXPECT_EQ(c.y, d.y);
        }
}

TEST(Sampler, SobolDirectionNumbersMatchJoeKuo) {
    // m_k of Joe–Kuo dimensions 2, 3, 4 worked out by hand from the recurrence
    // m_k = 2a_1 m_{k-1} ⊕ … ⊕ 2^s m_{k-s} ⊕ m_{k-s} (0x80000000, 0xc0000000, 0x60000000, ... for dimension 3).
    const uint32_t m[3][5] = {{1, 3, 5, 15, 17}, {1, 3, 3, 9, 29}, {1, 3, 1, 5, 31}};
    for (int d = 0; d < 3; ++d)
        for (int k = 0; k < 5; ++k) EXPECT_EQ(sobol::kDirections.v[d + 1][k], m[d][k] << (31 - k)) << d << " " << k;
    EXPECT_EQ(sobol::sample_bits(1, 0), 0x80000000u);
    EXPECT_EQ(sobol::sample_bits(6, 0), 0x60000000u);  // van der Corput: 6 = 110b -> 0.011b
}

TEST(Sampler, ReverseBitsReversesBits) {
    // reverse_bits (GFNI or shift steps, whichever the build has) against bit-by-bit reversal.
    PCG32 rng(8, 9);
    for (int t = 0; t < 20000; ++t) {
        const uint32_t x = t < 64 ? (t < 32 ? 1u << t : ~(1u << (t - 32))) : rng.next_u32();
        uint32_t r = 0;
        for (int b = 0; b < 32; ++b) r |= ((x >> b) & 1u) << (31 - b);
        ASSERT_EQ(sobol::reverse_bits(x), r) << x;
    }
}

TEST(Sampler, FastSobolEqualsTheDefinition) {
    // sample_2d (no table, reversals cancelled), which the Sampler uses, against Burley's Listing 5
    // with the table.
    PCG32 rng(4, 5);
    for (int t = 0; t < 20000; ++t) {
        uint32_t index = t < 1000 ? uint32_t(t) : rng.next_u32();
        sobol::GroupSeeds g{rng.next_u32(), {rng.next_u32(), rng.next_u32()}};
        EXPECT_EQ(sobol::reverse_bits(sobol::dim1_reversed(index)), sobol::sample_bits(index, 1)) << index;
        uint32_t x0, x1;
        sobol::sample_2d(index, g, &x0, &x1);
        ASSERT_EQ(x0, sobol::shuffled_scrambled(index, 0, g)) << index;
        ASSERT_EQ(x1, sobol::shuffled_scrambled(index, 1, g)) << index;
    }
}

TEST(Sampler, NestedUniformScrambleIsOwenScrambling) {
    // Owen scrambling maps every dyadic interval [i/2^m, (i+1)/2^m) onto one dyadic interval of the
    // same size: the top m bits of the output depend only on the top m bits of the input.
    for (uint32_t seed : {0u, 1u, 0xdeadbeefu, 12345u})
        for (int m = 1; m <= 12; ++m)
            for (uint32_t hi = 0; hi < 64; ++hi) {
                uint32_t base = hi << (32 - m);  // wraps for m < 6: fine, still a prefix
                uint32_t top = sobol::nested_uniform_scramble(base, seed) >> (32 - m);
                for (uint32_t lo : {1u, 0x1234u, (1u << (32 - m)) - 1u})
                    ASSERT_EQ(sobol::nested_uniform_scramble(base | (lo & ((1u << (32 - m)) - 1u)), seed) >> (32 - m),
                              top)
                        << "seed " << seed << " m " << m;
            }
    // ... and it is a permutation of the 2^m intervals (checked for m = 10 exhaustively).
    std::vector<int> seen(1024, 0);
    for (uint32_t i = 0; i < 1024; ++i) ++seen[sobol::nested_uniform_scramble(i << 22, 77u) >> 22];
    for (int c : seen) EXPECT_EQ(c, 1);
}

TEST(Sampler, SobolPixelPrefixesAreElementaryIntervalNets) {
    // For several pixels, seeds and dimension pairs, samples [0, 2^k) and [2^k, 2^(k+1)) of a pixel
    // are (0,k,2)-nets: one point in every elementary interval of every shape 2^a × 2^(k−a)
    // (1×2^k, square, 2^k×1 and those between).
    for (uint64_t pixel : {0ull, 1ull, 4097ull, 123456ull})
        for (uint64_t seed : {0ull, 42ull})
            for (int dim : {0, 2, 4, 11, 60})
                for (int k : {1, 4, 7, 10})
                    for (int first : {0, 1 << k}) {
                        auto pts = pixel_points_2d(SamplerType::Sobol, pixel, seed, dim, first, k);
                        EXPECT_EQ(first_failing_shape(pts, k), -1)
                            << "pixel " << pixel << " seed " << seed << " dim " << dim << " k " << k << " first " << first;
                    }
}

TEST(Sampler, SobolOneDimensionalPrefixesAreStratified) {
    for (uint64_t pixel : {3ull, 999ull})
        for (int dim : {2, 5, 8, 63})
            for (int k : {3, 8}) {
                std::vector<float> xs;
                for (int s = 0; s < (1 << k); ++s) {
                    Sampler u(SamplerType::Sobol, pixel, uint64_t(s), 5);
                    u.set_dimension(dim);
                    xs.push_back(u.get_1d());
                }
                EXPECT_TRUE(stratified_1d(xs, k)) << "pixel " << pixel << " dim " << dim << " k " << k;
            }
}

TEST(Sampler, NetCheckRejectsIndependentPoints) {
    // The checks above can fail: 256 i.i.d. points are (almost surely) not a net, nor 1D-stratified.
    auto pts = pixel_points_2d(SamplerType::Independent, 7, 0, 2, 0, 8);
    EXPECT_NE(first_failing_shape(pts, 8), -1);
    std::vector<float> xs;
    for (const Vec2f& p : pts) xs.push_back(p.x);
    EXPECT_FALSE(stratified_1d(xs, 8));
}

TEST(Sampler, SobolPastTheSobolDimensionsIsThePcg32Stream) {
    Sampler u(SamplerType::Sobol, 12, 3, 1);
    PCG32 rng = PCG32::for_sample(12, 3, 1);
    u.set_dimension(Sampler::kMaxSobolDims - 1);
    Vec2f a = u.get_2d(), b = rng.next_2d();  // straddles the limit: PCG32
    EXPECT_EQ(a.x, b.x);
    EXPECT_EQ(a.y, b.y);
    EXPECT_EQ(u.get_1d(), rng.next_float());
    EXPECT_EQ(u.dimension(), Sampler::kMaxSobolDims + 2);
}

TEST(Sampler, SobolIsUniformAcrossPixels) {
    // Sample s of many pixels (different shuffles and scrambles) is uniform: χ² over a 16×16 grid
    // (2D) and 64 bins (1D), for sample indices 0 and 5 and two dimensions; α = 0.01 Šidák-corrected
    // over the 8 tests.
    const int n_pixels = 100000, res = 16;
    const double alpha = test::sidak_alpha(0.01, 8);
    for (int s : {0, 5})
        for (int dim : {0, 9}) {
            std::vector<double> obs2(res * res, 0.0), obs1(64, 0.0);
            for (int p = 0; p < n_pixels; ++p) {
                Sampler u(SamplerType::Sobol, uint64_t(p), uint64_t(s), 3);
                Vec2f v;
                if (dim == 0) {
                    v = u.get_pixel_2d();
                } else {
                    u.set_dimension(dim);
                    v = u.get_2d();
                }
                obs2[size_t(int(v.x * res) * res + int(v.y * res))] += 1;
                u.set_dimension(dim + 20);
                obs1[size_t(u.get_1d() * 64.f)] += 1;
            }
            auto r2 = test::chi2_test(obs2, std::vector<double>(obs2.size(), double(n_pixels) / (res * res)));
            auto r1 = test::chi2_test(obs1, std::vector<double>(obs1.size(), double(n_pixels) / 64));
            EXPECT_GT(r2.p_value, alpha) << "2D s=" << s << " dim=" << dim << ": " << r2.message;
            EXPECT_GT(r1.p_value, alpha) << "1D s=" << s << " dim=" << dim << ": " << r1.message;
        }
}

namespace {
/// RMSE over `pixels` pixels of the N-sample estimate of ∫ f over [0,1)^2 (sampler dims 4, 5).
double rmse(SamplerType t, const std::function<double(Vec2f)>& f, double exact, int n, int pixels) {
    double se = 0;
    for (int p = 0; p < pixels; ++p) {
        double sum = 0;
        for (int s = 0; s < n; ++s) {
            Sampler u(t, uint64_t(p), uint64_t(s), 11);
            u.set_dimension(4);
            sum += f(u.get_2d());
        }
        se += std::pow(sum / n - exact, 2);
    }
    return std::sqrt(se / pixels);
}

/// Least-squares slope of log RMSE against log N at N = 16, 64, 256.
double convergence_slope(SamplerType t, const std::function<double(Vec2f)>& f, double exact, double* rmse256) {
    const int ns[3] = {16, 64, 256};
    double lx[3], ly[3];
    for (int i = 0; i < 3; ++i) {
        lx[i] = std::log(double(ns[i]));
        ly[i] = std::log(rmse(t, f, exact, ns[i], 2048));
    }
    *rmse256 = std::exp(ly[2]);
    double mx = (lx[0] + lx[1] + lx[2]) / 3, my = (ly[0] + ly[1] + ly[2]) / 3, sxy = 0, sxx = 0;
    for (int i = 0; i < 3; ++i) {
        sxy += (lx[i] - mx) * (ly[i] - my);
        sxx += (lx[i] - mx) * (lx[i] - mx);
    }
    return sxy / sxx;
}
}  // namespace

TEST(Sampler, SobolConvergesFasterThanIndependent) {
    // RMSE over 2048 pixels at N = 16, 64, 256. Independent sampling gives slope −1/2; Owen-scrambled
    // nets give about −3/2 on smooth integrands and −3/4 on a disk indicator (Owen 1997; Burley 2020
    // Fig. 10). With 2048 pixels each RMSE is known to about 1/sqrt(2·2048) ≈ 1.6 %, i.e. the slope
    // to about ±0.02, so the margins below (0.4 and 0.15 steeper than −1/2) are far outside noise.
    const double s = 0.15;
    auto gauss = [s](Vec2f v) {
        return std::exp(-(std::pow(v.x - 0.5, 2) + std::pow(v.y - 0.4, 2)) / (2 * s * s));
    };
    auto erf_1d = [s](double c) {  // ∫_0^1 exp(−(x−c)²/2s²) dx
        return s * std::sqrt(M_PI / 2) * (std::erf((1 - c) / (s * std::sqrt(2.0))) + std::erf(c / (s * std::sqrt(2.0))));
    };
    const double gauss_exact = erf_1d(0.5) * erf_1d(0.4);
    const double r = 0.35;
    auto disk = [r](Vec2f v) { return std::pow(v.x - 0.5, 2) + std::pow(v.y - 0.5, 2) < r * r ? 1.0 : 0.0; };
    const double disk_exact = M_PI * r * r;

    double ri, rs;
    double si = convergence_slope(SamplerType::Independent, gauss, gauss_exact, &ri);
    double ss = convergence_slope(SamplerType::Sobol, gauss, gauss_exact, &rs);
    EXPECT_NEAR(si, -0.5, 0.1) << "independent, Gaussian bump";
    EXPECT_LT(ss, -0.5 - 0.4) << "sobol, Gaussian bump (RMSE at 256: " << rs << " vs " << ri << ")";
    double di, ds;
    double sdi = convergence_slope(SamplerType::Independent, disk, disk_exact, &di);
    double sds = convergence_slope(SamplerType::Sobol, disk, disk_exact, &ds);
    EXPECT_NEAR(sdi, -0.5, 0.1) << "independent, disk";
    EXPECT_LT(sds, -0.5 - 0.15) << "sobol, disk (RMSE at 256: " << ds << " vs " << di << ")";
    std::printf("[ slopes ] Gaussian: independent %.3f sobol %.3f (RMSE@256 %.3g / %.3g); disk: independent %.3f "
                "sobol %.3f (RMSE@256 %.3g / %.3g)\n",
                si, ss, ri, rs, sdi, sds, di, ds);
}
