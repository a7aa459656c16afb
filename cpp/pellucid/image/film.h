// Film: per-pixel accumulation in double precision that also estimates the variance of every
// pixel's estimate. Two reconstructions of the filtered image:
//  - filter sampling (default): one sample, one pixel, weight 1; running mean and variance by
//    Welford 1962, exact for independent samples;
//  - splatting: each sample is added to every pixel within the filter radius with weight w = f(Δx)f(Δy)
//    and the pixel is the ratio R = Σ wL / Σ w (Mitsuba 3's ImageBlock). Neighbouring samples share
//    pixels, so per-pixel noise is lower at equal spp (neighbouring pixels are correlated instead).
//    A box of radius ½ splats every sample into its own pixel with weight 1, which is filter
//    sampling: the film then does exactly that (as Mitsuba 3's ImageBlock, which drops that filter).
//
// The variance of a splatted pixel. To first order (the delta method; Cochran 1977, Sampling
// Techniques, §6.3) R − R₀ ≈ Σ_j z_j / E[Σ w] with z_j = w_j (L_j − R₀), so Var R ≈ Var(Σ z) / (Σ w)².
// The samples are not one i.i.d. population: every pixel q of the footprint contributes its own n_q
// samples, uniform in q, so the sample positions are stratified by pixel and the weights w are random
// within each stratum. Hence Var(Σ z) = Σ_q n_q Var_q(z), the within-stratum variances only
// (Cochran 1977, eq. 5.3). The i.i.d. estimate Σ z_j² also counts the spread of the stratum means
// E_q[z] (an image with an edge but no noise at all would get a large variance) and overestimates
// (by 40 % in the median on an edge-only image). The film estimates each Var_q from pairs within
// the stratum: a pixel's samples 2i and 2i + 1 are i.i.d., so E[(z_b − z_a)²] = 2 Var_q(z), whatever
// the weights and the values do (with the sobol sampler the pair is stratified and the estimate is
// conservative, as Welford's is for filter sampling). Each source pixel keeps its last sample; the second sample of a
// pair adds, in each target pixel, the pair's differences Δ(wL) and Δw (second minus first, of
// w L and of w there) to Σ Δ(wL)², Σ Δ(wL)Δw and Σ Δw², from which
// Σ (Δz)² = Σ Δ(wL)² − 2R Σ Δ(wL)Δw + R² Σ Δw² (R₀ ≈ R), and
//    Var R ≈ n/(2⌊n/2⌋) · Σ (Δz)² / (Σ w)²,
// n the samples per pixel (⌊n/2⌋ pairs per stratum; exact when all pixels of the footprint have n
// samples, as after every complete pass). Pixels with fewer than 2 samples report 0, as with filter
// sampling. Pairs cost what the i.i.d. sums cost (the first sample of a pair updates only Σ w and
// Σ wL); successive differences (von Neumann et al. 1941) would use about a third more of the
// information but cost about 40 % more per splat.
//
// Cost. A pair of samples is added in one pass over its target pixels. The column and row weights
// of four pairs come from one eval_filter_taps16 call (sixteen rows side by side, two vector
// exponentials; image/filter.h; AVX-512 where the CPU has it, the same bits everywhere). Away
// from the border, margins 1 and 2 (σ = ½: 5 taps) update their whole (2m + 1)² block with fixed
// loop bounds, which costs less than trimming its zero rows and columns with loops whose length
// changes from pair to pair (a zero weight adds nothing), and each target's sums are loaded once,
// updated by the four pairs in order and stored once (the bits of one pair after the other); a
// sample's update of a target there is one multiply and one add, ((1, L)·wy)·wx with the row's
// vector formed once per row (as (1, L)·wy and wx·wy are exact in double, the same bits as
// (1, L)·(wx·wy); 0.95 of env_diffuse's render time, bench/README.md);
// elsewhere the pairs go one by one, trimmed to the film. The accumulation is compiled for the
// baseline and, on x86-64, for AVX2; a film takes the widest the CPU runs (accumulation_variants;
// the same bits). A variant with AVX-512 vectors (a target's pair sums in one register) measured
// slower than AVX2 on our Zen 5 machine, so none is built. Trimming a pair's block to its nonzero
// taps (4 or 5 columns and rows with σ = ½, nine fixed-size variants chosen per pair) also measured
// slower: the choice depends on each pair's positions and mispredicts. The renderer splats up to 16
// samples per pixel and pass (splat_pass_spp, render_loop.cpp), so splat_pixel receives up to
// eight pairs at a time, two batches of four. Tests:
// tests/cpp/image/test_film_splat.cpp, tests/cpp/image/test_filter.cpp.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "pellucid/image/filter.h"
#include "pellucid/image/image.h"
#include "pellucid/math/spectrum.h"

namespace pellucid {
struct FilmState;

/// One camera sample's estimate and where in the film it was taken (pixel units).
struct FilmSample {
    Spectrum L;
    float fx, fy;
};

class Film {
public:
    /// splat: the filter to splat with, or nullopt for filter sampling (add_sample). A box of radius
    /// ½ is filter sampling (splats() is then false).
    /// variance = false: a splatting film keeps no pair sums, so it gives the mean only (variance()
    /// and mean_relative_variance() throw); its splats update 4 doubles a target instead of 12, and
    /// its mean is the same, bit for bit. A filter-sampling film always keeps Welford's sums (they cost little).
    Film(int width, int height, std::optional<Filter> splat = std::nullopt, bool variance = true);
    int width() const { return m_width; }
    int height() const { return m_height; }
    bool splats() const { return m_splat.has_value(); }
    /// Whether the film estimates each pixel's variance (always, without splatting).
    bool has_variance() const { return !splats() || m_variance; }
    /// How many pixels beyond its own a splat reaches (0 without splatting). Tiles closer than
    /// this must not be rendered at the same time (render_loop colours them).
    int splat_margin() const { return m_margin; }

    /// Add one sample of pixel (x, y). Not thread-safe for the same pixel; tiles own their pixels.
    void add_sample(int x, int y, const Spectrum& L) {
        Pixel& p = m_pixels[size_t(y) * m_width + x];
        p.n += 1;
        double inv_n = 1.0 / double(p.n);
        for (int k = 0; k < 3; ++k) {
            double d = double(L[k]) - p.mean[k];
            p.mean[k] += d * inv_n;
            p.m2[k] += d * (double(L[k]) - p.mean[k]);
        }
    }
    /// Splat one sample taken at film position (fx, fy) (pixel units) inside pixel (x, y) to every
    /// pixel whose centre lies within the filter radius. Writes pixels up to splat_margin() away.
    /// Without a splat filter (splats() false) it is add_sample(x, y, L).
    void splat(int x, int y, float fx, float fy, const Spectrum& L);
    /// The n samples taken inside pixel (x, y), in order: the same sums, bit for bit, as n calls of
    /// splat(), but each pair of samples is added in one pass over its target pixels. Sample values
    /// must be finite (the renderer drops the others first).
    void splat_pixel(int x, int y, const FilmSample* s, int n);

    /// Per-pixel estimate, float RGB.
    Image mean() const;
    /// Per-pixel variance of that estimate, float RGB. Throws pellucid::Error without has_variance().
    Image variance() const;
    /// Camera samples taken inside pixel (x, y).
    uint64_t samples(int x, int y) const {
        size_t i = size_t(y) * m_width + x;
        return splats() ? m_sources[i].n : m_pixels[i].n;
    }
    /// Mean over pixels of the relative variance of each pixel's estimate, Var/(mean²+1e-4), on
    /// luminance; the quantity target_rel_error drives to e². The luminance variance is the weighted
    /// sum of channel variances, ignoring cross-channel covariance: a stopping estimate, not a
    /// statistic tests rely on. Throws pellucid::Error without has_variance().
    double mean_relative_variance() const;

    /// The splat filter (nullopt for filter sampling).
    const std::optional<Filter>& splat_filter() const { return m_splat; }

    /// The instruction-set variants of the splatting accumulation (film.cpp). All give the same
    /// sums, bit for bit; a film uses the widest this CPU runs, or the baseline where the
    /// environment variable PELLUCID_FILM_ACCUMULATION is `baseline` (for profilers that do not
    /// decode the AVX2 variant).
    enum class AccumulationVariant { Baseline, AVX2 };
    /// The variants this build and CPU run, narrowest first (Baseline always).
    static std::vector<AccumulationVariant> accumulation_variants();
    /// Use variant v from now on (tests compare them). Throws pellucid::Error if it is not available.
    void set_accumulation_variant(AccumulationVariant v);
    AccumulationVariant accumulation_variant() const { return m_variant; }

private:
    friend void save_film_state(const std::string& path, const FilmState& state);
    friend std::shared_ptr<FilmState> load_film_state(const std::string& path);
    struct Pixel {
        double mean[3] = {0, 0, 0};
        double m2[3] = {0, 0, 0};
        uint64_t n = 0;
    };
    // A splatting film keeps three arrays, so that the first sample of a pair touches only the
    // 32 bytes of SplatSums in each target pixel, and both are laid out as 4-vectors (Σw first,
    // then the three channels) that the compiler updates with packed arithmetic; aligned to their
    // size, so that no vector straddles a cache line.
    struct alignas(32) SplatSums {  // as a target: sums over the samples splatted here
        double v[4] = {0, 0, 0, 0};  ///< Σ w, Σ w L (channels 0..2)
    };
    struct alignas(64) SplatPairSums {  // sums over the pairs of samples within each source pixel
        double sq[4] = {0, 0, 0, 0};  ///< Σ Δw², Σ Δ(wL)² (Δ = second − first)
        double cr[4] = {0, 0, 0, 0};  ///< Σ Δw·Δw (unused: sq[0]), Σ Δ(wL)·Δw
    };
    struct SplatSource {            // as a source: the samples taken in this pixel and the last of them
        uint64_t n = 0;
        float last_fx = 0, last_fy = 0, last_l[3] = {0, 0, 0};
    };
    // One accumulation of splat_pixel: sample b at (bfx, bfy) with value *L, and its partner a at
    // (afx, afy) with value la where has_a (add_a: a is added to the sums here too; without a
    // partner, a is b's own position).
    struct SplatJob {
        float afx, afy, bfx, bfy;
        float la[3];
        bool has_a, add_a;
        const Spectrum* L;
    };
    // n ≤ 4 accumulations at pixel (x, y), in order; job k's weights (a column, a row, b column,
    // b row) of tap t at w + 16 t + 4 k (eval_filter_taps16's rows).
    void accumulate(int x, int y, int m, const float* w, int n, const SplatJob* jobs);
    // Estimate and variance of pixel i, channel k.
    void pixel_stats(size_t i, double mean[3], double var[3]) const;

    int m_width, m_height;
    std::optional<Filter> m_splat;
    int m_margin = 0;
    std::vector<Pixel> m_pixels;      // filter sampling
    std::vector<SplatSums> m_sums;          // splatting
    std::vector<SplatPairSums> m_pair_sums;  // empty without variance
    bool m_variance = true;
    std::vector<SplatSource> m_sources;
    AccumulationVariant m_variant;
};

/// A film and what a render needs to continue it (`--resume`, `render(..., resume=...)`): the
/// accumulators after `spp` complete passes, so every pixel holds exactly `spp` samples, and the
/// settings that must not change between the two parts of a render. Saved as the binary state file
/// described in docs/rendering.md ("Film state files").
struct FilmState {
    Film film;
    Filter filter;            ///< the scene's pixel filter (sampled or splatted)
    int spp = 0;              ///< samples per pixel in every pixel
    uint64_t seed = 0;        ///< the render's seed
    std::string sampler;      ///< "independent" | "sobol"
    std::string integrator;   ///< Integrator::to_string() of the render ("" = not recorded)
    uint64_t invalid_samples = 0;  ///< NaN/Inf/negative samples dropped so far
    double seconds = 0.0;     ///< render time so far
};

/// Write `state` to `path` (written to a temporary file next to it, then renamed, so an
/// interrupted write never leaves a truncated state file). Throws pellucid::Error naming the path.
void save_film_state(const std::string& path, const FilmState& state);
/// Read a state file written by save_film_state. Throws pellucid::Error naming the path and what is
/// wrong (not a state file, another version, truncated, corrupt).
std::shared_ptr<FilmState> load_film_state(const std::string& path);
}  // namespace pellucid
