// The Gaussian pixel filter's two profiles (image/filter.h): values at known points, the shifted
// profile against Mitsuba 3's, continuity at the radius, and filter sampling from the shifted
// profile (χ² against the profile, α = 0.01 over the four histograms; monotone in u), and the Mitsuba
// importer's choice of it; the film's splat weights (eval_filter_taps16) against the profile on a
// dense grid, the independence of their four rows, and their bits against the recurrence written
// out one row at a time.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <variant>
#include <vector>

#include "pellucid/bxdf/microfacet.h"
#include "pellucid/image/filter.h"
#include "pellucid/sampling/rng.h"
#include "pellucid/simd/packet.h"
#include "pellucid/scene/mitsuba_xml.h"
#include "support/chi2.h"
#include "support/scene_util.h"

using namespace pellucid;

TEST(GaussianFilter, ProfilesAtKnownPoints) {
    // With σ the standard deviation and r = 4σ: truncated g(x) = exp(−x²/2σ²) for |x| < r; shifted
    // g(x) − g(r), g(r) = e⁻⁸.
    const double e8 = std::exp(-8.0);
    for (float s : {0.5f, 1.3f}) {
        const GaussianFilter t(s), sh(s, true);
        EXPECT_FLOAT_EQ(t.radius_px(), 4.f * s);
        EXPECT_FLOAT_EQ(sh.radius_px(), 4.f * s);
        for (double k : {0.0, 0.5, 1.0, 2.0, 3.0, 3.9}) {  // x = kσ
            const float x = float(k * s);
            const double g = std::exp(-0.5 * k * k);
            EXPECT_NEAR(t.eval(x), g, 2e-7 + 1e-6 * g) << "σ=" << s << " x=" << x;
            EXPECT_NEAR(sh.eval(-x), g - e8, 2e-7 + 1e-6 * g) << "σ=" << s << " x=" << -x;
        }
        // At the radius: the truncated profile steps down from e⁻⁸, the shifted one reaches 0
        // continuously; beyond it both are 0.
        const float just_inside = 4.f * s * (1.f - 1e-4f);
        EXPECT_NEAR(t.eval(just_inside), e8, 1e-6);
        EXPECT_LT(sh.eval(just_inside), 1e-6f);
        EXPECT_GE(sh.eval(just_inside), 0.f);
        EXPECT_EQ(t.eval(4.f * s), 0.f);
        EXPECT_EQ(sh.eval(4.f * s), 0.f);
        EXPECT_EQ(sh.eval(4.f * s * 1.01f), 0.f);
    }
}

TEST(GaussianFilter, ShiftedProfileIsMitsubas) {
    // Mitsuba 3.9.1's `gaussian` rfilter (σ = 0.5), ReconstructionFilter::eval in llvm_ad_rgb, read
    // with the Mitsuba peer at these x. Its CPU variants evaluate exp(−x²/2σ²) − exp(−r²/2σ²) as a
    // degree-9 minimax polynomial, within 4.2e-4 of the exact profile (relative: 0.05 % to 2σ,
    // 0.15 % to 3σ, 2 % to 3.8σ). The truncated profile is 88 % above it at 3.8σ, and fails.
    const float xs[] = {0.f, 0.5f, 1.f, 1.5f, 1.9f};
    const double mitsuba[] = {0.999247133731842, 0.606423020362854, 0.13496048748493195, 0.010758209973573685,
                              0.0003878818533848971};
    const double rel[] = {5e-4, 5e-4, 5e-4, 1.5e-3, 0.025};
    const GaussianFilter shifted(0.5f, true), truncated(0.5f);
    for (int i = 0; i < 5; ++i) {
        EXPECT_NEAR(shifted.eval(xs[i]), mitsuba[i], rel[i] * mitsuba[i]) << "x=" << xs[i];
    }
    EXPECT_GT(std::fabs(truncated.eval(1.9f) - mitsuba[4]), 0.5 * mitsuba[4]);
}

TEST(GaussianFilter, SamplingFollowsTheProfile) {
    // Offsets from sample_1d, binned over [−r, r], against the normalised profile integrated per bin
    // (for both profiles). The shifted profile is solved by Newton steps; the truncated one is the
    // normal inverse CDF. Inverse CDFs are monotone in u (what keeps Sobol points stratified).
    constexpr int kSamples = 400000, n = 64;
    const double alpha = 0.01 / 4.0;  // Bonferroni over the four histograms
    int which = 0;
    for (float s : {0.5f, 1.2f})
        for (bool shift : {false, true}) {
            const GaussianFilter f(s, shift);
            const float r = f.radius_px();
            std::vector<double> obs(n, 0.0), expct(n, 0.0);
            PCG32 rng(11 + which++, 3);
            for (int i = 0; i < kSamples; ++i) {
                const float x = f.sample_1d(rng.next_float());
                ASSERT_LE(std::fabs(x), r);
                obs[std::min(n - 1, int((x + r) / (2 * r) * n))] += 1;
            }
            double total = 0;
            for (int i = 0; i < n; ++i) {
                const double x0 = -r + 2.0 * r * i / n, x1 = x0 + 2.0 * r / n;
                double m = 0;
                for (int k = 0; k < 64; ++k) m += f.eval(float(x0 + (k + 0.5) * (x1 - x0) / 64));
                expct[i] = m * (x1 - x0) / 64;
                total += expct[i];
            }
            for (double& e : expct) e *= kSamples / total;
            const auto res = test::chi2_test(obs, expct);
            EXPECT_GT(res.p_value, alpha) << f.to_string() << " " << res.message;
            float prev = -r;
            for (int i = 0; i <= 1000; ++i) {
                const float x = f.sample_1d(std::min(float(i) / 1000.f, 0.99999994f));
                EXPECT_GE(x, prev) << f.to_string() << " u=" << i / 1000.0;
                prev = x;
            }
        }
}

TEST(GaussianFilter, SamplingCanFail) {
    // The χ² above has teeth: truncated-profile samples judged against the shifted profile with
    // σ = 0.5 (their only difference is the tail beyond about 3σ) fail it.
    constexpr int kSamples = 400000, n = 64;
    const GaussianFilter drawn(0.5f), judged(0.5f, true);
    const float r = judged.radius_px();
    std::vector<double> obs(n, 0.0), expct(n, 0.0);
    PCG32 rng(5, 9);
    for (int i = 0; i < kSamples; ++i)
        obs[std::min(n - 1, int((drawn.sample_1d(rng.next_float()) + r) / (2 * r) * n))] += 1;
    double total = 0;
    for (int i = 0; i < n; ++i) {
        const double x0 = -r + 2.0 * r * i / n, x1 = x0 + 2.0 * r / n;
        for (int k = 0; k < 64; ++k) expct[i] += judged.eval(float(x0 + (k + 0.5) * (x1 - x0) / 64)) * (x1 - x0) / 64;
        total += expct[i];
    }
    for (double& e : expct) e *= kSamples / total;
    EXPECT_LT(test::chi2_test(obs, expct).p_value, 0.01 / 4.0);
}

TEST(GaussianFilter, MitsubaImportSplatsWithTheShiftedProfile) {
    // An imported hdrfilm splats (Mitsuba's ImageBlock) with Mitsuba's shifted Gaussian, given or by
    // default; our own scenes keep the truncated profile and filter sampling.
    auto built = [](const std::string& film) {
        const std::string xml = R"(<scene version="3.0.0"><sensor type="perspective">)" + film +
                                R"(</sensor><shape type="sphere"><bsdf type="diffuse"/></shape></scene>)";
        return load_desc(parse_mitsuba_xml(xml, "test.xml", ".", false));
    };
    for (const char* film :
         {R"(<film type="hdrfilm"><rfilter type="gaussian"><float name="stddev" value="0.7"/></rfilter></film>)",
          R"(<film type="hdrfilm"/>)"}) {
        auto scene = built(film);
        const auto* g = std::get_if<GaussianFilter>(&scene->filter);
        ASSERT_NE(g, nullptr) << film;
        EXPECT_TRUE(g->shift) << film;
        EXPECT_FLOAT_EQ(g->stddev, std::string(film).find("0.7") != std::string::npos ? 0.7f : 0.5f);
        EXPECT_TRUE(scene->film_splatting) << film;
    }
    auto box = built(R"(<film type="hdrfilm"><rfilter type="box"/></film>)");
    EXPECT_TRUE(std::holds_alternative<BoxFilter>(box->filter));
    EXPECT_TRUE(box->film_splatting);
    auto own = test::scene_from(R"({"shapes": [{"type": "sphere"}]})");
    const auto* g = std::get_if<GaussianFilter>(&own->filter);
    ASSERT_NE(g, nullptr);
    EXPECT_FALSE(g->shift);
    EXPECT_FALSE(own->film_splatting);
}

// The film's Gaussian splat weights (eval_filter_taps16: two float exponentials per row and a
// recurrence outwards from the middle tap) against the profile in double precision at the
// same float abscissa, over 2^16 sample offsets per pixel and every tap of the row: the error,
// relative to the unshifted Gaussian there, is at most 1.5e-6 up to σ = 1.2 (measured: 4.8e-7 at
// σ = 0.5, 1.3e-6 at σ = 1.2) and 6e-6 at σ = 4 (measured 5.0e-6; 16 steps each way). A
// recurrence started at the row’s end instead of its middle gives about 4e-6 at σ = 1.2 and fails.
TEST(GaussianFilter, SplatWeightsOnADenseGrid) {
    struct Case {
        float stddev;
        double bound;
    };
    for (const Case& c : {Case{0.3f, 1.5e-6}, Case{0.5f, 1.5e-6}, Case{1.2f, 1.5e-6}, Case{4.f, 6e-6}})
        for (bool shift : {false, true}) {
            const GaussianFilter g(c.stddev, shift);
            const Filter f(g);
            const int m = int(std::ceil(g.radius_px() - 0.5f)), n = 2 * m + 1;
            const double k = 1.0 / (2.0 * double(c.stddev) * c.stddev), bias = shift ? std::exp(-8.0) : 0.0;
            double worst = 0.0;
            for (int s = 0; s < (1 << 16); ++s) {
                const float x0 = float(-m) + 0.5f - float(s) / 65536.f;
                float w[kMaxFilterTaps];
                eval_filter_taps(f, x0, n, w);
                for (int i = 0; i < n; ++i) {
                    const float x = x0 + float(i);
                    const double gx = std::exp(-double(x) * x * k);
                    const double ref = std::fabs(x) < g.radius_px() ? std::max(0.0, gx - bias) : 0.0;
                    worst = std::max(worst, std::fabs(double(w[i]) - ref) / gx);
                }
            }
            EXPECT_LE(worst, c.bound) << to_string(f);
            EXPECT_GT(worst, 0.0) << to_string(f);  // float weights: never exact everywhere
        }
}

// The sixteen rows of one eval_filter_taps16 call are independent: each equals, bit for bit, the
// row evaluated alone (the film evaluates a pixel's waiting sample again, beside its partner and
// other pairs, and must get the weights it splatted it with).
TEST(GaussianFilter, SplatWeightRowsAreIndependent) {
    PCG32 rng(11, 5);
    for (const Filter& f : {Filter(GaussianFilter(0.5f, true)), Filter(GaussianFilter(1.2f)), Filter(TentFilter{1.5f})}) {
        const int n = 2 * int(std::ceil(filter_radius(f) - 0.5f)) + 1;
        for (int trial = 0; trial < 1000; ++trial) {
            float x0[16];
            for (float& v : x0) v = float(-n / 2) + 0.5f - rng.next_float();
            float rows[kMaxFilterTaps][16], alone[kMaxFilterTaps];
            eval_filter_taps16(f, x0, n, rows);
            for (int r = 0; r < 16; ++r) {
                eval_filter_taps(f, x0[r], n, alone);
                for (int i = 0; i < n; ++i) ASSERT_EQ(std::memcmp(&rows[i][r], &alone[i], 4), 0) << to_string(f) << " row " << r;
            }
        }
    }
}

// The film's Gaussian taps are, bit for bit, the recurrence of image/filter.h written out plainly,
// one row at a time in scalar floats: from the middle tap c, e(xc) = exp(−xc² k) and the ratio
// exp(−(2xc + 1)k) (film.cpp's exponential, which performs the operations of
// microfacet_detail::exp_t, the reference here), then e *= ratio, ratio *= q rightwards, and leftwards
// from ratio q / exp(−(2xc + 1)k); each tap is max(0, e − bias) inside the radius and 0 outside. The
// film takes fixed-size code for 3, 5 and 7 taps and a loop for the others, so each row length from
// 1 to 11 is checked, on offsets where the film puts them and anywhere in ±6 pixels, with every
// instruction-set variant of eval_filter_taps16 this machine runs (all must give these bits).
TEST(GaussianFilter, SplatWeightsAreTheRecurrence) {
    auto exp_ref = [](float a) { return microfacet_detail::exp_t<float>(a); };
    const std::vector<FilterTapsVariant> variants = filter_taps_variants();
    PCG32 rng(23, 9);
    for (const GaussianFilter& g : {GaussianFilter(0.5f, true), GaussianFilter(0.5f), GaussianFilter(1.2f, true),
                                    GaussianFilter(0.3f)}) {
        const Filter f(g);
        for (int n = 1; n <= 11; ++n)
            for (int trial = 0; trial < 100; ++trial) {
                float x0[16];
                for (float& v : x0)
                    v = trial % 2 == 0 ? float(-(n / 2)) + 0.5f - rng.next_float() : 12.f * rng.next_float() - 6.f;
                float rows[kMaxFilterTaps][16];
                const FilterTapsVariant variant = variants[size_t(trial) % variants.size()];
                eval_filter_taps16(f, x0, n, rows, variant);
                for (int r = 0; r < 16; ++r) {
                    float ref[kMaxFilterTaps];
                    auto tap = [&](int i, float e) {
                        const float xi = x0[r] + float(i);
                        const float v = std::max(0.f, e - g.m_bias);
                        ref[i] = std::fabs(xi) < g.m_radius ? v : 0.f;
                    };
                    const int c = n / 2;
                    const float xc = x0[r] + float(c);
                    const float ec = exp_ref(-xc * xc * g.m_k), r0 = exp_ref(-(2.f * xc + 1.f) * g.m_k);
                    float e = ec, ratio = r0;
                    for (int i = c; i < n; ++i) {
                        tap(i, e);
                        e *= ratio;
                        ratio *= g.m_q;
                    }
                    ratio = g.m_q / r0;
                    e = ec * ratio;
                    ratio *= g.m_q;
                    for (int i = c - 1; i >= 0; --i) {
                        tap(i, e);
                        e *= ratio;
                        ratio *= g.m_q;
                    }
                    for (int i = 0; i < n; ++i)
                        ASSERT_EQ(std::memcmp(&rows[i][r], &ref[i], 4), 0)
                            << to_string(f) << " variant " << int(variant) << " n " << n << " row " << r << " tap " << i << ": " << rows[i][r] << " vs " << ref[i];
                }
            }
    }
}
