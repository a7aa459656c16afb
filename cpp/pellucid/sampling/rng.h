// PCG32 random number generator (O'Neill 2014, "PCG: A Family of Simple Fast Space-Efficient
// Statistically Good Algorithms for Random Number Generation", pcg32 = XSH RR 64/32).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <algorithm>
#include <cstdint>
#include <cstring>

#include "pellucid/math/constants.h"
#include "pellucid/math/vec.h"

namespace pellucid {

// The generator's arithmetic, written once for a uint64_t and for PCG32x4's vectors of four
// (GCC/Clang vector types take the same operators, element by element). These and PCG32x4's
// functions take vectors by reference: a 32-byte vector argument, in code built for the baseline
// instruction set, draws GCC's note on the ABI of such arguments (which no pragma silences), and
// every one of them is inlined anyway.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"  // vector arguments: see PCG32x4
#endif
namespace rng_detail {
typedef uint64_t U64x4 __attribute__((vector_size(32)));
typedef uint32_t U32x4 __attribute__((vector_size(16)));
/// The low 32 bits of each element.
[[gnu::always_inline]] inline uint32_t low32(uint64_t v) { return uint32_t(v); }
[[gnu::always_inline]] inline U32x4 low32(const U64x4& v) { return __builtin_convertvector(v, U32x4); }

/// 64-bit finaliser of MurmurHash3 / splitmix64.
template <class T>
[[gnu::always_inline]] inline T mix_bits(const T& value) {
    T v = value;
    v ^= v >> 31u;
    v *= 0x7fb5d329728ea185ULL;
    v ^= v >> 27u;
    v *= 0x81dadef4bc2dd44dULL;
    v ^= v >> 33u;
    return v;
}
/// PCG32's state transition, the step of a 64-bit LCG with pcg32's
/// multiplier (O'Neill 2014).
template <class T>
[[gnu::always_inline]] inline T pcg_step(const T& state, const T& inc) {
    return state * 0x5851f42d4c957f2dULL + inc;
}
/// PCG32's output of a step from `state`: XSH RR, a xorshift of the high bits, kept to 32 bits
/// and rotated by the top 5 bits of the state (O'Neill 2014, PCG-XSH-RR).
template <class T>
[[gnu::always_inline]] inline auto pcg_output(const T& state) {
    const auto xorshifted = low32(((state >> 18u) ^ state) >> 27u);
    const auto rot = low32(state >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31u));
}
}  // namespace rng_detail
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

/// 64-bit finaliser of MurmurHash3 / splitmix64; used to decorrelate seeds.
inline uint64_t mix_bits(uint64_t v) { return rng_detail::mix_bits(v); }

class PCG32 {
public:
    PCG32() { seed(0x853c49e6748fea9bULL, 0xda3e39cb94b95bdbULL); }
    PCG32(uint64_t init_state, uint64_t stream) { seed(init_state, stream); }

    /// Seed for one (pixel, sample index, user seed) triple: every such triple owns an independent
    /// stream, so images do not depend on how work is split across threads.
    static PCG32 for_sample(uint64_t pixel, uint64_t sample_index, uint64_t seed) {
        return for_sample_of(pixel_stream(pixel, seed), sample_index);
    }
    /// for_sample in two steps: the part every sample of a pixel shares, then the sample's own.
    static uint64_t pixel_stream(uint64_t pixel, uint64_t seed) {
        return mix_bits(pixel * 0x9E3779B97F4A7C15ULL ^ mix_bits(seed + 0x632BE59BD9B4E019ULL));
    }
    static PCG32 for_sample_of(uint64_t stream, uint64_t sample_index) {
        return PCG32(sample_init(stream, sample_index), stream);
    }

    /// A generator at a given state and increment (what step() and seeded_state() compute).
    static PCG32 from_state(uint64_t state, uint64_t inc) { return PCG32(Raw{}, state, inc); }
    /// The increment of `stream`, and the state seed(init_state, stream) leaves: two steps from 0,
    /// the second after adding init_state. Plain arithmetic, for loops that seed many streams side
    /// by side (the path kernel starts a packet's samples at once).
    [[gnu::always_inline]] static uint64_t increment_of(uint64_t stream) { return (stream << 1u) | 1u; }
    [[gnu::always_inline]] static uint64_t seeded_state(uint64_t init_state, uint64_t inc) {
        return step(step(0u, inc) + init_state, inc);
    }
    /// for_sample_of's init_state.
    [[gnu::always_inline]] static uint64_t sample_init(uint64_t stream, uint64_t sample_index) {
        return mix_bits(sample_index ^ (stream << 1));
    }

    void seed(uint64_t init_state, uint64_t stream) {
        m_inc = increment_of(stream);
        m_state = seeded_state(init_state, m_inc);
    }
    // Always inlined: the path tracer's SIMD kernels draw the independent sampler's numbers
    // themselves, and each must hold its own copy (no shared out-of-line symbol).
    [[gnu::always_inline]] uint32_t next_u32() {
        const uint64_t old = m_state;
        m_state = step(old, m_inc);
        return output(old);
    }
    /// Uniform float in [0, 1).
    [[gnu::always_inline]] float next_float() { return to_float(next_u32()); }

    // The generator's parts, for code that advances many streams side by side (the path kernel
    // keeps a packet's states in arrays, and these loops vectorise): the state after `state`, the
    // output of a step from `state` (XSH RR: xorshift high, random rotation), and [0, 1) from it.
    [[gnu::always_inline]] static uint64_t step(uint64_t state, uint64_t inc) { return rng_detail::pcg_step(state, inc); }
    [[gnu::always_inline]] static uint32_t output(uint64_t state) { return rng_detail::pcg_output(state); }
    [[gnu::always_inline]] static float to_float(uint32_t v) {
        return std::min(float(v) * 0x1p-32f, kOneMinusEpsilon);  // std::min inlines; std::fmin is a libm call
    }
    uint64_t state() const { return m_state; }
    uint64_t increment() const { return m_inc; }
    void set_state(uint64_t state) { m_state = state; }
    Vec2f next_2d() {
        float a = next_float();
        return Vec2f(a, next_float());
    }
    /// Uniform double in [0, 1).
    double next_double() {
        uint64_t v = (uint64_t(next_u32()) << 21) ^ uint64_t(next_u32());
        return double(v & ((1ULL << 53) - 1)) * 0x1p-53;
    }

private:
    struct Raw {};
    PCG32(Raw, uint64_t state, uint64_t inc) : m_state(state), m_inc(inc) {}
    uint64_t m_state, m_inc;
};

/// PCG32's parts on four streams side by side, for the loops that advance a packet's streams (the
/// path kernel): GCC/Clang vector types, one AVX2 register of states (two SSE or NEON ones). Plain
/// loops over PCG32::step, output and to_float stay scalar on AVX2, which has neither a 64-bit
/// multiply nor an unsigned conversion to float; these spell both out, and every element is
/// computed as the scalar functions compute it, bit for bit (tests/cpp/sampling/test_rng.cpp).
/// (GCC notes that a vector return changes the ABI between instruction sets: these are always
/// inlined, never called. The kernel uses them on its AVX2 and AVX-512 targets, whose registers hold
/// a State, and its SSE4.2 and scalar targets keep the scalar loops.)
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
#endif
struct PCG32x4 {
    typedef rng_detail::U64x4 State;
    typedef int64_t Mask64 __attribute__((vector_size(32)));
    typedef rng_detail::U32x4 U32;
    typedef int32_t I32 __attribute__((vector_size(16)));
    typedef float F32 __attribute__((vector_size(16)));

    /// Four elements of an array as a vector V (State, I32 or F32), and back.
    template <class V, class T>
    [[gnu::always_inline]] static V load(const T* p) {
        static_assert(sizeof(V) == 4 * sizeof(T), "four elements");
        V v;
        std::memcpy(&v, p, sizeof v);
        return v;
    }
    template <class V, class T>
    [[gnu::always_inline]] static void store(T* p, const V& v) {
        static_assert(sizeof(V) == 4 * sizeof(T), "four elements");
        std::memcpy(p, &v, sizeof v);
    }
    [[gnu::always_inline]] static State step(const State& state, const State& inc) { return rng_detail::pcg_step(state, inc); }
    [[gnu::always_inline]] static U32 output(const State& state) { return rng_detail::pcg_output(state); }
    /// PCG32::to_float: float(v) is v rounded once to the nearest float; so is hi·2¹⁶ + lo with v's
    /// high and low 16 bits, both converted exactly (as signed integers) and hi·2¹⁶ exact, so the
    /// sum's one rounding gives the same float.
    [[gnu::always_inline]] static F32 to_float(U32 v) {
        const F32 hi = __builtin_convertvector((I32)(v >> 16u), F32);
        const F32 lo = __builtin_convertvector((I32)(v & 0xffffu), F32);
        const F32 f = (hi * 65536.f + lo) * 0x1p-32f;
        return kOneMinusEpsilon < f ? F32{} + kOneMinusEpsilon : f;  // std::min(f, kOneMinusEpsilon)
    }
    /// mix_bits on four values.
    [[gnu::always_inline]] static State mix_bits(const State& v) { return rng_detail::mix_bits(v); }
};

/// PCG32's parts on eight streams: the states of two PCG32x4 (lanes 0–3 and 4–7), whose outputs are
/// made as one vector of eight 32-bit values and converted to floats as one (the path kernel's AVX2
/// and AVX-512 targets: on AVX2, PCG32x4's outputs fill half a register each, and its narrowing of
/// 64-bit elements to 32 bits costs five shuffles where the pair's costs two). Every element is
/// PCG32::output and to_float's, bit for bit (tests/cpp/sampling/test_rng.cpp).
struct PCG32x8 {
    typedef PCG32x4::State State;  ///< four streams: a PCG32x8 is two
    typedef PCG32x4::Mask64 Mask64;
    typedef uint32_t U32 __attribute__((vector_size(32)));
    typedef int32_t I32 __attribute__((vector_size(32)));
    typedef float F32 __attribute__((vector_size(32)));

    template <class V, class T>
    [[gnu::always_inline]] static V load(const T* p) {
        static_assert(sizeof(V) == 32, "one 32-byte vector");
        V v;
        std::memcpy(&v, p, sizeof v);
        return v;
    }
    template <class V, class T>
    [[gnu::always_inline]] static void store(T* p, const V& v) {
        static_assert(sizeof(V) == 32, "one 32-byte vector");
        std::memcpy(p, &v, sizeof v);
    }
    /// The outputs of steps from the states of lanes 0–3 (lo) and 4–7 (hi). XSH RR's rotation is
    /// done on each state's 64-bit element: the 32 bits x of the xorshift, twice side by side
    /// (x·2³² + x), shifted right by rot < 32, hold x rotated right by rot in their low half, which
    /// is PCG32::output's (x >> rot) | (x << (−rot & 31)); the two vectors' low halves are then
    /// gathered into one.
    [[gnu::always_inline]] static U32 output(const State& lo, const State& hi) {
        const State a = rotated(lo), b = rotated(hi);
        typedef uint32_t U32x8 __attribute__((vector_size(32)));
        const U32x8 a32 = (U32x8)a, b32 = (U32x8)b;
#if __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
        return __builtin_shufflevector(a32, b32, 0, 2, 4, 6, 8, 10, 12, 14);
#else
        return __builtin_shufflevector(a32, b32, 1, 3, 5, 7, 9, 11, 13, 15);
#endif
    }
    /// PCG32::to_float on eight values, as PCG32x4::to_float (the same operations, element by element).
    [[gnu::always_inline]] static F32 to_float(U32 v) {
        const F32 hi = __builtin_convertvector((I32)(v >> 16u), F32);
        const F32 lo = __builtin_convertvector((I32)(v & 0xffffu), F32);
        const F32 f = (hi * 65536.f + lo) * 0x1p-32f;
        return kOneMinusEpsilon < f ? F32{} + kOneMinusEpsilon : f;  // std::min(f, kOneMinusEpsilon)
    }
    /// Lanes 0–3 and 4–7 of a mask of eight, widened to masks of the two states' elements.
    [[gnu::always_inline]] static Mask64 low_mask(const I32& m) {
        typedef int32_t I32x4 __attribute__((vector_size(16)));
        return __builtin_convertvector((I32x4)__builtin_shufflevector(m, m, 0, 1, 2, 3), Mask64);
    }
    [[gnu::always_inline]] static Mask64 high_mask(const I32& m) {
        typedef int32_t I32x4 __attribute__((vector_size(16)));
        return __builtin_convertvector((I32x4)__builtin_shufflevector(m, m, 4, 5, 6, 7), Mask64);
    }

private:
    [[gnu::always_inline]] static State rotated(const State& state) {
        const State x = ((state >> 18u) ^ state) >> 27u;
        return ((x << 32u) | (x & 0xffffffffULL)) >> (state >> 59u);
    }
};
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
}  // namespace pellucid
