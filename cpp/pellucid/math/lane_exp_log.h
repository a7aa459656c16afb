// e^x, ln x and ln(1 + x) over a lane type F (simd/lane.h), written with lane operations only.
// Each is built from lane operations that IEEE 754 rounds exactly (+ − × ÷ √, comparisons,
// selects, integer bit operations; the library is compiled without contraction), so the float
// instantiation and every packet give the same bits. lane::exp and lane::log would not: they are
// libm's on float and xsimd's on packets. Accuracy against double-precision libm is measured in
// tests/cpp/bxdf/test_microfacet.cpp (BeckmannMath*).
// Used by the Beckmann microfacet model (bxdf/microfacet.h), the filter taps' reference and the
// homogeneous media's distance sampling and transmittance (medium/medium.h).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include "pellucid/math/lane_types.h"

namespace pellucid {
namespace lane_math {
/// 2^n for an integer-valued n ∈ [−126, 127]: the float whose exponent field is n + 127. Adding
/// 1.5·2²³ puts n in the low mantissa bits (exact for |n| < 2²²).
template <class F>
inline F exp2_int(const F& n) {
    using I = IntT<F>;
    const I k = lane::as_int(n + F(12582912.f)) - lane::as_int(F(12582912.f));
    return lane::as_float((k + I(127)) << 23);
}
/// e^x, 0 for x < −87 (where e^x < 1.7e-38 leaves the normal floats), x clamped to ≤ 88:
/// x = n ln 2 + r with n = round(x / ln 2) and ln 2 split in two so that n·ln2_hi is exact (Cody &
/// Waite 1980), e^r by its Taylor series to r⁷ on |r| ≤ ln 2/2 (truncation (ln 2/2)⁸/8! < 6e-9),
/// times 2^n.
template <class F>
inline F exp_t(const F& x) {
    const F xc = lane::min(lane::max(x, F(-87.f)), F(88.f));
    const F n = (xc * F(1.44269504f) + F(12582912.f)) - F(12582912.f);
    const F r = (xc - n * F(0.693359375f)) - n * F(-2.12194440e-4f);
    const F p =
        F(1.f) + r * (F(1.f) + r * (F(0.5f) + r * (F(1.f / 6.f) + r * (F(1.f / 24.f) + r * (F(1.f / 120.f) +
                                                                                             r * (F(1.f / 720.f) + r * F(1.f / 5040.f)))))));
    return lane::select(x < F(-87.f), F(0.f), p * exp2_int(n));
}
/// ln x for a positive normal float x: x = m·2^k with m ∈ [√½, √2) read from the bits, ln m =
/// 2 atanh s = 2(s + s³/3 + s⁵/5 + s⁷/7 + s⁹/9) with s = (m − 1)/(m + 1), |s| ≤ 0.172 (truncation
/// below 2e-9 relative; m − 1 is exact), plus k ln 2 in two parts.
template <class F>
inline F log_t(const F& x) {
    using I = IntT<F>;
    const I bits = lane::as_int(x);
    // 0x004afb0d = bits(1) − bits(√½): the biased exponent of x/√½, so that m lands in [√½, √2).
    const I kb = (bits + I(0x004afb0d)) >> 23;
    const F m = lane::as_float((bits - (kb << 23)) + I(0x3f800000));
    const F k = lane::to_float(kb - I(127));
    const F s = (m - F(1.f)) / (m + F(1.f)), z = s * s;
    const F lm = F(2.f) * s * (F(1.f) + z * (F(1.f / 3.f) + z * (F(0.2f) + z * (F(1.f / 7.f) + z * F(1.f / 9.f)))));
    return k * F(0.693359375f) + (lm + k * F(-2.12194440e-4f));
}
/// ln(1 + x) for x ∈ (−1, 0]: ln y · x/(y − 1) with y = 1 + x rounded, which is x itself where y
/// rounds to 1 (Goldberg 1991, "What every computer scientist should know about floating-point
/// arithmetic", Theorem 4: the factor x/(y − 1) corrects for y's rounding; y − 1 is exact here).
/// Accurate to a few ulps wherever ln(1 + x) is, unlike log_t(1 + x) for small |x|.
template <class F>
inline F log1p_t(const F& x) {
    const F y = F(1.f) + x;
    const auto one = y == F(1.f);
    return lane::select(one, x, log_t(lane::select(one, F(2.f), y)) * (x / lane::select(one, F(1.f), y - F(1.f))));
}
}  // namespace lane_math
}  // namespace pellucid
