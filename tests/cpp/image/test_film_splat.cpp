// The splatting film (image/film.h): a 1-pixel box is filter sampling, its variance is the
// formula over pairs of samples (checked by hand on a few samples) and is calibrated against the
// spread of independent renders (with and without path noise, on an edge-only image where the
// i.i.d. formula overestimates by 40 %), it estimates the same filtered image as filter sampling
// (per-pixel z-test, two-sided α = 0.01 Šidák-corrected over the pixel channels, ≥ 99.75 % must
// pass, as in test_analytic_scenes.cpp), and tile colouring keeps images bit-identical across
// thread counts.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <functional>
#include <string>
#include <vector>

#include "pellucid/api.h"
#include "pellucid/image/film.h"
#include "pellucid/sampling/rng.h"
#include "pellucid/util/error.h"
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

TEST(FilmSplat, OnePixelBoxIsFilterSampling) {
    // A box of radius ½ gives every sample weight 1 in its own pixel only: the film drops it and
    // splat() is add_sample(), so mean and variance are Welford's, bit for bit.
    Film a(3, 2), b(3, 2, Filter(BoxFilter{0.5f}));
    EXPECT_FALSE(b.splats());
    EXPECT_EQ(b.splat_margin(), 0);
    EXPECT_TRUE(Film(3, 2, Filter(BoxFilter{0.6f})).splats());
    PCG32 rng = PCG32::for_sample(7, 0, 3);
    for (int i = 0; i < 200; ++i) {
        int x = i % 3, y = (i / 3) % 2;
        Spectrum L(rng.next_float() * 4.f, rng.next_float(), 0.25f);
        a.add_sample(x, y, L);
        b.splat(x, y, float(x) + rng.next_float(), float(y) + rng.next_float(), L);
    }
    Image ma = a.mean(), mb = b.mean(), va = a.variance(), vb = b.variance();
    for (size_t i = 0; i < ma.data.size(); ++i) {
        EXPECT_EQ(ma.data[i], mb.data[i]);
        EXPECT_EQ(va.data[i], vb.data[i]);
    }
    EXPECT_EQ(a.samples(1, 1), b.samples(1, 1));
}

TEST(FilmSplat, VarianceIsThePairFormula) {
    // A 3×1 film and a tent of radius 1 (margin 1): three samples in each pixel, at known x (y at
    // the row's centre, so the row weight is 1). For every target pixel t, written out here:
    // R = Σ wL / Σ w and Var = n/(2⌊n/2⌋) Σ_q (w₁L₁ − w₀L₀ − R (w₁ − w₀))² / (Σ w)², the sum over the
    // first pair (samples 0 and 1) of each source pixel q, n = 3 (sample 2 has no partner yet). The
    // film is fed twice: pixel by pixel (a pair's second sample finds its partner's taps in the
    // per-thread cache) and interleaved over the pixels (it evaluates them again); both must agree
    // bit for bit.
    const float fx[3][3] = {{0.2f, 0.9f, 0.5f}, {1.1f, 1.6f, 1.95f}, {2.3f, 2.5f, 2.05f}};
    const float Lv[3][3] = {{1.f, 3.f, 2.f}, {0.5f, 4.f, 1.f}, {2.f, 2.f, 6.f}};
    Film a(3, 1, Filter(TentFilter{1.f})), b(3, 1, Filter(TentFilter{1.f}));
    ASSERT_EQ(a.splat_margin(), 1);
    auto sample = [&](Film& f, int q, int j) { f.splat(q, 0, fx[q][j], 0.5f, Spectrum(Lv[q][j], 2.f * Lv[q][j], 1.f)); };
    for (int q = 0; q < 3; ++q)
        for (int j = 0; j < 3; ++j) sample(a, q, j);
    for (int j = 0; j < 3; ++j)
        for (int q = 0; q < 3; ++q) sample(b, q, j);
    Image m = a.mean(), v = a.variance(), mb = b.mean(), vb = b.variance();
    for (size_t i = 0; i < m.data.size(); ++i) {
        EXPECT_EQ(m.data[i], mb.data[i]);
        EXPECT_EQ(v.data[i], vb.data[i]);
    }
    for (int t = 0; t < 3; ++t) {
        auto w = [&](float x) { return std::max(0.0, 1.0 - std::fabs(t + 0.5 - double(x))); };
        double sw = 0, swl = 0;
        for (int q = 0; q < 3; ++q)
            for (int j = 0; j < 3; ++j) sw += w(fx[q][j]), swl += w(fx[q][j]) * Lv[q][j];
        const double R = swl / sw;
        double s = 0;
        for (int q = 0; q < 3; ++q) {
            const double wa = w(fx[q][0]), wb = w(fx[q][1]);
            const double d = wb * Lv[q][1] - wa * Lv[q][0] - R * (wb - wa);
            s += d * d;
        }
        const double var = 3.0 / 2.0 * s / (sw * sw);
        EXPECT_NEAR(m.data[3 * t], R, 1e-6 * R) << t;
        EXPECT_NEAR(m.data[3 * t + 1], 2 * R, 2e-6 * R) << t;
        EXPECT_NEAR(m.data[3 * t + 2], 1.0, 1e-6) << t;
        EXPECT_NEAR(v.data[3 * t], var, 1e-5 * var) << t;
        EXPECT_NEAR(v.data[3 * t + 1], 4 * var, 4e-5 * var) << t;
        EXPECT_NEAR(v.data[3 * t + 2], 0.0, 1e-12) << t;  // a constant channel has no variance
        EXPECT_GT(var, 0.0);
    }
}

namespace {
// The film's sums written out the plainest way, one sample at a time over every target pixel of
// its (2m + 1)² block (zero weights included: adding w·(1, L) = 0 leaves a finite sum's bits
// unchanged), with the operations of film.h in their order: per target, Σ(w, wL) += w·(1, L); the
// second sample b of a pair (a, b) of a source pixel then adds d·d and d·Δw to the pair sums, with
// d = w_b(1, L_b) − w_a(1, L_a). The weights are the film's own taps (eval_filter_taps).
struct ReferenceFilm {
    int w, h, m;
    Filter filter;
    std::vector<double> sum, sq, cr;  // 4 per pixel
    std::vector<uint64_t> n;
    std::vector<std::array<float, 5>> last;  // fx, fy, L of each pixel's waiting sample
    ReferenceFilm(int w_, int h_, const Filter& f)
        : w(w_), h(h_), m(int(std::ceil(filter_radius(f) - 0.5f))), filter(f), sum(size_t(4 * w * h)),
          sq(size_t(4 * w * h)), cr(size_t(4 * w * h)), n(size_t(w * h)), last(size_t(w * h)) {}
    void rows(int x, int y, float fx, float fy, float* wx, float* wy) const {
        eval_filter_taps(filter, float(x - m) + 0.5f - fx, 2 * m + 1, wx);
        eval_filter_taps(filter, float(y - m) + 0.5f - fy, 2 * m + 1, wy);
    }
    void splat(int x, int y, float fx, float fy, const Spectrum& L) {
        const size_t src = size_t(y) * w + x;
        float bx[64], by[64], ax[64], ay[64];
        rows(x, y, fx, fy, bx, by);
        const bool second = n[src] % 2 == 1;
        if (second) rows(x, y, last[src][0], last[src][1], ax, ay);
        for (int j = -m; j <= m; ++j)
            for (int i = -m; i <= m; ++i) {
                if (x + i < 0 || x + i >= w || y + j < 0 || y + j >= h) continue;
                double* s = &sum[4 * (size_t(y + j) * w + x + i)];
                const double wb = double(bx[i + m]) * double(by[j + m]);
                const double b[4] = {1.0 * wb, double(L[0]) * wb, double(L[1]) * wb, double(L[2]) * wb};
                for (int k = 0; k < 4; ++k) s[k] = s[k] + b[k];
                if (!second) continue;
                const double wa = double(ax[i + m]) * double(ay[j + m]);
                const double a[4] = {1.0 * wa, double(last[src][2]) * wa, double(last[src][3]) * wa,
                                     double(last[src][4]) * wa};
                double* q = &sq[4 * (size_t(y + j) * w + x + i)];
                double* c = &cr[4 * (size_t(y + j) * w + x + i)];
                const double d0 = b[0] - a[0];
                for (int k = 0; k < 4; ++k) {
                    const double d = b[k] - a[k];
                    q[k] = q[k] + d * d;
                    c[k] = c[k] + d * d0;
                }
            }
        n[src] += 1;
        last[src] = {fx, fy, L[0], L[1], L[2]};
    }
    // Film::mean() and Film::variance(), pixel_stats's formulas.
    void images(Image& mean, Image& var) const {
        mean = Image(w, h, 3), var = Image(w, h, 3);
        for (size_t p = 0; p < size_t(w) * h; ++p) {
            const double* s = &sum[4 * p];
            const double* q = &sq[4 * p];
            const double* c = &cr[4 * p];
            const double W = s[0];
            for (int k = 0; k < 3; ++k) {
                double mk = 0.0, vk = 0.0;
                if (W > 0.0) {
                    const double scale = n[p] > 1 ? double(n[p]) / (2.0 * double(n[p] / 2)) / (W * W) : 0.0;
                    const double r = s[k + 1] / W;
                    mk = r;
                    vk = std::max(0.0, q[k + 1] - 2.0 * r * c[k + 1] + r * r * q[0]) * scale;
                }
                mean.data[3 * p + k] = float(mk);
                var.data[3 * p + k] = float(vk);
            }
        }
    }
};

// A splatting film's eleven sums per pixel, as its state file stores them (docs/rendering.md, "Film
// state files": Σ wL[3], Σ w, Σ Δ(wL)²[3], Σ Δ(wL)Δw[3], Σ Δw², then n and the waiting sample).
std::vector<double> film_sums(const Film& f, const Filter& filter, const std::string& name) {
    const std::string path = (std::filesystem::temp_directory_path() / ("pellucid_test_film_splat_" + name)).string();
    save_film_state(path, FilmState{f, filter, 0, 0, "independent", "", 0, 0.0});
    std::ifstream in(path, std::ios::binary);
    const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::filesystem::remove(path);
    const size_t record = 11 * 8 + 8 + 5 * 4, pixels = size_t(f.width()) * f.height();
    EXPECT_GE(data.size(), pixels * record + 8);
    std::vector<double> sums(11 * pixels);
    const char* p = data.data() + data.size() - 8 - pixels * record;
    for (size_t i = 0; i < pixels; ++i) std::memcpy(&sums[11 * i], p + i * record, 11 * 8);
    return sums;
}
std::vector<double> reference_sums(const ReferenceFilm& r) {
    std::vector<double> sums;
    for (size_t i = 0; i < r.n.size(); ++i) {
        const double* s = &r.sum[4 * i];
        const double* q = &r.sq[4 * i];
        const double* c = &r.cr[4 * i];
        for (double v : {s[1], s[2], s[3], s[0], q[1], q[2], q[3], c[1], c[2], c[3], q[0]}) sums.push_back(v);
    }
    return sums;
}
size_t count_differing(const std::vector<double>& a, const std::vector<double>& b) {
    size_t differ = a.size() == b.size() ? 0 : 1;
    for (size_t i = 0; i < std::min(a.size(), b.size()); ++i) differ += std::memcmp(&a[i], &b[i], 8) != 0;
    return differ;
}

size_t count_differing(const Image& a, const Image& b) {
    size_t differ = 0;
    for (size_t i = 0; i < a.data.size(); ++i) differ += std::memcmp(&a.data[i], &b.data[i], 4) != 0;
    return differ;
}
}  // namespace

TEST(FilmSplat, PixelRunsEqualSingleSplats) {
    // Film::splat_pixel (the renderer's path) adds a pixel's samples pair by pair in one pass; it
    // must give, bit for bit, the sums (and so the mean and variance images) of one splat() per
    // sample and those of the reference above:
    // runs of 1 to 9 samples, so pairs start inside a run, span two runs of one pixel, and span runs
    // of different pixels (the second sample re-evaluates its partner's taps), and a run fills one
    // batch of four accumulations or more (splat_pixel adds four at a time), on a 7×6 film (pixels
    // whose block is cut by the border, and pixels whose whole block is inside, which margins 1 and
    // 2 take on fixed bounds), with Gaussians (shifted or not) reaching 2 and 3 pixels, a tent and a
    // box of radius 1.5; and through every variant of the accumulation this CPU runs (AVX2 and the
    // baseline on x86-64), which must all give the same bits.
    const Filter filters[] = {GaussianFilter(0.5f, true), GaussianFilter(0.5f), GaussianFilter(0.7f, true),
                              TentFilter{1.f}, BoxFilter{1.5f}};
    const int W = 7, H = 6;
    const std::vector<Film::AccumulationVariant> variants = Film::accumulation_variants();
    ASSERT_FALSE(variants.empty());
    EXPECT_EQ(Film(2, 2, Filter(TentFilter{1.f})).accumulation_variant(), variants.back());
    for (const Film::AccumulationVariant variant : variants)
        for (const Filter& filter : filters) {
            const std::string what = to_string(filter) + " variant " + std::to_string(int(variant));
            Film a(W, H, filter), b(W, H, filter);
            a.set_accumulation_variant(variant);
            b.set_accumulation_variant(variant);
            ReferenceFilm ref(W, H, filter);
            PCG32 rng(7, 3);
            const int runs[] = {1, 2, 3, 5, 4, 8, 9, 7};
            for (int pass = 0; pass < 3; ++pass)
                for (int y = 0; y < H; ++y)
                    for (int x = 0; x < W; ++x) {
                        const int n = runs[(x + 3 * y + pass) % 8];
                        std::vector<FilmSample> s(static_cast<size_t>(n));
                        for (FilmSample& e : s) {
                            e.fx = float(x) + rng.next_float();
                            e.fy = float(y) + rng.next_float();
                            e.L = Spectrum(rng.next_float(), 3.f * rng.next_float(), 0.25f);
                            a.splat(x, y, e.fx, e.fy, e.L);
                            ref.splat(x, y, e.fx, e.fy, e.L);
                        }
                        b.splat_pixel(x, y, s.data(), n);
                    }
            // The sums themselves (a one-ulp change in one of them rarely shows in the float images).
            const std::vector<double> sa = film_sums(a, filter, "a"), sb = film_sums(b, filter, "b"), sr = reference_sums(ref);
            EXPECT_EQ(count_differing(sa, sb), 0u) << what;
            EXPECT_EQ(count_differing(sa, sr), 0u) << what;
            Image mr, vr;
            ref.images(mr, vr);
            const Image ma = a.mean(), mb = b.mean(), va = a.variance(), vb = b.variance();
            EXPECT_EQ(count_differing(ma, mb) + count_differing(va, vb), 0u) << what;
            EXPECT_EQ(count_differing(ma, mr) + count_differing(va, vr), 0u) << what;
            for (int y = 0; y < H; ++y)
                for (int x = 0; x < W; ++x) EXPECT_EQ(a.samples(x, y), b.samples(x, y));
            EXPECT_GT(va.data[0], 0.f);
        }
}

TEST(FilmSplat, MeanWithoutVarianceIsTheSameBits) {
    // A film made with variance off keeps Σw and Σw·L only: they, and so the mean image, must be
    // the bits of a film with variance, through every accumulation variant, for runs of 1 to 9
    // samples (pairs inside a run and across runs), at the border and inside, with each filter of
    // PixelRunsEqualSingleSplats. Its variance() throws, and its state file keeps the flag and the
    // sums (written and read back).
    const Filter filters[] = {GaussianFilter(0.5f, true), GaussianFilter(0.5f), GaussianFilter(0.7f, true),
                              TentFilter{1.f}, BoxFilter{1.5f}};
    const int W = 7, H = 6;
    for (const Film::AccumulationVariant variant : Film::accumulation_variants())
        for (const Filter& filter : filters) {
            const std::string what = to_string(filter) + " variant " + std::to_string(int(variant));
            Film with(W, H, filter), without(W, H, filter, false);
            EXPECT_TRUE(with.has_variance());
            EXPECT_FALSE(without.has_variance());
            with.set_accumulation_variant(variant);
            without.set_accumulation_variant(variant);
            PCG32 rng(11, 5);
            const int runs[] = {1, 2, 3, 5, 4, 8, 9, 7};
            for (int pass = 0; pass < 3; ++pass)
                for (int y = 0; y < H; ++y)
                    for (int x = 0; x < W; ++x) {
                        const int n = runs[(2 * x + y + pass) % 8];
                        std::vector<FilmSample> s(static_cast<size_t>(n));
                        for (FilmSample& e : s) {
                            e.fx = float(x) + rng.next_float();
                            e.fy = float(y) + rng.next_float();
                            e.L = Spectrum(2.f * rng.next_float(), rng.next_float(), 0.5f);
                        }
                        with.splat_pixel(x, y, s.data(), n);
                        without.splat_pixel(x, y, s.data(), n);
                    }
            EXPECT_EQ(count_differing(with.mean(), without.mean()), 0u) << what;
            EXPECT_THROW(without.variance(), Error);
            EXPECT_THROW(without.mean_relative_variance(), Error);
            // The state file: Σ wL[3], Σ w, n, the waiting sample (no pair sums) per pixel.
            const std::string path = (std::filesystem::temp_directory_path() / "pellucid_test_film_no_variance").string();
            save_film_state(path, FilmState{without, filter, 0, 0, "independent", "", 0, 0.0});
            const std::vector<double> sw = film_sums(with, filter, "with");
            std::ifstream in(path, std::ios::binary);
            const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
            const size_t record = 4 * 8 + 8 + 5 * 4, pixels = size_t(W) * H;
            ASSERT_GE(data.size(), pixels * record + 8);
            const char* p = data.data() + data.size() - 8 - pixels * record;
            size_t differ = 0;
            for (size_t i = 0; i < pixels; ++i) differ += std::memcmp(&sw[11 * i], p + i * record, 4 * 8) != 0;
            EXPECT_EQ(differ, 0u) << what;
            const std::shared_ptr<FilmState> back = load_film_state(path);
            std::filesystem::remove(path);
            EXPECT_FALSE(back->film.has_variance());
            EXPECT_EQ(count_differing(back->film.mean(), without.mean()), 0u) << what;
            for (int y = 0; y < H; ++y)
                for (int x = 0; x < W; ++x) EXPECT_EQ(back->film.samples(x, y), with.samples(x, y));
        }
}

TEST(FilmSplat, AccumulationVariantsAreChecked) {
    // A variant this CPU lacks is refused (the enum's values past the last are never available).
    Film f(3, 3, Filter(TentFilter{1.f}));
    EXPECT_THROW(f.set_accumulation_variant(Film::AccumulationVariant(99)), Error);
    f.set_accumulation_variant(Film::AccumulationVariant::Baseline);
    EXPECT_EQ(f.accumulation_variant(), Film::AccumulationVariant::Baseline);
    // A new film takes the widest, or the baseline where PELLUCID_FILM_ACCUMULATION says so.
    ASSERT_EQ(std::getenv("PELLUCID_FILM_ACCUMULATION"), nullptr);
    EXPECT_EQ(Film(3, 3, Filter(TentFilter{1.f})).accumulation_variant(), Film::accumulation_variants().back());
    setenv("PELLUCID_FILM_ACCUMULATION", "baseline", 1);
    EXPECT_EQ(Film(3, 3, Filter(TentFilter{1.f})).accumulation_variant(), Film::AccumulationVariant::Baseline);
    setenv("PELLUCID_FILM_ACCUMULATION", "avx2", 1);  // anything else: the default
    EXPECT_EQ(Film(3, 3, Filter(TentFilter{1.f})).accumulation_variant(), Film::accumulation_variants().back());
    unsetenv("PELLUCID_FILM_ACCUMULATION");
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

namespace {
/// Per pixel channel, over K renders with seeds 100.., the spread of the K estimates (unbiased sample
/// variance: the true variance) and the mean of the film's K variance estimates.
struct Spread {
    std::vector<double> empirical, predicted;
};
Spread spread_of_renders(const std::function<std::string(int)>& json, int K) {
    Spread out;
    std::vector<double> sum, sum2;
    for (int k = 0; k < K; ++k) {
        RenderResult r = render(*scene_from(json(100 + k)), RenderOptions{});
        if (sum.empty()) sum.assign(r.image.data.size(), 0.0), sum2 = sum, out.predicted = sum;
        for (size_t i = 0; i < sum.size(); ++i) {
            sum[i] += r.image.data[i];
            sum2[i] += double(r.image.data[i]) * r.image.data[i];
            out.predicted[i] += double(r.variance.data[i]) / K;
        }
    }
    out.empirical.resize(sum.size());
    for (size_t i = 0; i < sum.size(); ++i) {
        const double m = sum[i] / K;
        out.empirical[i] = std::max(0.0, (sum2[i] - K * m * m) / (K - 1));
    }
    return out;
}
}  // namespace

TEST(FilmSplat, VarianceMatchesSpreadOfIndependentRenders) {
    // The path-traced test scene at 8 spp, K = 96 renders: summed over all pixel channels, the film's
    // variance against the spread of the renders. The empirical total has a relative standard error of
    // about √(2/(K−1))/√(pixels) ≈ 0.6 % here, a few times more as bright pixels dominate and
    // neighbours correlate; the bounds are ±8 %.
    constexpr int K = 96;
    const Spread s = spread_of_renders([](int seed) { return scene_json(kSplatGaussian, 8, seed, 16, 12); }, K);
    double emp_total = 0, pred_total = 0;
    for (size_t i = 0; i < s.empirical.size(); ++i) emp_total += s.empirical[i], pred_total += s.predicted[i];
    ASSERT_GT(emp_total, 0.0);
    const double ratio = pred_total / emp_total;
    EXPECT_GT(ratio, 0.92) << "predicted " << pred_total << " empirical " << emp_total;
    EXPECT_LT(ratio, 1.08) << "predicted " << pred_total << " empirical " << emp_total;
}

TEST(FilmSplat, VarianceMatchesSpreadOfRendersAtEdges) {
    // Only edges: emission and the background seen directly (max_depth 1), so all the variance comes
    // from where the samples land in their pixels, and samples are stratified by pixel. K = 128
    // renders at 16 spp. Per pixel channel that varies, r = (mean film variance) / (spread of the
    // renders); with a calibrated film r ≈ (K − 1)/χ²(K − 1), whose median is 1.005. The median over
    // the ≈ 250 channels (correlated: they lie along a few edges) has a standard deviation of 0.03
    // (ten sets of seeds: 0.94–1.05); it must lie in [0.88, 1.13]. The i.i.d. (Cochran) formula gives
    // 1.4 here; dropping the factor n/(2⌊n/2⌋) of the pairs doubles it. No channel that varies
    // across the renders may have a zero film variance.
    constexpr int K = 128;
    const Spread s = spread_of_renders(
        [](int seed) {
            return std::string(R"({"camera": {"type": "perspective", "fov": 45,
                "to_world": [{"look_at": {"origin": [0, 1.5, 4], "target": [0, 0, 0], "up": [0, 1, 0]}}]},
                "film": {"width": 16, "height": 12, "filter": {"type": "gaussian", "shift": true},
                         "reconstruction": "splatting"},
                "sampler": {"sample_count": 16, "seed": )") + std::to_string(seed) + R"(},
                "integrator": {"type": "path", "max_depth": 1},
                "materials": {"white": {"type": "lambertian", "reflectance": 0.7}},
                "shapes": [{"type": "sphere", "radius": 0.8, "material": "white"},
                           {"type": "rectangle", "material": "white",
                            "to_world": [{"scale": 3}, {"rotate": {"axis": [1, 0, 0], "angle": -90}},
                                         {"translate": [0, -0.8, 0]}]},
                           {"type": "rectangle", "emitter": {"type": "area", "radiance": 10},
                            "to_world": [{"scale": 0.4}, {"rotate": {"axis": [1, 0, 0], "angle": 90}},
                                         {"translate": [0.5, 2.5, 0.5]}]}],
                "lights": [{"type": "constant", "radiance": 0.5}]})";
        }, K);
    std::vector<double> r;
    int zero_but_varies = 0;
    for (size_t i = 0; i < s.empirical.size(); ++i) {
        if (!(s.empirical[i] > 1e-12)) continue;  // constant across the renders
        if (s.predicted[i] == 0.0) ++zero_but_varies;
        r.push_back(s.predicted[i] / s.empirical[i]);
    }
    ASSERT_GT(r.size(), 100u);
    std::nth_element(r.begin(), r.begin() + r.size() / 2, r.end());
    const double median = r[r.size() / 2];
    EXPECT_GT(median, 0.88) << r.size() << " channels";
    EXPECT_LT(median, 1.13) << r.size() << " channels";
    EXPECT_EQ(zero_but_varies, 0);
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
// recurrence outwards from the middle tap) equals the filter's profile, including the cut at the
// radius. The reference is the profile in double precision at the same float abscissa; the bound,
// 4e-6 relative to the unshifted Gaussian (+1e-9 absolute), covers float exp's error of about
// |argument|·2^-24 compounded over the row's steps, and is far below anything a wrong recurrence
// gives (test_filter.cpp bounds the error on a dense grid).
TEST(FilmSplat, FilterTapsEqualTheFilterProfile) {
    const Filter filters[] = {GaussianFilter(0.5f), GaussianFilter(0.3f), GaussianFilter(1.2f),
                              GaussianFilter(0.5f, true), GaussianFilter(1.2f, true), TentFilter{1.5f}, BoxFilter{0.5f}};
    for (const Filter& f : filters) {
        const int m = int(std::ceil(filter_radius(f) - 0.5f)), n = 2 * m + 1;
        for (int s = 0; s < 200; ++s) {
            const float frac = float(s) / 200.f;  // the sample's offset within its pixel
            const float x0 = float(-m) + 0.5f - frac;
            float w[64];
            eval_filter_taps(f, x0, n, w);
            for (int i = 0; i < n; ++i) {
                const float x = x0 + float(i);
                double ref = eval_filter(f, x), shift = 0.0;  // box, tent: exact in float
                if (const auto* g = std::get_if<GaussianFilter>(&f)) {
                    const double k = 1.0 / (2.0 * g->stddev * g->stddev);
                    shift = g->shift ? std::exp(-8.0) : 0.0;
                    ref = std::fabs(x) < 4.f * g->stddev ? std::max(0.0, std::exp(-double(x) * x * k) - shift) : 0.0;
                }
                EXPECT_NEAR(w[i], ref, 4e-6 * (ref + shift) + 1e-9) << to_string(f) << " x=" << x;
            }
        }
    }
}
