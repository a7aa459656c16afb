// Lane types. The estimator, the BxDFs that have a packet form, the warps, the frames and the ray
// offsets are written once as templates over a lane type F:
//   * F = float: one path; the Python BSDF API, the scalar tests and the width-1 fallback use it;
//   * F = a SIMD packet of 16 (AVX-512), 8 (AVX2) or 4 (SSE4.2) floats: rendering (simd/packet.h).
// This header holds the lane traits, the float side of every lane operation (namespace `lane`), and
// nothing from a SIMD library: simd/packet.h is the one file that includes one.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace pellucid {

/// What a lane type is made of: its width, its mask type, its 32-bit integer type, and the
/// double-precision type its lanes widen to (Double), kDoubleParts of which hold them in order.
template <class F>
struct LaneTraits;
template <>
struct LaneTraits<float> {
    static constexpr int kWidth = 1;
    using Mask = bool;
    using Int = int32_t;
    using Double = double;
    static constexpr int kDoubleParts = 1;
};
template <class F>
using MaskT = typename LaneTraits<F>::Mask;
template <class F>
using IntT = typename LaneTraits<F>::Int;
template <class F>
inline constexpr int kLaneWidth = LaneTraits<F>::kWidth;
/// Double-precision lanes: a float lane type F widens to kDoubleParts<F> values of DoubleT<F>
/// (one double for a float; two double packets of half the width for a float packet), and code
/// written over a double lane type D (double or a double packet) runs on each part.
template <class F>
using DoubleT = typename LaneTraits<F>::Double;
template <class F>
inline constexpr int kDoubleParts = LaneTraits<F>::kDoubleParts;

/// Lane operations on floats, named as their packet overloads (simd/packet.h) so that templated
/// code calls `lane::sqrt(x)` whatever F is.
namespace lane {
inline float select(bool m, float a, float b) { return m ? a : b; }
inline int32_t select(bool m, int32_t a, int32_t b) { return m ? a : b; }
inline bool select(bool m, bool a, bool b) { return m ? a : b; }
inline bool any(bool m) { return m; }
inline bool all(bool m) { return m; }
inline bool none(bool m) { return !m; }
/// -x with the sign bit flipped, zeros included (-(+0) = -0), as the float negation does.
inline float neg(float x) { return -x; }
inline float sqrt(float x) { return std::sqrt(x); }
inline float abs(float x) { return std::fabs(x); }
inline float min(float a, float b) { return std::min(a, b); }
inline float max(float a, float b) { return std::max(a, b); }
inline int32_t min(int32_t a, int32_t b) { return std::min(a, b); }
inline int32_t max(int32_t a, int32_t b) { return std::max(a, b); }
/// Sign of y on the magnitude of x.
inline float copysign(float x, float y) { return std::copysign(x, y); }
inline float exp(float x) { return std::exp(x); }
inline float log(float x) { return std::log(x); }
inline float sin(float x) { return std::sin(x); }
inline float cos(float x) { return std::cos(x); }
inline float atan2(float y, float x) { return std::atan2(y, x); }
inline float pow(float x, float y) { return std::pow(x, y); }
inline float floor(float x) { return std::floor(x); }
inline float to_float(int32_t i) { return float(i); }
/// x rounded toward zero (x within the int range).
inline int32_t to_int(float x) { return int32_t(x); }
/// The bits of x as an integer, and back (for ulp steps).
inline int32_t as_int(float x) {
    int32_t i;
    std::memcpy(&i, &x, sizeof i);
    return i;
}
inline float as_float(int32_t i) {
    float x;
    std::memcpy(&x, &i, sizeof x);
    return x;
}
/// base[idx] (one lane).
inline float gather(const float* base, int32_t idx) { return base[idx]; }
inline int32_t gather(const int32_t* base, int32_t idx) { return base[idx]; }
/// out[k] = base[off + k] for k < N (one lane; simd/packet.h reads a packet's rows and transposes).
template <int N>
inline void gather_rows(const float* base, int32_t off, float* out) {
    for (int k = 0; k < N; ++k) out[k] = base[off + k];
}
/// The float mask m as a mask of the integer lane type, and back.
inline bool int_mask(bool m) { return m; }
inline bool float_mask(bool m) { return m; }
/// The double side: the operations code over a double lane type D needs (simd/packet.h has their
/// packet overloads), and the exact conversions between a float lane type and its double parts.
inline double select(bool m, double a, double b) { return m ? a : b; }
inline double neg(double x) { return -x; }
inline double sqrt(double x) { return std::sqrt(x); }
/// x rounded to float and widened back: the result of a float operation whose exact value is x
/// (a product of two floats is exact in double, so round_to_float(double(a) * double(b)) is a * b
/// in float, bit for bit).
inline double round_to_float(double x) { return double(float(x)); }
/// The lanes of x as doubles, exactly (parts[0..kDoubleParts<F>)), and doubles rounded to float.
inline void to_doubles(float x, double* parts) { parts[0] = double(x); }
inline float from_doubles(const double* parts) { return float(parts[0]); }
/// Load and store W lanes from/to memory.
inline float load(const float* p) { return *p; }
inline int32_t load(const int32_t* p) { return *p; }
inline void store(float* p, float x) { *p = x; }
inline void store(int32_t* p, int32_t x) { *p = x; }
inline void store(bool* p, bool m) { *p = m; }
/// kLaneWidth<F> values from memory as an F (a float, or a packet's load).
template <class F>
inline F load_as(const float* p) {
    if constexpr (std::is_same_v<F, float>) return *p;
    else return F::load_unaligned(p);
}
template <class I>
inline I load_int_as(const int32_t* p) {
    if constexpr (std::is_same_v<I, int32_t>) return *p;
    else return I::load_unaligned(p);
}
/// The packet of half F's width that the packet forms of a 16-lane F run on where at most half its
/// lanes take part (simd/packet.h: the AVX-512 packets'), or void where F has none.
template <class F, class = void>
struct HalfOf {
    using type = void;
};
template <class F>
using HalfT = typename HalfOf<F>::type;
template <class F>
inline constexpr bool kHasHalf = !std::is_void_v<HalfT<F>>;
/// How a packet's mask is read from bools (simd/packet.h specialises it for its masks).
template <class M>
struct MaskLoad {
    static M load(const bool* p) { return M::load_unaligned(p); }
};
template <class M>
inline M load_mask_as(const bool* p) {
    if constexpr (std::is_same_v<M, bool>) return *p;
    else return MaskLoad<M>::load(p);
}
}  // namespace lane
}  // namespace pellucid
