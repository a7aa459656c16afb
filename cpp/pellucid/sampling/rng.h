// PCG32 random number generator (O'Neill 2014, "PCG: A Family of Simple Fast Space-Efficient
// Statistically Good Algorithms for Random Number Generation", pcg32 = XSH RR 64/32).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <algorithm>
#include <cstdint>

#include "pellucid/math/constants.h"
#include "pellucid/math/vec.h"

namespace pellucid {

/// 64-bit finaliser of MurmurHash3 / splitmix64; used to decorrelate seeds.
inline uint64_t mix_bits(uint64_t v) {
    v ^= v >> 31;
    v *= 0x7fb5d329728ea185ULL;
    v ^= v >> 27;
    v *= 0x81dadef4bc2dd44dULL;
    v ^= v >> 33;
    return v;
}

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
    [[gnu::always_inline]] static uint64_t step(uint64_t state, uint64_t inc) {
        return state * 0x5851f42d4c957f2dULL + inc;
    }
    [[gnu::always_inline]] static uint32_t output(uint64_t state) {
        const uint32_t xorshifted = uint32_t(((state >> 18u) ^ state) >> 27u);
        const uint32_t rot = uint32_t(state >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31));
    }
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
}  // namespace pellucid
