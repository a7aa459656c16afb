// The splatting film (image/film.h): it reduces to filter sampling for a 1-pixel box, its variance
// estimate is calibrated against the spread of independent renders, it estimates the same filtered
// image as filter sampling (per-pixel z-test, two-sided α = 0.01 Šidák-corrected over the pixel
// channels, ≥ 99.75 % must pass, as in test_analytic_scenes.cpp), and tile colouring keeps images
// bit-identical across thread counts.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>

#include "pellucid/api.h"
#include "pellucid/image/film.h"
#include "support/chi2.h"
#include "support/scene_util.h"

using namespace pellucid;
using pellucid::test::scene_from;
using pellucid::test::z_two_sided;

namespace {
// A diffuse floor and a sphere under a small area light: edges, soft shadows and penumbrae, so the
// filter matters and pixels differ.
std::string scene_json(const std::string& film_extra, int spp, int seed, int w = 24, int h = 18) {
    return std::string(R"({"camera": {"type": "perspective", "fov": 45,
        "to_world": [{"look_at": {"origin": [0, 1.5, 4], "target": [0, 0, 0], "up": [0, 1, 0]}}]},
        "film": {"width": )") + std::to_string(w) + R"(, "height": )" + std::to_string(h) + film_extra +
           R"(}, "sampler": {"sample_count": )" + std::to_string(spp) + R"(, "seed": )" + std::to_string(seed) +
           R"(}, "integrator": {"type": "path", "max_depth": 3},
        "materials": {"white": {"type": "lambertian", "reflectance": 0.7},
                      "red": {"type": "lambertian", "reflectance": [0.8, 0.1, 0.1]}},
        "shapes": [{"type": "sphere", "radius": 0.8, "material": "red"},
                   {"type": "rectangle", "material": "white",
                    "to_world": [{"scale": 3}, {"rotate": {"axis": [1, 0, 0], "angle": -90}}, {"translate": [0, -0.8, 0]}]},
                   {"type": "rectangle", "to_world": [{"scale": 0.4}, {"rotate": {"axis": [1, 0, 0], "angle": 90}}, {"translate": [0.5, 2.5, 0.5]}],
                    "emitter": {"type": "area", "radiance": 10}}]})";
}
const char* kSplatGaussian = R"(, "filter": {"type": "gaussian", "stddev": 0.5}, "reconstruction": "splatting")";
}  // namespace

TEST(FilmSplat, OnePixelBoxEqualsFilterSampling) {
    // A box of radius ½ gives every sample weight 1 in its own pixel only: the ratio estimator is the
    // sample mean and the delta-method variance with the n_eff/(n_eff − 1) factor is Welford's.
    Film a(3, 2), b(3, 2, Filter(BoxFilter{0.5f}));
    EXPECT_EQ(b.splat_margin(), 0);
    PCG32 rng = PCG32::for_sample(7, 0, 3);
    for (int i = 0; i < 200; ++i) {
        int x = i % 3, y = (i / 3) % 2;
        Spectrum L(rng.next_float() * 4.f, rng.next_float(), 0.25f);
        a.add_sample(x, y, L);
        b.splat(x, y, float(x) + rng.next_float(), float(y) + rng.next_float(), L);
    }
    Image ma = a.mean(), mb = b.mean(), va = a.variance(), vb = b.variance();
    for (size_t i = 0; i < ma.data.size(); ++i) {
        EXPECT_NEAR(ma.data[i], mb.data[i], 1e-6 * (1 + std::fabs(ma.data[i])));
        EXPECT_NEAR(va.data[i], vb.data[i], 1e-5 * va.data[i] + 1e-12);
    }
    EXPECT_EQ(a.samples(1, 1), b.samples(1, 1));
}

TEST(FilmSplat, SplatsReachTheFilterRadiusOnly) {
    // One sample at the centre of pixel (5, 5) with a Gaussian of σ = 0.5 (radius 2): pixels whose
    // centres are within 2 px get weight exp(−d²/2σ²)-proportional shares of the same value; the
    // others stay empty.
    Film f(11, 11, Filter(GaussianFilter(0.5f)));
    EXPECT_EQ(f.splat_margin(), 2);
    f.splat(5, 5, 5.5f, 5.5f, Spectrum(2.f));
    Image m = f.mean();
    for (int y = 0; y < 11; ++y)
        for (int x = 0; x < 11; ++x) {
            float v = m.data[3 * (y * 11 + x)];
            bool inside = std::abs(x - 5) < 2 && std::abs(y - 5) < 2;  // |Δ| = 2 is exactly at the radius
            EXPECT_FLOAT_EQ(v, inside ? 2.f : 0.f) << x << "," << y;
        }
    EXPECT_EQ(f.samples(5, 5), 1u);
    EXPECT_EQ(f.samples(4, 5), 0u);
}

TEST(FilmSplat, MatchesTheFilteredImageOfAnEdge) {
    // L(x, y) = 1 right of the slanted edge x = 5.3 + 0.3 y, else 0.2, on a 12×10 film, splatted with
    // 4096 stratified samples per pixel (σ = 0.6 Gaussian, radius 2.4). Each pixel must equal
    // ∫ f(c − p) L(p) dp / ∫ f(c − p) dp over the film (splats stop at its border, as in Mitsuba 3
    // without sample_border), integrated on a 1/64-pixel grid, within a per-pixel z-test using the
    // film's own variance plus the quadrature's error (α = 0.01, Šidák over the pixels). A filter
    // 16 % narrower (σ·√0.7) fails it.
    const int W = 12, H = 10, n = 64;
    const GaussianFilter g(0.6f);
    auto L = [](float x, float y) { return x > 5.3f + 0.3f * y ? 1.f : 0.2f; };
    Film film(W, H, Filter(g));
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i) {
                    PCG32 rng = PCG32::for_sample(uint64_t(y * W + x), uint64_t(j * n + i), 9);
                    float fx = float(x) + (float(i) + rng.next_float()) / n, fy = float(y) + (float(j) + rng.next_float()) / n;
                    film.splat(x, y, fx, fy, Spectrum(L(fx, fy)));
                }
    Image m = film.mean(), v = film.variance();
    const double z_max = z_two_sided(test::sidak_alpha(0.01, W * H));
    const int q = 64;  // quadrature points per pixel and axis
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            double num = 0, den = 0;
            for (int b = 0; b < H * q; ++b)
                for (int a = 0; a < W * q; ++a) {
                    float px = (a + 0.5f) / q, py = (b + 0.5f) / q;
                    // The filter written out here, independent of GaussianFilter::eval.
                    double dx = x + 0.5 - px, dy = y + 0.5 - py, r = 4 * 0.6;
                    double w = (std::fabs(dx) < r && std::fabs(dy) < r) ? std::exp(-(dx * dx + dy * dy) / (2 * 0.36)) : 0.0;
                    num += w * L(px, py);
                    den += w;
                }
            double expected = num / den, got = m.data[3 * (y * W + x)];
            double sd = std::sqrt(double(v.data[3 * (y * W + x)]) + 1e-10);
            EXPECT_LT(std::fabs(got - expected), z_max * sd + 2e-4) << "pixel " << x << "," << y << " got " << got
                                                                   << " expected " << expected << " sd " << sd;
        }
}

TEST(FilmSplat, VarianceMatchesSpreadOfIndependentRenders) {
    // K renders with different seeds: per pixel, the spread of the K estimates is the true variance
    // (unbiased sample variance); the film's delta-method estimate, averaged over the K renders, is
    // compared with it. Summed over all pixel channels, the empirical variance has a relative
    // standard error of about √(2/(K−1))/√(pixels) ≈ 1.5 % here (more, as neighbours correlate).
    // The estimate is conservative by design: it treats the samples as i.i.d. over the splat's
    // footprint, but every pixel contributes exactly spp of them (stratification by pixel), so the
    // spread of the per-pixel means around R is counted as noise. The film documents that; the
    // test holds it to "never below the truth by more than noise (−6 %), at most 30 % above".
    constexpr int K = 96;
    const int spp = 8;
    std::vector<double> sum, sum2, pred;
    for (int k = 0; k < K; ++k) {
        RenderResult r = render(*scene_from(scene_json(kSplatGaussian, spp, 100 + k, 16, 12)), RenderOptions{});
        if (sum.empty()) sum.assign(r.image.data.size(), 0.0), sum2 = sum, pred = sum;
        for (size_t i = 0; i < sum.size(); ++i) {
            sum[i] += r.image.data[i];
            sum2[i] += double(r.image.data[i]) * r.image.data[i];
            pred[i] += r.variance.data[i];
        }
    }
    double emp_total = 0, pred_total = 0;
    for (size_t i = 0; i < sum.size(); ++i) {
        double m = sum[i] / K;
        emp_total += (sum2[i] - K * m * m) / (K - 1);
        pred_total += pred[i] / K;
    }
    ASSERT_GT(emp_total, 0.0);
    const double ratio = pred_total / emp_total;
    EXPECT_GT(ratio, 0.94);
    EXPECT_LT(ratio, 1.30) << "predicted " << pred_total << " empirical " << emp_total;
}

TEST(FilmSplat, SameImageAsFilterSampling) {
    // Both reconstructions estimate the same filtered image; splatting's ratio estimator is
    // consistent (bias O(1/n)), negligible at 256 spp against the per-pixel noise.
    RenderResult fs = render(*scene_from(scene_json(R"(, "filter": {"type": "gaussian", "stddev": 0.5})", 256, 1)),
                             RenderOptions{});
    RenderResult sp = render(*scene_from(scene_json(kSplatGaussian, 256, 2)), RenderOptions{});
    size_t n = fs.image.data.size();
    double z_max = z_two_sided(test::sidak_alpha(0.01, int(n)));
    int fails = 0, skipped = 0;
    double rel_fs = 0, rel_sp = 0;
    for (size_t i = 0; i < n; ++i) {
        double s2 = fs.variance.data[i] + sp.variance.data[i] + 1e-12;
        if (fs.image.data[i] == sp.image.data[i]) continue;  // e.g. both 0 on the background
        if (fs.variance.data[i] == 0.f || sp.variance.data[i] == 0.f) {
            // A zero sample variance says nothing of the true one: filter sampling sees a dim edge
            // pixel's rare bright paths with probability < 1 per sample (and often none at all),
            // while splatting also collects them from the neighbours. Such pixels must be dim.
            ++skipped;
            EXPECT_LT(std::max(fs.image.data[i], sp.image.data[i]), 2e-3f) << "pixel channel " << i;
            continue;
        }
        if (std::fabs(fs.image.data[i] - sp.image.data[i]) / std::sqrt(s2) > z_max) ++fails;
        rel_fs += fs.variance.data[i];
        rel_sp += sp.variance.data[i];
    }
    EXPECT_LE(fails, int(0.0025 * double(n)));
    EXPECT_LT(skipped, int(0.1 * double(n)));  // a sanity bound: the scene is mostly lit or black
    // And the point of splatting: lower per-pixel variance at equal spp.
    EXPECT_LT(rel_sp, 0.6 * rel_fs) << "splatting variance " << rel_sp << " vs filter sampling " << rel_fs;
}

TEST(FilmSplat, BitIdenticalAcrossThreadCounts) {
    // A wide Gaussian (σ = 3, radius 12 px) needs 3×3 tile colours; σ = 0.5 needs 2×2.
    for (const char* filter : {kSplatGaussian,
                               R"(, "filter": {"type": "gaussian", "stddev": 3}, "reconstruction": "splatting")"}) {
        auto scene = scene_from(scene_json(filter, 2, 5, 70, 40));
        RenderOptions o;
        o.threads = 1;
        RenderResult a = render(*scene, o);
        o.threads = 2;
        RenderResult b = render(*scene, o);
        ASSERT_EQ(a.image.data.size(), b.image.data.size());
        EXPECT_EQ(0, std::memcmp(a.image.data.data(), b.image.data.data(), a.image.data.size() * sizeof(float)))
            << filter;
        EXPECT_EQ(0, std::memcmp(a.variance.data.data(), b.variance.data.data(), a.variance.data.size() * sizeof(float)))
            << filter;
    }
}

// A row of splat weights (eval_filter_taps, which the Gaussian computes with two exponentials and a
// recurrence) equals the filter's profile, including the cut at the radius. The reference is the
// profile in double precision at the same float abscissa; the bound, 4e-6 relative (+1e-9 absolute),
// covers float exp's error of about |argument|·2^-24 (the argument reaches (2·4σ+1)/(2σ²) in the
// ratio term) compounded over the row's steps, and is far below anything a wrong recurrence gives.
TEST(FilmSplat, FilterTapsEqualTheFilterProfile) {
    const Filter filters[] = {GaussianFilter(0.5f), GaussianFilter(0.3f), GaussianFilter(1.2f), TentFilter{1.5f},
                              BoxFilter{0.5f}};
    for (const Filter& f : filters) {
        const int m = int(std::ceil(filter_radius(f) - 0.5f)), n = 2 * m + 1;
        for (int s = 0; s < 200; ++s) {
            const float frac = float(s) / 200.f;  // the sample's offset within its pixel
            const float x0 = float(-m) + 0.5f - frac;
            float w[64];
            eval_filter_taps(f, x0, n, w);
            for (int i = 0; i < n; ++i) {
                const float x = x0 + float(i);
                double ref = eval_filter(f, x);  // box, tent: exact in float
                if (const auto* g = std::get_if<GaussianFilter>(&f))
                    ref = std::fabs(x) < 4.f * g->stddev ? std::exp(-double(x) * x / (2.0 * g->stddev * g->stddev)) : 0.0;
                EXPECT_NEAR(w[i], ref, 4e-6 * ref + 1e-9) << to_string(f) << " x=" << x;
            }
        }
    }
}
