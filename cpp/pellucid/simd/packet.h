// SIMD packets: the lane operations of simd/lane.h on xsimd batches. The one file that includes
// xsimd. The per-target translation units (integrator/kernel_*.cpp) include it, each built for its
// instruction set; the rest of the library stays baseline x86-64 (or arm64) code, and the one
// baseline file that includes it (image/film.cpp, for the filter taps' exponentials) takes the
// baseline packet, NativePacket, whose results are then the same on every machine.
// SPDX-License-Identifier: Apache-2.0
//
// Why xsimd (Debian's libxsimd-dev 8.1): a batch is a type, so a template over the lane type F
// instantiates on it directly (Highway's vectors need a descriptor argument and per-target
// namespaces); it converts from float implicitly, so `2.f * x` reads as for floats; and it has every
// function the models need, including atan2 and pow (Highway 1.0.3 has neither).
#pragma once
#include <cstring>
#include <type_traits>

#include <xsimd/xsimd.hpp>

#include "pellucid/simd/lane.h"

#if defined(__AVX512F__) && defined(__AVX512VL__) && defined(__AVX512DQ__) && defined(__BMI2__)
#define PELLUCID_HALF_PACKETS 1
namespace pellucid {
/// The low half of the 512-bit registers of architecture Full (an AVX-512 one) as an architecture
/// of its own: 8-lane packets on xsimd's AVX2 kernels, for the packet forms that run on few lanes of
/// a 16-lane packet (lane::HalfOf, integrator/form_lanes.h). Its own type, named after Full, so that what
/// the AVX-512 kernel instantiates on it never shares a symbol with the AVX2 kernel's batches.
template <class Full>
struct half_of : xsimd::avx2 {
    static constexpr char const* name() noexcept { return "half_of_avx512"; }
};
}  // namespace pellucid
namespace xsimd {
namespace types {
// half_of<Full>'s registers are AVX2's (as XSIMD_DECLARE_SIMD_REGISTER_ALIAS declares an alias).
template <class T, class Full>
struct simd_register<T, pellucid::half_of<Full>> : simd_register<T, avx2> {
    using register_type = typename simd_register<T, avx2>::register_type;
    simd_register(register_type reg) noexcept : simd_register<T, avx2>{reg} {}
    simd_register() = default;
};
template <class T, class Full>
struct has_simd_register<T, pellucid::half_of<Full>> : has_simd_register<T, avx2> {};
}  // namespace types
}  // namespace xsimd
#endif

namespace pellucid {

template <class A>
struct LaneTraits<xsimd::batch<float, A>> {
    static constexpr int kWidth = int(xsimd::batch<float, A>::size);
    using Mask = xsimd::batch_bool<float, A>;
    using Int = xsimd::batch<int32_t, A>;
    using Double = xsimd::batch<double, A>;
    static constexpr int kDoubleParts = kWidth / int(xsimd::batch<double, A>::size);
};

/// The packet of the instruction set the including translation unit is built for.
using NativePacket = xsimd::batch<float>;

namespace lane {
template <class A>
using FP = xsimd::batch<float, A>;
template <class A>
using IP = xsimd::batch<int32_t, A>;
template <class A>
using MP = xsimd::batch_bool<float, A>;
template <class A>
using MIP = xsimd::batch_bool<int32_t, A>;
template <class A>
using DP = xsimd::batch<double, A>;
template <class A>
using MDP = xsimd::batch_bool<double, A>;

template <class A>
inline FP<A> select(const MP<A>& m, const FP<A>& a, const FP<A>& b) { return xsimd::select(m, a, b); }
template <class A>
inline IP<A> select(const MIP<A>& m, const IP<A>& a, const IP<A>& b) { return xsimd::select(m, a, b); }
template <class A>
inline MP<A> select(const MP<A>& m, const MP<A>& a, const MP<A>& b) { return (m && a) || (!m && b); }
template <class A>
inline bool any(const MP<A>& m) { return xsimd::any(m); }
template <class A>
inline bool all(const MP<A>& m) { return xsimd::all(m); }
template <class A>
inline bool none(const MP<A>& m) { return !xsimd::any(m); }
template <class A>
inline bool any(const MIP<A>& m) { return xsimd::any(m); }
/// The sign bit flipped (xsimd's unary minus subtracts from +0 on some targets, which loses -0).
template <class A>
inline FP<A> neg(const FP<A>& x) { return x ^ FP<A>(-0.f); }
template <class A>
inline FP<A> sqrt(const FP<A>& x) { return xsimd::sqrt(x); }
template <class A>
inline FP<A> abs(const FP<A>& x) { return xsimd::abs(x); }
template <class A>
inline FP<A> min(const FP<A>& a, const FP<A>& b) { return xsimd::min(a, b); }
template <class A>
inline FP<A> max(const FP<A>& a, const FP<A>& b) { return xsimd::max(a, b); }
template <class A>
inline IP<A> min(const IP<A>& a, const IP<A>& b) { return xsimd::min(a, b); }
template <class A>
inline IP<A> max(const IP<A>& a, const IP<A>& b) { return xsimd::max(a, b); }
template <class A>
inline FP<A> copysign(const FP<A>& x, const FP<A>& y) { return xsimd::copysign(x, y); }
template <class A>
inline FP<A> exp(const FP<A>& x) { return xsimd::exp(x); }
template <class A>
inline FP<A> log(const FP<A>& x) { return xsimd::log(x); }
template <class A>
inline FP<A> sin(const FP<A>& x) { return xsimd::sin(x); }
template <class A>
inline FP<A> cos(const FP<A>& x) { return xsimd::cos(x); }
template <class A>
inline FP<A> atan2(const FP<A>& y, const FP<A>& x) { return xsimd::atan2(y, x); }
template <class A>
inline FP<A> pow(const FP<A>& x, const FP<A>& y) { return xsimd::pow(x, y); }
template <class A>
inline FP<A> floor(const FP<A>& x) { return xsimd::floor(x); }
template <class A>
inline FP<A> to_float(const IP<A>& i) { return xsimd::to_float(i); }
template <class A>
inline IP<A> to_int(const FP<A>& x) { return xsimd::to_int(x); }
template <class A>
inline IP<A> as_int(const FP<A>& x) { return xsimd::bitwise_cast<IP<A>>(x); }
template <class A>
inline FP<A> as_float(const IP<A>& i) { return xsimd::bitwise_cast<FP<A>>(i); }
/// base[idx[k]] in every lane k.
/// (xsimd 8.1 gathers element by element; the AVX-512 and AVX2 gather instructions are used here.)
template <class A>
inline FP<A> gather(const float* base, const IP<A>& idx) {
#if defined(__AVX512F__)
    if constexpr (std::is_base_of_v<xsimd::avx512f, A>) return FP<A>(_mm512_i32gather_ps(idx, base, 4));
#endif
#if defined(__AVX2__)
    if constexpr (std::is_base_of_v<xsimd::avx2, A>) return FP<A>(_mm256_i32gather_ps(base, idx, 4));
#endif
    return FP<A>::gather(base, idx);
}
template <class A>
inline IP<A> gather(const int32_t* base, const IP<A>& idx) {
#if defined(__AVX512F__)
    if constexpr (std::is_base_of_v<xsimd::avx512f, A>) return IP<A>(_mm512_i32gather_epi32(idx, base, 4));
#endif
#if defined(__AVX2__)
    if constexpr (std::is_base_of_v<xsimd::avx2, A>) return IP<A>(_mm256_i32gather_epi32(base, idx, 4));
#endif
    return IP<A>::gather(base, idx);
}
namespace detail {
#if defined(__AVX2__)
/// Transpose of the 8 × 8 floats r[0..8) (row i → lane i of out[k] = r[i][k]). Templated on the
/// architecture A only so that each kernel target's copy has its own symbol (an inline function
/// compiled with two targets' flags must not be merged by the linker).
template <class A>
inline void transpose8(__m256* r) {
    __m256 t[8], u[8];
    for (int i = 0; i < 8; i += 2) t[i] = _mm256_unpacklo_ps(r[i], r[i + 1]), t[i + 1] = _mm256_unpackhi_ps(r[i], r[i + 1]);
    for (int i = 0; i < 8; i += 4) {
        u[i + 0] = _mm256_shuffle_ps(t[i], t[i + 2], 0x44), u[i + 1] = _mm256_shuffle_ps(t[i], t[i + 2], 0xee);
        u[i + 2] = _mm256_shuffle_ps(t[i + 1], t[i + 3], 0x44), u[i + 3] = _mm256_shuffle_ps(t[i + 1], t[i + 3], 0xee);
    }
    for (int k = 0; k < 4; ++k) {
        r[k] = _mm256_permute2f128_ps(u[k], u[k + 4], 0x20);
        r[k + 4] = _mm256_permute2f128_ps(u[k], u[k + 4], 0x31);
    }
}
#endif
#if defined(__AVX512F__)
/// Transpose of the 16 × 16 floats r[0..16) (templated on A as transpose8).
template <class A>
inline void transpose16(__m512* r) {
    __m512 t[16];
    for (int i = 0; i < 16; i += 2) t[i] = _mm512_unpacklo_ps(r[i], r[i + 1]), t[i + 1] = _mm512_unpackhi_ps(r[i], r[i + 1]);
    for (int i = 0; i < 16; i += 4) {
        auto pd = [](__m512 x) { return _mm512_castps_pd(x); };
        r[i + 0] = _mm512_castpd_ps(_mm512_unpacklo_pd(pd(t[i]), pd(t[i + 2])));
        r[i + 1] = _mm512_castpd_ps(_mm512_unpackhi_pd(pd(t[i]), pd(t[i + 2])));
        r[i + 2] = _mm512_castpd_ps(_mm512_unpacklo_pd(pd(t[i + 1]), pd(t[i + 3])));
        r[i + 3] = _mm512_castpd_ps(_mm512_unpackhi_pd(pd(t[i + 1]), pd(t[i + 3])));
    }
    // r[4b + c] now holds, in 128-bit block q, column 4q' + c of rows 4b..4b+3 (q' the block).
    for (int h = 0; h < 2; ++h)
        for (int c = 0; c < 4; ++c) {
            t[8 * h + c] = _mm512_shuffle_f32x4(r[8 * h + c], r[8 * h + 4 + c], 0x88);
            t[8 * h + 4 + c] = _mm512_shuffle_f32x4(r[8 * h + c], r[8 * h + 4 + c], 0xdd);
        }
    for (int c = 0; c < 8; ++c) {
        r[c] = _mm512_shuffle_f32x4(t[c], t[8 + c], 0x88);
        r[8 + c] = _mm512_shuffle_f32x4(t[c], t[8 + c], 0xdd);
    }
}
#endif
}  // namespace detail

/// out[k] = base[off + k] in every lane, for k < N (8 or 16): each lane's N consecutive floats,
/// read as one row and transposed into N packets (a gather per column costs more where the rows
/// are scattered: on AVX-512 sixteen row loads and a 16 × 16 transpose replace sixteen gathers).
/// Reads N floats from every lane's offset, valid or not.
template <int N, class A>
inline void gather_rows(const float* base, const IP<A>& off, FP<A>* out) {
    static_assert(N == 8 || N == 16, "rows of 8 or 16 floats");
    constexpr int W = int(FP<A>::size);
    alignas(64) int32_t o[W];
    off.store_aligned(o);
#if defined(__AVX512F__)
    if constexpr (std::is_base_of_v<xsimd::avx512f, A>) {
        if constexpr (N == 16) {
            __m512 r[16];
            for (int i = 0; i < 16; ++i) r[i] = _mm512_loadu_ps(base + o[i]);
            detail::transpose16<A>(r);
            for (int k = 0; k < 16; ++k) out[k] = FP<A>(r[k]);
        } else {
            __m256 lo[8], hi[8];
            for (int i = 0; i < 8; ++i) lo[i] = _mm256_loadu_ps(base + o[i]), hi[i] = _mm256_loadu_ps(base + o[i + 8]);
            detail::transpose8<A>(lo), detail::transpose8<A>(hi);
            for (int k = 0; k < 8; ++k) out[k] = FP<A>(_mm512_insertf32x8(_mm512_castps256_ps512(lo[k]), hi[k], 1));
        }
        return;
    }
#endif
#if defined(__AVX2__)
    if constexpr (std::is_base_of_v<xsimd::avx2, A>) {
        for (int h = 0; h < N; h += 8) {
            __m256 r[8];
            for (int i = 0; i < 8; ++i) r[i] = _mm256_loadu_ps(base + o[i] + h);
            detail::transpose8<A>(r);
            for (int k = 0; k < 8; ++k) out[h + k] = FP<A>(r[k]);
        }
        return;
    }
#endif
#if defined(__SSE4_2__)
    if constexpr (std::is_same_v<A, xsimd::sse4_2>) {
        for (int h = 0; h < N; h += 4) {
            __m128 r0 = _mm_loadu_ps(base + o[0] + h), r1 = _mm_loadu_ps(base + o[1] + h);
            __m128 r2 = _mm_loadu_ps(base + o[2] + h), r3 = _mm_loadu_ps(base + o[3] + h);
            _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
            out[h] = FP<A>(r0), out[h + 1] = FP<A>(r1), out[h + 2] = FP<A>(r2), out[h + 3] = FP<A>(r3);
        }
        return;
    }
#endif
    for (int k = 0; k < N; ++k) out[k] = gather(base, off + IP<A>(k));
}

/// A float-lane mask as an integer-lane mask, and back.
template <class A>
inline MIP<A> int_mask(const MP<A>& m) {
#if defined(__AVX2__)
    // (An AVX2 mask's lanes are all ones or all zeros whatever their type: the same register.)
    if constexpr (std::is_base_of_v<xsimd::avx2, A>) return MIP<A>(_mm256_castps_si256(m));
#endif
    return as_int(select(m, FP<A>(1.f), FP<A>(0.f))) != IP<A>(0);
}
template <class A>
inline MP<A> float_mask(const MIP<A>& m) {
#if defined(__AVX2__)
    if constexpr (std::is_base_of_v<xsimd::avx2, A>) return MP<A>(_mm256_castsi256_ps(m));
#endif
    return to_float(select(m, IP<A>(1), IP<A>(0))) != FP<A>(0.f);
}
template <class A>
inline void store(float* p, const FP<A>& x) { x.store_unaligned(p); }
template <class A>
inline void store(int32_t* p, const IP<A>& x) { x.store_unaligned(p); }
// Double packets (simd/lane.h, "The double side"): a float packet's lanes are its two double
// packets' lanes, low half first. The conversions are the float<->double conversion instructions,
// exact to double and correctly rounded (to nearest) back to float, as the scalar conversions.
// (Of xsimd 8.1's mask operators, != on SSE masks is cmpneq, true on two all-ones lanes, and ^ on
// AVX-512 masks is an or: inequality of masks is spelt (a && !b) || (!a && b).)
template <class A>
inline DP<A> select(const MDP<A>& m, const DP<A>& a, const DP<A>& b) { return xsimd::select(m, a, b); }
template <class A>
inline DP<A> neg(const DP<A>& x) { return x ^ DP<A>(-0.0); }
template <class A>
inline DP<A> sqrt(const DP<A>& x) { return xsimd::sqrt(x); }
template <class A>
inline void to_doubles(const FP<A>& x, DP<A>* parts) {
    static_assert(FP<A>::size == 2 * DP<A>::size, "a float packet is two double packets");
#if defined(__AVX512F__)
    if constexpr (std::is_base_of_v<xsimd::avx512f, A>) {
        parts[0] = DP<A>(_mm512_cvtps_pd(_mm512_castps512_ps256(x)));
        parts[1] = DP<A>(_mm512_cvtps_pd(_mm256_castpd_ps(_mm512_extractf64x4_pd(_mm512_castps_pd(x), 1))));
        return;
    }
#endif
#if defined(__AVX2__)
    if constexpr (std::is_base_of_v<xsimd::avx2, A>) {
        parts[0] = DP<A>(_mm256_cvtps_pd(_mm256_castps256_ps128(x)));
        parts[1] = DP<A>(_mm256_cvtps_pd(_mm256_extractf128_ps(x, 1)));
        return;
    }
#endif
#if defined(__SSE4_2__)
    if constexpr (std::is_same_v<A, xsimd::sse4_2>) {
        parts[0] = DP<A>(_mm_cvtps_pd(x));
        parts[1] = DP<A>(_mm_cvtps_pd(_mm_movehl_ps(x, x)));
        return;
    }
#endif
    alignas(64) float f[FP<A>::size];
    alignas(64) double d[FP<A>::size];
    x.store_aligned(f);
    for (size_t i = 0; i < FP<A>::size; ++i) d[i] = double(f[i]);
    parts[0] = DP<A>::load_aligned(d), parts[1] = DP<A>::load_aligned(d + DP<A>::size);
}
template <class A>
inline FP<A> from_doubles(const DP<A>* parts) {
#if defined(__AVX512F__)
    if constexpr (std::is_base_of_v<xsimd::avx512f, A>) {
        const __m512d lo = _mm512_castps_pd(_mm512_castps256_ps512(_mm512_cvtpd_ps(parts[0])));
        return FP<A>(_mm512_castpd_ps(_mm512_insertf64x4(lo, _mm256_castps_pd(_mm512_cvtpd_ps(parts[1])), 1)));
    }
#endif
#if defined(__AVX2__)
    if constexpr (std::is_base_of_v<xsimd::avx2, A>)
        return FP<A>(_mm256_insertf128_ps(_mm256_castps128_ps256(_mm256_cvtpd_ps(parts[0])), _mm256_cvtpd_ps(parts[1]), 1));
#endif
#if defined(__SSE4_2__)
    if constexpr (std::is_same_v<A, xsimd::sse4_2>) return FP<A>(_mm_movelh_ps(_mm_cvtpd_ps(parts[0]), _mm_cvtpd_ps(parts[1])));
#endif
    alignas(64) double d[FP<A>::size];
    alignas(64) float f[FP<A>::size];
    parts[0].store_aligned(d), parts[1].store_aligned(d + DP<A>::size);
    for (size_t i = 0; i < FP<A>::size; ++i) f[i] = float(d[i]);
    return FP<A>::load_aligned(f);
}
template <class A>
inline DP<A> round_to_float(const DP<A>& x) {
#if defined(__AVX512F__)
    if constexpr (std::is_base_of_v<xsimd::avx512f, A>) return DP<A>(_mm512_cvtps_pd(_mm512_cvtpd_ps(x)));
#endif
#if defined(__AVX2__)
    if constexpr (std::is_base_of_v<xsimd::avx2, A>) return DP<A>(_mm256_cvtps_pd(_mm256_cvtpd_ps(x)));
#endif
#if defined(__SSE4_2__)
    if constexpr (std::is_same_v<A, xsimd::sse4_2>) return DP<A>(_mm_cvtps_pd(_mm_cvtpd_ps(x)));
#endif
    alignas(64) double d[DP<A>::size];
    x.store_aligned(d);
    for (size_t i = 0; i < DP<A>::size; ++i) d[i] = double(float(d[i]));
    return DP<A>::load_aligned(d);
}
// Masks to and from bool arrays (the kernel's per-lane flags). xsimd 8.1 converts them one lane at
// a time through a float buffer, which took 6 % of a render; these widen or narrow the bytes in
// registers. A bool in memory is the byte 0 or 1.
template <class A>
inline void store(bool* p, const MP<A>& m) {
#if defined(__AVX512BW__) && defined(__AVX512VL__)
    if constexpr (std::is_base_of_v<xsimd::avx512f, A>) {
        _mm_storeu_si128(reinterpret_cast<__m128i*>(p), _mm_maskz_set1_epi8(__mmask16(m.data), 1));
        return;
    }
#endif
#if defined(__AVX2__)
    if constexpr (std::is_base_of_v<xsimd::avx2, A>) {
        const __m256i one = _mm256_srli_epi32(_mm256_castps_si256(m), 31);
        const __m128i w = _mm_packus_epi32(_mm256_castsi256_si128(one), _mm256_extracti128_si256(one, 1));
        _mm_storel_epi64(reinterpret_cast<__m128i*>(p), _mm_packus_epi16(w, w));
        return;
    }
#endif
#if defined(__SSE4_2__)
    if constexpr (std::is_same_v<A, xsimd::sse4_2>) {
        const __m128i one = _mm_srli_epi32(_mm_castps_si128(m), 31);
        const __m128i w = _mm_packus_epi32(one, one);
        const int32_t bytes = _mm_cvtsi128_si32(_mm_packus_epi16(w, w));
        std::memcpy(p, &bytes, 4);
        return;
    }
#endif
    m.store_unaligned(p);
}

#if PELLUCID_HALF_PACKETS
/// A 16-lane packet's lanes `where` (at most 8) moved into the low lanes of its half-width packet,
/// in lane order (AVX-512's compress), and results moved back onto those lanes (its expand). Lanes
/// of the half packet past the moved ones repeat the first moved lane, so that they hold inputs some
/// lane really has (their masks are false).
template <class A>
class HalfMove {
public:
    using H = half_of<A>;
    explicit HalfMove(const MP<A>& where)
        : m_(__mmask16(where.data)), fill_(_mm512_set1_epi32(int(__builtin_ctz(uint32_t(m_) | 0x10000u)))) {}
    FP<H> in(const FP<A>& x) const {
        return FP<H>(_mm512_castps512_ps256(_mm512_mask_compress_ps(_mm512_permutexvar_ps(fill_, x), m_, x)));
    }
    IP<H> in(const IP<A>& x) const {
        return IP<H>(_mm512_castsi512_si256(_mm512_mask_compress_epi32(_mm512_permutexvar_epi32(fill_, x), m_, x)));
    }
    MP<H> in(const MP<A>& v) const {
        const uint32_t b = _pext_u32(uint32_t(v.data), uint32_t(m_));
        return MP<H>(_mm256_castsi256_ps(_mm256_movm_epi32(__mmask8(b))));
    }
    void out(FP<A>& dst, const FP<H>& v) const { dst = FP<A>(_mm512_mask_expand_ps(dst, m_, _mm512_zextps256_ps512(v))); }
    void out(IP<A>& dst, const IP<H>& v) const {
        dst = IP<A>(_mm512_mask_expand_epi32(dst, m_, _mm512_zextsi256_si512(v)));
    }
    void out(MP<A>& dst, const MP<H>& v) const {
        const uint32_t b = _pdep_u32(uint32_t(_mm256_movepi32_mask(_mm256_castps_si256(v))), uint32_t(m_));
        dst = MP<A>(__mmask16((uint32_t(dst.data) & ~uint32_t(m_)) | b));
    }
    /// How many lanes move.
    int count() const { return __builtin_popcount(uint32_t(m_)); }

private:
    __mmask16 m_;
    __m512i fill_;
};
template <class A>
struct HalfOf<FP<A>, std::enable_if_t<std::is_base_of_v<xsimd::avx512f, A>>> {
    using type = FP<half_of<A>>;
    using Move = HalfMove<A>;
};
#endif
}  // namespace lane

template <class A>
struct lane::MaskLoad<xsimd::batch_bool<float, A>> {
    static xsimd::batch_bool<float, A> load(const bool* p) {
#if defined(__AVX512BW__) && defined(__AVX512VL__)
        if constexpr (std::is_base_of_v<xsimd::avx512f, A>) {
            const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p));
            return xsimd::batch_bool<float, A>(_mm_test_epi8_mask(b, b));
        }
#endif
#if defined(__AVX2__)
        if constexpr (std::is_base_of_v<xsimd::avx2, A>) {
            const __m256i v = _mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p)));
            return xsimd::batch_bool<float, A>(_mm256_castsi256_ps(_mm256_cmpgt_epi32(v, _mm256_setzero_si256())));
        }
#endif
#if defined(__SSE4_2__)
        if constexpr (std::is_same_v<A, xsimd::sse4_2>) {
            int32_t bytes;
            std::memcpy(&bytes, p, 4);
            const __m128i v = _mm_cvtepu8_epi32(_mm_cvtsi32_si128(bytes));
            return xsimd::batch_bool<float, A>(_mm_castsi128_ps(_mm_cmpgt_epi32(v, _mm_setzero_si128())));
        }
#endif
        return xsimd::batch_bool<float, A>::load_unaligned(p);
    }
};

}  // namespace pellucid
