// Film accumulation.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/image/film.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <type_traits>

#include "pellucid/util/error.h"

namespace pellucid {

namespace {
/// Four doubles: (Σw, Σw·L) of a target pixel, or one of its pair sums. (GCC notes that a vector
/// return changes the ABI between the clones; these helpers are internal and always inlined.)
#pragma GCC diagnostic ignored "-Wpsabi"
typedef double D4 __attribute__((vector_size(32)));
inline D4 load4(const double* p) {
    D4 v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
inline void store4(double* p, D4 v) { std::memcpy(p, &v, sizeof v); }

/// A box of radius ½ gives each sample weight 1 in its own pixel and 0 elsewhere: splatting with it
/// is filter sampling.
bool is_one_pixel_box(const Filter& f) {
    const auto* b = std::get_if<BoxFilter>(&f);
    return b && b->radius == 0.5f;
}

/// N floats and N int32 (N = 16, 8 or 4): a block of rows of eval_filter_taps16. GCC vector types,
/// the same IEEE operation per element on any width (no contraction: -ffp-contract=off). Each
/// variant takes the width of its registers (AVX-512 16, AVX2 8, the SSE2/NEON baseline 4) and runs
/// the sixteen rows as 16/N blocks: wider types than the registers are split by GCC into scalar
/// code in places (inserts, extracts and scalar compares: about 10,000 instructions for the AVX2
/// variant on 16-wide types, 14 % of an `env_diffuse` render), and each row's arithmetic does not
/// depend on the other rows, so the blocks give the same bits.
template <int N>
struct TapVec {
    typedef float F __attribute__((vector_size(4 * N)));
    typedef int32_t I __attribute__((vector_size(4 * N)));
};

/// The abscissa offsets of the taps, float(i), as constants.
constexpr float kTapOffset[kMaxFilterTaps] = {0,  1,  2,  3,  4,  5,  6,  7,  8,  9,  10, 11, 12, 13, 14, 15, 16,
                                              17, 18, 19, 20, 21, 22, 23, 24, 25, 26, 27, 28, 29, 30, 31, 32};

/// e^x per element, 0 for x < −87, x clamped to ≤ 88: x = n ln 2 + r, n = round(x / ln 2), ln 2 in two
/// parts so that n·ln2_hi is exact (Cody & Waite 1980, Software Manual for the Elementary Functions,
/// ch. 6), e^r by its Taylor series to r⁷ on |r| ≤ ln 2/2 (truncation below 6e-9), times 2^n built in
/// the exponent field. Only IEEE-rounded operations, so every instruction set gives the same bits.
template <int N>
__attribute__((always_inline)) inline typename TapVec<N>::F exp_taps(typename TapVec<N>::F x) {
    using FV = typename TapVec<N>::F;
    using IV = typename TapVec<N>::I;
    const FV lo = x < -87.f ? FV{} - 87.f : x;
    const FV xc = lo > 88.f ? FV{} + 88.f : lo;
    const FV n = (xc * 1.44269504f + 12582912.f) - 12582912.f;
    const FV r = (xc - n * 0.693359375f) - n * -2.12194440e-4f;
    const FV p = 1.f + r * (1.f + r * (0.5f + r * (1.f / 6.f + r * (1.f / 24.f + r * (1.f / 120.f + r * (1.f / 720.f + r * (1.f / 5040.f)))))));
    const IV k = (IV)(n + 12582912.f) - (IV)(FV{} + 12582912.f);
    const FV two_n = (FV)((k + 127) << 23);
    const FV e = p * two_n;
    return (FV)((IV)e & (x < -87.f ? IV{} : IV{} - 1));
}

// The Gaussian's taps on rows [r0, r0 + N) (kShift: the shifted profile; kN: the number of taps when
// it is known at compile time, 0 for any n). Each row starts at its middle tap c, at xc = x0 + c, and
// walks outwards: right with the ratio e(x + 1)/e(x) = exp(−(2x + 1)k), left with e(x − 1)/e(x) =
// exp(−(1 − 2x)k), each ratio shrinking by q = exp(−2k) a step. The product of the two first ratios
// is q, so each row takes two exponentials, e(xc) and the right ratio (exp_taps). Every element is one
// IEEE operation of the row's own input, in the same order whatever kShift, kN, N and the instruction set.
template <int N, bool kShift, int kN>
__attribute__((always_inline)) inline void gaussian_taps_block(const GaussianFilter& g, const float* x0, int n_dyn,
                                                               float (*w)[16], int r0) {
    using FV = typename TapVec<N>::F;
    using IV = typename TapVec<N>::I;
    const int n = kN > 0 ? kN : n_dyn, c = n / 2;
    const FV zero{};
    FV x;
    std::memcpy(&x, x0 + r0, sizeof x);
    const FV k = zero + g.m_k;
    const FV xc = x + kTapOffset[c];
    const FV ec = exp_taps<N>(-xc * xc * k), r0v = exp_taps<N>(-(2.f * xc + 1.f) * k);
    const FV q = zero + g.m_q, radius = zero + g.m_radius;
    auto tap = [&](int i, FV e) {
        const FV xi = x + kTapOffset[i];
        FV v;
        if constexpr (kShift) {
            const FV d = e - g.m_bias;
            v = zero < d ? d : zero;  // std::max(0, g − g(r))
        } else {
            v = zero < e ? e : zero;  // std::max(0, e) (e − 0 is e)
        }
        // |x| < r (false for NaN, as fabs)
        const IV in = ((FV)((IV)xi & 0x7fffffff) < radius);
        const FV out = (FV)((IV)v & in);
        std::memcpy(w[i] + r0, &out, sizeof out);
    };
    // The two walks are independent: the left one's first ratio (a division) starts at once.
    FV el_ratio = q / r0v;  // exp(−(1 − 2xc)k)
    FV el = ec * el_ratio;
    el_ratio *= q;
    FV er = ec, er_ratio = r0v;
    for (int i = c; i < n; ++i) {
        tap(i, er);
        er *= er_ratio;
        er_ratio *= q;
    }
    for (int i = c - 1; i >= 0; --i) {
        tap(i, el);
        el *= el_ratio;
        el_ratio *= q;
    }
}

template <int N, bool kShift, int kN>
__attribute__((always_inline)) inline void gaussian_taps16_impl(const GaussianFilter& g, const float x0[16], int n,
                                                                float (*w)[16]) {
    static_assert(16 % N == 0, "whole blocks of rows");
    for (int r0 = 0; r0 < 16; r0 += N) gaussian_taps_block<N, kShift, kN>(g, x0, n, w, r0);
}

template <int N, bool kShift>
__attribute__((always_inline)) inline void gaussian_taps16_shift(const GaussianFilter& g, const float x0[16], int n,
                                                                 float (*w)[16]) {
    switch (n) {  // the film's common sizes fully unrolled
    case 5: return gaussian_taps16_impl<N, kShift, 5>(g, x0, n, w);
    case 7: return gaussian_taps16_impl<N, kShift, 7>(g, x0, n, w);
    case 3: return gaussian_taps16_impl<N, kShift, 3>(g, x0, n, w);
    default: return gaussian_taps16_impl<N, kShift, 0>(g, x0, n, w);
    }
}

/// The sixteen rows in blocks of N (the variant's register width in floats).
template <int N>
__attribute__((always_inline)) inline void gaussian_taps16(const GaussianFilter& g, const float x0[16], int n, float (*w)[16]) {
    if (g.shift) gaussian_taps16_shift<N, true>(g, x0, n, w);
    else gaussian_taps16_shift<N, false>(g, x0, n, w);
}

// The instruction-set variants of the Gaussian's taps (FilterTapsVariant): on x86-64 with GCC,
// baseline, AVX2 and AVX-512 (a row vector in one register); elsewhere the baseline only.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define PELLUCID_TAPS_X86_VARIANTS 1
#endif
void gaussian_taps16_baseline(const GaussianFilter& g, const float x0[16], int n, float (*w)[16]) {
    gaussian_taps16<4>(g, x0, n, w);
}
#ifdef PELLUCID_TAPS_X86_VARIANTS
__attribute__((target("avx2"))) void gaussian_taps16_avx2(const GaussianFilter& g, const float x0[16], int n, float (*w)[16]) {
    gaussian_taps16<8>(g, x0, n, w);
}
__attribute__((target("avx512f"))) void gaussian_taps16_avx512(const GaussianFilter& g, const float x0[16], int n,
                                                               float (*w)[16]) {
    gaussian_taps16<16>(g, x0, n, w);
}
#endif

/// The widest taps variant this CPU runs (chosen once).
FilterTapsVariant widest_taps_variant() {
    static const FilterTapsVariant v = filter_taps_variants().back();
    return v;
}
}  // namespace

std::vector<FilterTapsVariant> filter_taps_variants() {
    std::vector<FilterTapsVariant> v{FilterTapsVariant::Baseline};
#ifdef PELLUCID_TAPS_X86_VARIANTS
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx2")) v.push_back(FilterTapsVariant::AVX2);
    if (__builtin_cpu_supports("avx512f")) v.push_back(FilterTapsVariant::AVX512);
#endif
    return v;
}

void eval_filter_taps16(const Filter& f, const float x0[16], int n, float (*w)[16]) {
    eval_filter_taps16(f, x0, n, w, widest_taps_variant());
}

void eval_filter_taps16(const Filter& f, const float x0[16], int n, float (*w)[16], FilterTapsVariant variant) {
    std::visit([&](const auto& k) {
        if constexpr (std::is_same_v<std::decay_t<decltype(k)>, GaussianFilter>) {
            switch (variant) {
#ifdef PELLUCID_TAPS_X86_VARIANTS
            case FilterTapsVariant::AVX512: return gaussian_taps16_avx512(k, x0, n, w);
            case FilterTapsVariant::AVX2: return gaussian_taps16_avx2(k, x0, n, w);
#endif
            default: return gaussian_taps16_baseline(k, x0, n, w);
            }
        } else {
            for (int i = 0; i < n; ++i)
                for (int r = 0; r < 16; ++r) w[i][r] = k.eval(x0[r] + float(i));
        }
    }, f);
}

namespace {
/// The widest accumulation variant, or the baseline where the environment variable
/// PELLUCID_FILM_ACCUMULATION is `baseline` (for instruction counts under valgrind 3.19, which does
/// not decode the AVX2 variant's register-to-register VEX vmovq).
Film::AccumulationVariant default_accumulation_variant() {
    const char* env = std::getenv("PELLUCID_FILM_ACCUMULATION");
    if (env && std::string(env) == "baseline") return Film::AccumulationVariant::Baseline;
    return Film::accumulation_variants().back();
}
}  // namespace

Film::Film(int width, int height, std::optional<Filter> splat, bool variance)
    : m_width(width), m_height(height), m_splat(std::move(splat)), m_variance(variance),
      m_variant(default_accumulation_variant()) {
    if (m_splat && is_one_pixel_box(*m_splat)) m_splat.reset();
    if (m_splat) {
        // Pixel centres px + ½ within the radius r of a sample in [x, x + 1) satisfy
        // |px − x| <= ⌈r − ½⌉.
        m_margin = std::max(0, int(std::ceil(filter_radius(*m_splat) - 0.5f)));
        m_sums.resize(size_t(width) * height);
        if (m_variance) m_pair_sums.resize(size_t(width) * height);
        m_sources.resize(size_t(width) * height);
    } else {
        m_pixels.resize(size_t(width) * height);
    }
}

void Film::splat(int x, int y, float fx, float fy, const Spectrum& L) {
    if (!m_splat) {
        add_sample(x, y, L);
        return;
    }
    const FilmSample s{L, fx, fy};
    splat_pixel(x, y, &s, 1);
}

void Film::splat_pixel(int x, int y, const FilmSample* s, int n) {
    if (!m_splat) {
        for (int i = 0; i < n; ++i) add_sample(x, y, s[i].L);
        return;
    }
    if (n <= 0) return;
    const int m = std::min(m_margin, 16), n_taps = 2 * m + 1;
    SplatSource& src = m_sources[size_t(y) * m_width + x];
    // The accumulations of this call, in order, each a sample b and its partner a: a pixel whose
    // last sample waits for its partner pairs it with s[0] (its weights are evaluated again, the
    // same numbers as when it was splatted); then whole pairs; then a first sample whose partner
    // comes later (its own weights in both halves, no partner). They run four at a time, so that one
    // eval_filter_taps16 call gives the weights of four.
    SplatJob jobs[4];
    int n_jobs = 0;
    auto flush = [&]() {
        // Row 4j + r of the weights is job j's a column (r = 0), a row (1), b column (2), b row (3).
        const float ox = float(x - m) + 0.5f, oy = float(y - m) + 0.5f;
        float x0[16];
        for (int j = 0; j < 4; ++j) {
            const SplatJob& b = jobs[std::min(j, n_jobs - 1)];
            x0[4 * j + 0] = ox - b.afx, x0[4 * j + 1] = oy - b.afy, x0[4 * j + 2] = ox - b.bfx, x0[4 * j + 3] = oy - b.bfy;
        }
        float w[kMaxFilterTaps][16];
        eval_filter_taps16(*m_splat, x0, n_taps, w);
        accumulate(x, y, m, &w[0][0], n_jobs, jobs);
        n_jobs = 0;
    };
    auto run = [&](float afx, float afy, const float* la, bool add_a, const FilmSample& b) {
        SplatJob& j = jobs[n_jobs++];
        j.afx = afx, j.afy = afy, j.bfx = b.fx, j.bfy = b.fy;
        j.has_a = la != nullptr, j.add_a = add_a, j.L = &b.L;
        for (int k = 0; k < 3; ++k) j.la[k] = la ? la[k] : 0.f;
        if (n_jobs == 4) flush();
    };
    int i = 0;
    if (src.n % 2 == 1) {
        run(src.last_fx, src.last_fy, src.last_l, false, s[0]);
        src.n += 1;
        i = 1;
    }
    for (; i + 1 < n; i += 2) {  // whole pairs: both samples and their difference in one pass
        const float la[3] = {s[i].L[0], s[i].L[1], s[i].L[2]};
        run(s[i].fx, s[i].fy, la, true, s[i + 1]);
        src.n += 2;
    }
    if (i < n) {  // the first sample of a pair whose partner comes later
        run(s[i].fx, s[i].fy, nullptr, false, s[i]);
        src.n += 1;
        src.last_fx = s[i].fx;
        src.last_fy = s[i].fy;
        for (int k = 0; k < 3; ++k) src.last_l[k] = s[i].L[k];
    }
    if (n_jobs > 0) flush();
}

namespace {
/// What one accumulation reads and writes: the film's sums (4 doubles a pixel: Σw, Σw·L) and pair
/// sums (8 doubles a pixel: Σ Δ(1, L)², Σ Δ(1, L)·Δw), and one pair of samples (Film::accumulate).
struct AccumulateArgs {
    double* sums;
    double* pairs;
    int width, height, x, y, m;
    const float* w;  // tap t's (a column, a row, b column, b row) at w + 16 t
    const float* la;
    bool add_a;
    const float* L;
};
/// Up to four accumulations at one pixel (Film::accumulate): job k's weights at w + 4k (stride 16).
struct AccumulateBatch {
    double* sums;
    double* pairs;
    int width, height, x, y, m, n;
    const float* w;
    const float* la[4];
    bool add_a[4];
    float L[4][3];
};

// One accumulation, written once for every instruction set (Film::AccumulationVariant), at any
// margin and position: its targets trimmed to the film and to the nonzero end taps. (Inside the
// film, margins 1 and 2 take accumulate_block, which updates the whole (2m + 1)² block: a target
// with weight 0 for both samples adds 0, which leaves a sum's bits as they are, as no sum is ever
// −0: the sums start at +0 and x + (−x) is +0.)
// kVar false: the film keeps no pair sums (A.pairs is null); Σw and Σw·L get the same operations.
template <bool kVar>
__attribute__((always_inline)) inline void accumulate_impl(const AccumulateArgs& A) {
    const int m = A.m, x = A.x, y = A.y;
    // The weights as doubles (exact), so that each target's weight is one product.
    double wd[kMaxFilterTaps][4];
    for (int t = 0; t <= 2 * m; ++t)
        for (int r = 0; r < 4; ++r) wd[t][r] = double(A.w[16 * t + r]);
    // Targets inside the film, columns x + i0 .. x + i1, rows y + j0 .. y + j1, that may have a
    // nonzero weight. A sample in [x, x + 1) has a zero tap at one end of its row or the other for
    // about half the offsets (with σ = ½: every offset), so the end taps are tested, without a
    // branch; a zero weight inside the block adds w·(1, L) = 0, which leaves a finite sum's bits as
    // they are. (Without a partner, w[·][0..1] repeat b's weights.)
    int i0 = -m, i1 = m, j0 = -m, j1 = m;
    {
        auto nz = [&](int t, int axis) { return int(A.w[16 * t + axis] > 0.f) | int(A.w[16 * t + 2 + axis] > 0.f); };
        i0 = -m + (1 - nz(0, 0)), i1 = m - (1 - nz(2 * m, 0));
        j0 = -m + (1 - nz(0, 1)), j1 = m - (1 - nz(2 * m, 1));
        i0 = std::max(i0, -x), i1 = std::min(i1, A.width - 1 - x);
        j0 = std::max(j0, -y), j1 = std::min(j1, A.height - 1 - y);
    }
    const float* L = A.L;
    // (1, L) and (1, L_a): w·l4 is (w, wL), and its pair difference (Δw, Δ(wL)). Four doubles at a
    // time (a GCC/Clang vector: one AVX2 register, or two SSE2/NEON ones; the same IEEE operation
    // per element either way).
    const D4 l4 = {1.0, double(L[0]), double(L[1]), double(L[2])};
    if (!A.la) {
        for (int j = j0; j <= j1; ++j) {
            const double wyj = wd[j + m][3];
            double* sums = A.sums + 4 * (size_t(y + j) * A.width + x);
            for (int i = i0; i <= i1; ++i) {
                const double wb = wd[i + m][2] * wyj;
                store4(sums + 4 * i, load4(sums + 4 * i) + l4 * wb);
            }
        }
        return;
    }
    const float* la = A.la;
    const D4 lp4 = {1.0, double(la[0]), double(la[1]), double(la[2])};
    auto pair_rows = [&](auto add_a_constant) {
        constexpr bool add_a = decltype(add_a_constant)::value;
        for (int j = j0; j <= j1; ++j) {
            const double wyj = wd[j + m][3], pyj = wd[j + m][1];
            const size_t row = size_t(y + j) * A.width + x;
            double* sums = A.sums + 4 * row;
            double* pairs = kVar ? A.pairs + 8 * row : nullptr;
            for (int i = i0; i <= i1; ++i) {
                // Σ(w, wL) += a (if add_a), += b; the pair sums += (d·d, d·Δw), d = b − a.
                const double wb = wd[i + m][2] * wyj, wa = wd[i + m][0] * pyj;
                const D4 b = l4 * wb, a = lp4 * wa;
                D4 t = load4(sums + 4 * i);
                if constexpr (add_a) t += a;
                store4(sums + 4 * i, t + b);
                if constexpr (kVar) {
                    const D4 d = b - a;
                    double* q = pairs + 8 * i;
                    store4(q, load4(q) + d * d);
                    store4(q + 4, load4(q + 4) + d * d[0]);
                }
            }
        }
    };
    if (A.add_a) pair_rows(std::true_type{});
    else pair_rows(std::false_type{});
}

// The n accumulations of a batch, in order, on the whole (2kM + 1)² block inside the film: each
// target's sums are loaded once, take every job's updates in the order accumulate_impl applies them
// (a, then b, then the pair sums), and are stored once (a job without a partner leaves the pair sums
// as they are). A sample's update of target (i, j) is (1, L)·w with w = wx_i·wy_j; here it is
// computed as ((1, L)·wy_j)·wx_i, the row's vector once per row and then one product per target:
// both (1, L)·wy_j and wx_i·wy_j are exact in double (products of two floats), so either way the
// result is the exact triple product rounded once, the same bits, for a multiply and an add per
// target instead of two multiplies, a broadcast and an add. A partner that is not added here
// (add_a false) adds ((0, 0)·wy)·wx = +0, which leaves a sum's bits as they are (no sum is ever −0),
// so the loop has no branch on it.
template <int kM, bool kVar>
__attribute__((always_inline)) inline void accumulate_block(const AccumulateBatch& B) {
    constexpr int kT = 2 * kM + 1;
    const int n = B.n, x = B.x, y = B.y;
    // Job k's column weights (sample a, then b) as doubles, and its row vectors (1, L)·wy.
    double cx[4][2][kT];
    D4 ra[4][kT], rb[4][kT], pa[4][kT];  // a's row vectors for the sums (0 without add_a) and for the pair sums
    bool has_a[4];
    for (int k = 0; k < n; ++k) {
        const D4 l4 = D4{1.0, double(B.L[k][0]), double(B.L[k][1]), double(B.L[k][2])};
        has_a[k] = B.la[k] != nullptr;
        const D4 lp4 = has_a[k] ? D4{1.0, double(B.la[k][0]), double(B.la[k][1]), double(B.la[k][2])} : l4;
        const D4 zero{};
        for (int t = 0; t < kT; ++t) {
            const float* w = B.w + 16 * t + 4 * k;
            cx[k][0][t] = double(w[0]), cx[k][1][t] = double(w[2]);
            rb[k][t] = l4 * double(w[3]);
            pa[k][t] = lp4 * double(w[1]);
            ra[k][t] = B.add_a[k] ? pa[k][t] : zero;
        }
    }
    for (int j = -kM; j <= kM; ++j) {
        const size_t row = size_t(y + j) * B.width + x;
        double* sums = B.sums + 4 * row;
        double* pairs = kVar ? B.pairs + 8 * row : nullptr;
        D4 t[kT], q0[kVar ? kT : 1], q1[kVar ? kT : 1];
        for (int i = 0; i < kT; ++i) {
            t[i] = load4(sums + 4 * (i - kM));
            if constexpr (kVar) q0[i] = load4(pairs + 8 * (i - kM)), q1[i] = load4(pairs + 8 * (i - kM) + 4);
        }
        for (int k = 0; k < n; ++k) {
            const D4 a_row = ra[k][j + kM], b_row = rb[k][j + kM];
            for (int i = 0; i < kT; ++i) {
                const D4 b = b_row * cx[k][1][i];
                t[i] = (t[i] + a_row * cx[k][0][i]) + b;
                if constexpr (kVar) {
                    if (!has_a[k]) continue;
                    const D4 d = b - pa[k][j + kM] * cx[k][0][i];
                    q0[i] = q0[i] + d * d;
                    q1[i] = q1[i] + d * d[0];
                }
            }
        }
        for (int i = 0; i < kT; ++i) {
            store4(sums + 4 * (i - kM), t[i]);
            if constexpr (kVar) store4(pairs + 8 * (i - kM), q0[i]), store4(pairs + 8 * (i - kM) + 4, q1[i]);
        }
    }
}

// A batch: the fixed-bound block for margins 1 and 2 inside the film, else one trimmed
// accumulation after the other.
template <bool kVar>
__attribute__((always_inline)) inline void accumulate_batch_var(const AccumulateBatch& B) {
    const bool inside = B.x >= B.m && B.y >= B.m && B.x + B.m < B.width && B.y + B.m < B.height;
    if (inside && B.m == 2) return accumulate_block<2, kVar>(B);
    if (inside && B.m == 1) return accumulate_block<1, kVar>(B);
    for (int k = 0; k < B.n; ++k) {
        const AccumulateArgs a{B.sums, B.pairs, B.width, B.height, B.x, B.y, B.m, B.w + 4 * k, B.la[k], B.add_a[k], B.L[k]};
        accumulate_impl<kVar>(a);
    }
}
// With the pair sums (B.pairs set) or without them.
__attribute__((always_inline)) inline void accumulate_batch(const AccumulateBatch& B) {
    if (B.pairs) accumulate_batch_var<true>(B);
    else accumulate_batch_var<false>(B);
}
}  // namespace

// The variants of the accumulation (film.h, AccumulationVariant): on x86-64 with GCC, baseline and
// AVX2 (a four-double vector in one register), chosen once per film from the CPU; elsewhere the
// baseline only.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define PELLUCID_FILM_X86_VARIANTS 1
#endif

namespace {
void accumulate_baseline(const AccumulateBatch& b) { accumulate_batch(b); }
#ifdef PELLUCID_FILM_X86_VARIANTS
__attribute__((target("avx2"))) void accumulate_avx2(const AccumulateBatch& b) { accumulate_batch(b); }
#endif
}  // namespace

// Job k of n adds sample b (weights w[·][4k + 2], w[·][4k + 3], value *L) to the sums of every
// target pixel; with a partner a (weights w[·][4k], w[·][4k + 1], value la, where has_a) also the
// pair's differences, and a itself first if add_a. The sums are updated in the order a,
// then b, accumulation after accumulation, so a pair gives the bits of two single calls and a batch
// those of its accumulations one by one. Every variant does the same IEEE operations per element, in
// the same order (no contraction: -ffp-contract=off), so all give the same bits.
void Film::accumulate(int x, int y, int m, const float* w, int n, const SplatJob* jobs) {
    static_assert(sizeof(SplatSums) == 4 * sizeof(double) && sizeof(SplatPairSums) == 8 * sizeof(double));
    AccumulateBatch b{reinterpret_cast<double*>(m_sums.data()),
                      m_variance ? reinterpret_cast<double*>(m_pair_sums.data()) : nullptr,
                      m_width, m_height, x, y, m, n, w, {}, {}, {}};
    for (int k = 0; k < n; ++k) {
        b.la[k] = jobs[k].has_a ? jobs[k].la : nullptr, b.add_a[k] = jobs[k].add_a;
        for (int c = 0; c < 3; ++c) b.L[k][c] = (*jobs[k].L)[c];
    }
#ifdef PELLUCID_FILM_X86_VARIANTS
    if (m_variant == AccumulationVariant::AVX2) return accumulate_avx2(b);
#endif
    accumulate_baseline(b);
}

std::vector<Film::AccumulationVariant> Film::accumulation_variants() {
    std::vector<AccumulationVariant> v{AccumulationVariant::Baseline};
#ifdef PELLUCID_FILM_X86_VARIANTS
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx2")) v.push_back(AccumulationVariant::AVX2);
#endif
    return v;
}

void Film::set_accumulation_variant(AccumulationVariant v) {
    const std::vector<AccumulationVariant> ok = accumulation_variants();
    if (std::find(ok.begin(), ok.end(), v) == ok.end())
        throw Error("Film: accumulation variant " + std::to_string(int(v)) + " is not available on this CPU");
    m_variant = v;
}

void Film::pixel_stats(size_t i, double mean[3], double var[3]) const {
    if (!splats()) {
        const Pixel& p = m_pixels[i];
        for (int k = 0; k < 3; ++k) {
            mean[k] = p.mean[k];
            var[k] = p.n > 1 ? p.m2[k] / double(p.n - 1) / double(p.n) : 0.0;
        }
        return;
    }
    const double* sum = m_sums[i].v;
    const uint64_t n = m_sources[i].n;
    const double w = sum[0];
    if (!(w > 0.0)) {
        for (int k = 0; k < 3; ++k) mean[k] = var[k] = 0.0;
        return;
    }
    if (!m_variance) {
        for (int k = 0; k < 3; ++k) mean[k] = sum[k + 1] / w, var[k] = 0.0;
        return;
    }
    const SplatPairSums& q = m_pair_sums[i];
    // ⌊n/2⌋ pairs of each stratum estimate 2⌊n/2⌋ Var_q; its share of Var(Σ z) is n Var_q (film.h).
    const double scale = n > 1 ? double(n) / (2.0 * double(n / 2)) / (w * w) : 0.0;
    for (int k = 0; k < 3; ++k) {
        const double r = sum[k + 1] / w;
        const double s = q.sq[k + 1] - 2.0 * r * q.cr[k + 1] + r * r * q.sq[0];  // Σ (Δ(wL) − R Δw)²
        mean[k] = r;
        var[k] = std::max(0.0, s) * scale;
    }
}

Image Film::mean() const {
    Image img(m_width, m_height, 3);
    double m[3], v[3];
    for (size_t i = 0; i < size_t(m_width) * m_height; ++i) {
        pixel_stats(i, m, v);
        for (int k = 0; k < 3; ++k) img.data[3 * i + k] = float(m[k]);
    }
    return img;
}

Image Film::variance() const {
    if (!has_variance()) throw Error("Film: this film keeps no variance (it was made with variance off)");
    Image img(m_width, m_height, 3);
    double m[3], v[3];
    for (size_t i = 0; i < size_t(m_width) * m_height; ++i) {
        pixel_stats(i, m, v);
        for (int k = 0; k < 3; ++k) img.data[3 * i + k] = float(v[k]);
    }
    return img;
}

double Film::mean_relative_variance() const {
    if (!has_variance()) throw Error("Film: this film keeps no variance (it was made with variance off)");
    double sum = 0.0, m[3], v[3];
    const size_t n = size_t(m_width) * m_height;
    for (size_t i = 0; i < n; ++i) {
        if ((splats() ? m_sources[i].n : m_pixels[i].n) < 2) return 1e30;
        pixel_stats(i, m, v);
        double lm = 0.2126 * m[0] + 0.7152 * m[1] + 0.0722 * m[2];
        double lv = 0.2126 * v[0] + 0.7152 * v[1] + 0.0722 * v[2];
        sum += lv / (lm * lm + 1e-4);
    }
    return sum / double(n);
}

// ---- film state files (docs/rendering.md, "Film state files") ----------------------------------
namespace {
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "film state files are little-endian");
constexpr char kStateMagic[8] = {'P', 'L', 'C', 'D', 'F', 'I', 'L', 'M'};
constexpr uint32_t kStateVersion = 2;  // version 1: no variance byte, pair sums always
constexpr uint32_t kMaxStateSide = 1u << 16;
constexpr uint32_t kMaxStateString = 1u << 16;

uint64_t fnv1a(const char* p, size_t n) {
    uint64_t h = 1469598103934665603ull;
    for (size_t i = 0; i < n; ++i) h = (h ^ uint64_t(uint8_t(p[i]))) * 1099511628211ull;
    return h;
}

class Writer {
public:
    template <class T>
    void put(T v) {
        char b[sizeof(T)];
        std::memcpy(b, &v, sizeof(T));
        buf.append(b, sizeof(T));
    }
    template <class T, size_t N>
    void put(const T (&a)[N]) {
        for (const T& v : a) put(v);
    }
    void put_string(const std::string& s) {
        put(uint32_t(s.size()));
        buf += s;
    }
    std::string buf;
};

class Reader {
public:
    Reader(const std::string& path, const std::string& data) : m_path(path), m_data(data) {}
    template <class T>
    T get(const char* what) {
        need(sizeof(T), what);
        T v;
        std::memcpy(&v, m_data.data() + m_pos, sizeof(T));
        m_pos += sizeof(T);
        return v;
    }
    template <class T, size_t N>
    void get(T (&a)[N], const char* what) {
        for (T& v : a) v = get<T>(what);
    }
    std::string get_string(const char* what) {
        uint32_t n = get<uint32_t>(what);
        if (n > kMaxStateString) fail(std::string(what) + ": string of " + std::to_string(n) + " bytes");
        need(n, what);
        std::string s = m_data.substr(m_pos, n);
        m_pos += n;
        return s;
    }
    void need(size_t n, const char* what) const {
        if (m_data.size() - m_pos < n)
            fail(std::string("truncated film state file (ends inside ") + what + ", at byte " + std::to_string(m_pos) +
                 " of " + std::to_string(m_data.size()) + ")");
    }
    [[noreturn]] void fail(const std::string& msg) const { throw Error(m_path + ": " + msg); }
    size_t pos() const { return m_pos; }

private:
    const std::string& m_path;
    const std::string& m_data;
    size_t m_pos = 0;
};

// Filter: type (0 box, 1 tent, 2 gaussian), its size parameter (radius or stddev), shift flag.
void put_filter(Writer& w, const Filter& f) {
    if (const auto* b = std::get_if<BoxFilter>(&f)) {
        w.put(uint8_t(0)), w.put(uint8_t(0)), w.put(b->radius);
    } else if (const auto* t = std::get_if<TentFilter>(&f)) {
        w.put(uint8_t(1)), w.put(uint8_t(0)), w.put(t->radius);
    } else {
        const auto& g = std::get<GaussianFilter>(f);
        w.put(uint8_t(2)), w.put(uint8_t(g.shift ? 1 : 0)), w.put(g.stddev);
    }
}
Filter get_filter(Reader& r) {
    const uint8_t type = r.get<uint8_t>("filter"), shift = r.get<uint8_t>("filter");
    const float size = r.get<float>("filter");
    if (!(size > 0.f && size <= 16.f)) r.fail("filter size " + std::to_string(size) + " is outside (0, 16]");
    switch (type) {
        case 0: return BoxFilter{size};
        case 1: return TentFilter{size};
        case 2: return GaussianFilter(size, shift != 0);
        default: r.fail("unknown filter type " + std::to_string(type));
    }
}
}  // namespace

void save_film_state(const std::string& path, const FilmState& st) {
    const Film& f = st.film;
    Writer w;
    w.buf.append(kStateMagic, sizeof(kStateMagic));
    w.put(kStateVersion);
    w.put(uint32_t(f.m_width)), w.put(uint32_t(f.m_height));
    w.put(uint8_t(f.splats() ? 1 : 0));
    w.put(uint8_t(f.has_variance() ? 1 : 0));
    put_filter(w, st.filter);
    w.put(uint32_t(st.spp));
    w.put(st.seed);
    w.put(st.invalid_samples);
    w.put(st.seconds);
    w.put_string(st.sampler);
    w.put_string(st.integrator);
    if (f.splats()) {
        for (size_t i = 0; i < f.m_sums.size(); ++i) {
            const double* v = f.m_sums[i].v;
            const Film::SplatSource& p = f.m_sources[i];
            const double wl[3] = {v[1], v[2], v[3]};
            w.put(wl), w.put(v[0]);
            if (f.m_variance) {
                const Film::SplatPairSums& q = f.m_pair_sums[i];
                const double dl2[3] = {q.sq[1], q.sq[2], q.sq[3]}, dldw[3] = {q.cr[1], q.cr[2], q.cr[3]};
                w.put(dl2), w.put(dldw), w.put(q.sq[0]);
            }
            w.put(p.n);
            w.put(p.last_fx), w.put(p.last_fy), w.put(p.last_l);
        }
    } else {
        for (const Film::Pixel& p : f.m_pixels) w.put(p.mean), w.put(p.m2), w.put(p.n);
    }
    w.put(fnv1a(w.buf.data(), w.buf.size()));

    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path parent = fs::path(path).parent_path();
    if (!parent.empty()) fs::create_directories(parent, ec);
    const std::string tmp = path + ".part";
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) throw Error(path + ": cannot open film state file for writing");
        out.write(w.buf.data(), std::streamsize(w.buf.size()));
        if (!out.flush()) throw Error(path + ": cannot write film state file");
    }
    fs::rename(tmp, path, ec);
    if (ec) {
        fs::remove(tmp, ec);
        throw Error(path + ": cannot write film state file (rename failed)");
    }
}

std::shared_ptr<FilmState> load_film_state(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot open film state file (does it exist?)");
    const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    Reader r(path, data);
    r.need(sizeof(kStateMagic), "the header");
    if (std::memcmp(data.data(), kStateMagic, sizeof(kStateMagic)) != 0)
        r.fail("not a pellucid film state file (it does not start with \"PLCDFILM\")");
    for (size_t i = 0; i < sizeof(kStateMagic); ++i) r.get<char>("the header");
    const uint32_t version = r.get<uint32_t>("the header");
    if (version != kStateVersion && version != 1)
        r.fail("film state version " + std::to_string(version) + " is not supported (this build reads versions 1 and " +
               std::to_string(kStateVersion) + ")");
    const uint32_t width = r.get<uint32_t>("the header"), height = r.get<uint32_t>("the header");
    if (width < 1 || height < 1 || width > kMaxStateSide || height > kMaxStateSide)
        r.fail("film size " + std::to_string(width) + "x" + std::to_string(height) + " is out of range");
    const uint8_t splat = r.get<uint8_t>("the header");
    if (splat > 1) r.fail("unknown reconstruction " + std::to_string(splat));
    const uint8_t variance = version == 1 ? 1 : r.get<uint8_t>("the header");
    if (variance > 1) r.fail("variance flag " + std::to_string(variance) + " is not 0 or 1");
    if (!variance && !splat) r.fail("a filter-sampling film without variance");
    Filter filter = get_filter(r);
    const uint32_t spp = r.get<uint32_t>("the header");
    if (spp > (1u << 24)) r.fail("spp " + std::to_string(spp) + " is out of range [0, 16777216]");
    auto st = std::make_shared<FilmState>(FilmState{
        Film(int(width), int(height), splat ? std::optional<Filter>(filter) : std::nullopt, variance == 1), filter, int(spp),
        0, "", "", 0, 0.0});
    if (st->film.splats() != (splat == 1)) r.fail("a splatting film with a one-pixel box filter");
    st->seed = r.get<uint64_t>("the header");
    st->invalid_samples = r.get<uint64_t>("the header");
    st->seconds = r.get<double>("the header");
    st->sampler = r.get_string("the sampler name");
    st->integrator = r.get_string("the integrator");
    const size_t record = splat ? (variance ? 11 : 4) * 8 + 8 + 5 * 4 : 6 * 8 + 8;
    r.need(size_t(width) * height * record + 8, "the pixels");
    Film& f = st->film;
    if (splat) {
        for (size_t i = 0; i < f.m_sums.size(); ++i) {
            double* v = f.m_sums[i].v;
            Film::SplatSource& p = f.m_sources[i];
            double wl[3];
            r.get(wl, "pixels"), v[0] = r.get<double>("pixels");
            for (int k = 0; k < 3; ++k) v[k + 1] = wl[k];
            if (variance) {
                Film::SplatPairSums& q = f.m_pair_sums[i];
                double dl2[3], dldw[3];
                r.get(dl2, "pixels"), r.get(dldw, "pixels");
                q.sq[0] = q.cr[0] = r.get<double>("pixels");
                for (int k = 0; k < 3; ++k) q.sq[k + 1] = dl2[k], q.cr[k + 1] = dldw[k];
            }
            p.n = r.get<uint64_t>("pixels");
            p.last_fx = r.get<float>("pixels"), p.last_fy = r.get<float>("pixels"), r.get(p.last_l, "pixels");
        }
    } else {
        for (Film::Pixel& p : f.m_pixels) r.get(p.mean, "pixels"), r.get(p.m2, "pixels"), p.n = r.get<uint64_t>("pixels");
    }
    const size_t body = r.pos();
    const uint64_t sum = r.get<uint64_t>("the checksum");
    if (r.pos() != data.size())
        r.fail(std::to_string(data.size() - r.pos()) + " unexpected bytes after the checksum");
    if (sum != fnv1a(data.data(), body)) r.fail("checksum mismatch: the film state file is corrupt");
    if (st->sampler != "independent" && st->sampler != "sobol") r.fail("unknown sampler '" + st->sampler + "'");
    return st;
}
}  // namespace pellucid
