// Per-camera-sample random numbers: i.i.d. PCG32 ("independent") or shuffled, Owen-scrambled Sobol
// ("sobol"; Burley 2020, "Practical Hash-based Owen Scrambling", JCGT 9(4)).
// SPDX-License-Identifier: Apache-2.0
//
// A Sampler is made for one (pixel, sample index, seed) and hands out the sample's dimensions in
// order. The integrator places its dimensions explicitly with set_dimension() (integrator/path.cpp
// documents its layout), so that a given dimension means the same decision in every sample of a
// pixel whichever branches ran: that is what keeps the Sobol points of one decision stratified.
//
// "sobol" follows Burley 2020 (the scheme Cycles calls "sobol-burley"):
// * every request (get_pixel_2d, get_1d, get_2d) is one dimension group and uses the first one or two
//   dimensions of the Sobol sequence, which form a (0,2)-sequence in base 2 (Joe & Kuo 2008
//   direction numbers; §2 of the paper);
// * the sample index is shuffled per (pixel, group) by a nested uniform (Owen) scramble of the index
//   (§4, Listing 5 "shuffled_scrambled_sobol"): any prefix of 2^k indices maps onto an aligned block
//   of 2^k Sobol indices, so prefixes stay (0,k,2)-nets, and groups are decorrelated ("padding", §5);
// * every output dimension gets its own nested uniform scramble (§3, Listings 2–4), computed with a
//   hash that, on bit-reversed integers, flips each bit as a function of the bits below it only: the
//   Laine–Karras construction, here with Vegdahl's 2021 constants ("Building a Better LK Hash").
// After kMaxSobolDims dimensions the sampler falls back to the sample's PCG32 stream (deep bounces
// gain little from stratification).
//
// "independent" is the PCG32 stream PCG32::for_sample(pixel, sample index, seed), consumed in call
// order: set_dimension() is a no-op for it, so images are bit-identical to the pre-Sampler renderer.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#if defined(__GFNI__) && defined(__SSE2__)
#include <immintrin.h>
#endif

#include "pellucid/math/vec.h"
#include "pellucid/sampling/rng.h"
#include "pellucid/util/error.h"

namespace pellucid {

enum class SamplerType : uint8_t { Independent, Sobol };

inline const char* to_string(SamplerType t) { return t == SamplerType::Sobol ? "sobol" : "independent"; }

/// "independent" | "sobol"; anything else throws pellucid::Error naming `what` and the known types.
inline SamplerType parse_sampler_type(const std::string& name, const std::string& what = "sampler") {
    if (name == "independent") return SamplerType::Independent;
    if (name == "sobol") return SamplerType::Sobol;
    throw Error(what + ": unknown sampler '" + name + "' (known: independent, sobol)");
}

namespace sobol {

/// The bits of x in reverse order. With GFNI (x86), one affine transform over GF(2) reverses the
/// bits of each byte (the matrix is the anti-diagonal 0x8040201008040201) and a byte swap does the
/// rest; otherwise five swap steps of halves, quarters, ... (Always inlined: a copy emitted in a
/// kernel object, built for its instruction set, must not stand in for other objects' calls.)
[[gnu::always_inline]] inline uint32_t reverse_bits(uint32_t x) {
#if defined(__GFNI__) && defined(__SSE2__)
    const __m128i v = _mm_gf2p8affine_epi64_epi8(_mm_cvtsi32_si128(int(x)), _mm_set1_epi64x(0x8040201008040201LL), 0);
    return __builtin_bswap32(uint32_t(_mm_cvtsi128_si32(v)));
#else
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    x = ((x >> 4) & 0x0F0F0F0Fu) | ((x & 0x0F0F0F0Fu) << 4);
    x = ((x >> 8) & 0x00FF00FFu) | ((x & 0x00FF00FFu) << 8);
    return (x >> 16) | (x << 16);
#endif
}

/// Owen scramble of a bit-reversed integer: bit j of the result is bit j of x flipped by a
/// function of bits 0..j-1 of x and the seed (multiplication by an even constant, addition and
/// multiplication by an odd number only carry upward). Burley 2020 §3 (the Laine–Karras
/// permutation, Listing 2); constants from Vegdahl 2021, which randomises the high bits better.
[[gnu::always_inline]] inline uint32_t owen_scramble_reversed(uint32_t x, uint32_t seed) {
    x ^= x * 0x3d20adeau;
    x += seed;
    x *= (seed >> 16) | 1u;
    x ^= x * 0x05526c56u;
    x ^= x * 0x53a22864u;
    return x;
}

/// Nested uniform scramble of a 32-bit fixed-point value (Burley 2020, Listing 3): bit i (counted
/// from the most significant) flips as a function of the bits above it, as in Owen 1995.
inline uint32_t nested_uniform_scramble(uint32_t x, uint32_t seed) {
    return reverse_bits(owen_scramble_reversed(reverse_bits(x), seed));
}

constexpr int kDimensions = 4;  ///< Sobol dimensions tabulated (Burley's 4D sets)

/// Direction numbers V_k = m_k · 2^(32-k) of the first four Sobol dimensions, from the primitive
/// polynomials and initial m_k of Joe & Kuo 2008 (new-joe-kuo-6.21201: dimension 1 is the van der
/// Corput sequence; then s=1 a=0 m=1; s=2 a=1 m=1,3; s=3 a=1 m=1,3,1) and the Bratley–Fox
/// recurrence V_k = V_{k-s} ⊕ (V_{k-s} >> s) ⊕ ⊕_{j<s} a_j V_{k-j}.
struct Directions {
    uint32_t v[kDimensions][32];
};
constexpr Directions make_directions() {
    Directions d{};
    for (int k = 0; k < 32; ++k) d.v[0][k] = 1u << (31 - k);
    const int s[3] = {1, 2, 3};
    const uint32_t a[3] = {0, 1, 1};
    const uint32_t m[3][3] = {{1, 0, 0}, {1, 3, 0}, {1, 3, 1}};
    for (int dim = 1; dim < kDimensions; ++dim) {
        const int deg = s[dim - 1];
        uint32_t* v = d.v[dim];
        for (int k = 0; k < deg; ++k) v[k] = m[dim - 1][k] << (31 - k);
        for (int k = deg; k < 32; ++k) {
            uint32_t x = v[k - deg] ^ (v[k - deg] >> deg);
            for (int j = 1; j < deg; ++j)
                if ((a[dim - 1] >> (deg - 1 - j)) & 1u) x ^= v[k - j];
            v[k] = x;
        }
    }
    return d;
}
inline constexpr Directions kDirections = make_directions();

/// Unscrambled Sobol point `index` in dimension `dim` < kDimensions, as 32-bit fixed point.
inline uint32_t sample_bits(uint32_t index, int dim) {
    uint32_t x = 0;
    for (int k = 0; index; index >>= 1, ++k)
        if (index & 1u) x ^= kDirections.v[dim][k];
    return x;
}

/// Sobol dimension 1 of index i, bit-reversed, in five shift-xor steps instead of a 32-step table
/// walk. Its generator matrix is Pascal's triangle mod 2 (V_k has bit 31 − j set iff C(k−1, j) is
/// odd, see make_directions), and by Lucas' theorem C(n, j) is odd iff the bits of j are a subset of
/// those of n. So bit j of the reversed result is the parity of the bits n ⊇ j of i: a superset-sum
/// (zeta) transform over GF(2), one step per bit of the position index.
inline uint32_t dim1_reversed(uint32_t i) {
    i ^= (i >> 1) & 0x55555555u;
    i ^= (i >> 2) & 0x33333333u;
    i ^= (i >> 4) & 0x0F0F0F0Fu;
    i ^= (i >> 8) & 0x00FF00FFu;
    i ^= (i >> 16) & 0x0000FFFFu;
    return i;
}

/// 32-bit fixed point to a float in [0, 1): the top 24 bits are exact in a float, so never 1.
inline float to_float(uint32_t x) { return float(x >> 8) * 0x1p-24f; }

/// One dimension group's seeds: the index shuffle and one scramble per output dimension.
struct GroupSeeds {
    uint32_t shuffle, scramble[2];
};
inline GroupSeeds group_seeds(uint64_t pixel_hash, uint32_t group) {
    uint64_t h0 = mix_bits(pixel_hash ^ (uint64_t(group) + 1) * 0x9E3779B97F4A7C15ULL);
    uint64_t h1 = mix_bits(h0 + 0xD1B54A32D192ED03ULL);
    return {uint32_t(h0), {uint32_t(h0 >> 32), uint32_t(h1)}};
}

/// Shuffled, scrambled Sobol (Burley 2020, Listing 5) in Sobol dimension `dim` of one group: the
/// definition, with the table (the sampler uses the equal, faster sample_2d; tests compare them).
inline uint32_t shuffled_scrambled(uint32_t index, int dim, const GroupSeeds& g) {
    uint32_t i = nested_uniform_scramble(index, g.shuffle);
    return nested_uniform_scramble(sample_bits(i, dim), g.scramble[dim]);
}

/// shuffled_scrambled in dimensions 0 and 1 without the table and with the bit reversals that
/// cancel removed: Sobol dimension 0 of i is reverse_bits(i), so nested_uniform_scramble of it is
/// reverse_bits(owen_scramble_reversed(i)); dimension 1 comes bit-reversed from dim1_reversed.
inline void sample_2d_rev(uint32_t index_reversed, const GroupSeeds& g, uint32_t* x0, uint32_t* x1) {
    const uint32_t i = reverse_bits(owen_scramble_reversed(index_reversed, g.shuffle));
    *x0 = reverse_bits(owen_scramble_reversed(i, g.scramble[0]));
    if (x1) *x1 = reverse_bits(owen_scramble_reversed(dim1_reversed(i), g.scramble[1]));
}
/// sample_2d_rev of reverse_bits(index) (the Sampler reverses its index once).
inline void sample_2d(uint32_t index, const GroupSeeds& g, uint32_t* x0, uint32_t* x1) {
    sample_2d_rev(reverse_bits(index), g, x0, x1);
}
}  // namespace sobol

/// The random numbers of one camera sample. A value type: no allocation, no virtual calls.
class Sampler {
public:
    /// Sobol dimensions per sample; later dimensions come from the sample's PCG32 stream.
    static constexpr int kMaxSobolDims = 64;
    /// Dimensions 0 and 1 are the pixel (filter) offset.
    static constexpr int kPixelDims = 2;

    /// A placeholder (independent, pixel 0, sample 0, seed 0), to be assigned a real one.
    Sampler() : Sampler(SamplerType::Independent, 0, 0, 0) {}
    Sampler(SamplerType type, uint64_t pixel, uint64_t sample_index, uint64_t seed)
        : Sampler(type, PixelSeed::of(type, pixel, seed), sample_index) {}
    /// What every sample of one pixel shares (the same for all its samples: computed once a pixel).
    struct PixelSeed {
        uint64_t stream = 0;  ///< PCG32::pixel_stream
        uint64_t hash = 0;    ///< the sobol sampler's scrambling seed of the pixel
        static PixelSeed of(SamplerType type, uint64_t pixel, uint64_t seed) {
            // (Only the sobol sampler's scrambles read the pixel hash.)
            return {PCG32::pixel_stream(pixel, seed),
                    type == SamplerType::Sobol ? mix_bits(pixel * 0xBF58476D1CE4E5B9ULL ^ mix_bits(seed ^ 0x94D049BB133111EBULL))
                                               : 0};
        }
    };
    Sampler(SamplerType type, const PixelSeed& px, uint64_t sample_index)
        : m_rng(PCG32::for_sample_of(px.stream, sample_index)), m_type(type),
          m_index_rev(sobol::reverse_bits(uint32_t(sample_index))), m_pixel_hash(px.hash) {}

    /// What Sampler(SamplerType::Independent, px, sample_index) is after get_pixel_2d(), built
    /// from the stream that seeding and those two draws leave (`rng`): the path kernel seeds a
    /// packet's samples and draws their pixel offsets side by side, with PCG32's parts.
    static Sampler independent_after_pixel(const PCG32& rng, const PixelSeed& px, uint64_t sample_index) {
        return Sampler(rng, px, uint32_t(sample_index), kPixelDims);
    }

    SamplerType type() const { return m_type; }
    /// The sample's PCG32 stream: every number of the independent sampler (get_1d and get_2d
    /// draw from it in turn), and the Sobol sampler's past kMaxSobolDims.
    PCG32& stream() { return m_rng; }
    /// Next dimension to be handed out.
    int dimension() const { return m_dim; }

    /// Jump to dimension `dim` (sobol); the independent sampler ignores it and keeps its stream.
    void set_dimension(int dim) { m_dim = dim; }

    /// The pixel-filter offset: always dimensions 0 and 1.
    Vec2f get_pixel_2d() {
        m_dim = 0;
        return get_2d();
    }
    // The independent sampler's draws are a few instructions and inline; the Sobol points are out
    // of line (sobol_1d, sobol_2d), so that the callers of these stay small enough to inline them.
    float get_1d() {
        const int d = m_dim++;
        if (m_type == SamplerType::Independent || d >= kMaxSobolDims) return m_rng.next_float();
        return sobol_1d(d);
    }
    /// Two dimensions with joint (0,2)-sequence stratification (sobol).
    Vec2f get_2d() {
        const int d = m_dim;
        m_dim += 2;
        if (m_type == SamplerType::Independent || d + 2 > kMaxSobolDims) return m_rng.next_2d();
        return sobol_2d(d);
    }

private:
    [[gnu::noinline]] float sobol_1d(int d) const {
        uint32_t x;
        sobol::sample_2d_rev(m_index_rev, seeds(d), &x, nullptr);
        return sobol::to_float(x);
    }
    [[gnu::noinline]] Vec2f sobol_2d(int d) const {
        uint32_t x0, x1;
        sobol::sample_2d_rev(m_index_rev, seeds(d), &x0, &x1);
        return Vec2f(sobol::to_float(x0), sobol::to_float(x1));
    }
    Sampler(const PCG32& rng, const PixelSeed& px, uint32_t sample_index, int dim)
        : m_rng(rng), m_type(SamplerType::Independent), m_index_rev(sobol::reverse_bits(sample_index)),
          m_pixel_hash(px.hash), m_dim(dim) {}
    sobol::GroupSeeds seeds(int d) const { return sobol::group_seeds(m_pixel_hash, uint32_t(d)); }
    PCG32 m_rng;
    SamplerType m_type;
    uint32_t m_index_rev;  ///< the sample index, bit-reversed
    uint64_t m_pixel_hash;
    int m_dim = 0;
};
}  // namespace pellucid
