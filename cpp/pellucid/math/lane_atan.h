// atan2 and acos over a lane type F (simd/lane.h), written with lane operations only (+ − × ÷ √,
// comparisons, selects, copysign), which IEEE 754 rounds exactly, so the float instantiation and
// every packet give the same bits (libm's on float and xsimd's on packets would not). Used by the
// environment map's lat-long lookup (light/envmap.h) and the spot light's falloff angle
// (light/point.h). Accuracy against double-precision libm: tests/cpp/light/test_envmap_lanes.cpp
// (EnvmapLanes.AnglesMatchLibmToFloatPrecision, EnvmapLanes.LaneAcosMatchesLibm).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include "pellucid/math/constants.h"
#include "pellucid/math/lane_types.h"

namespace pellucid {
namespace lane_math {
/// atan t for t ∈ [0, 1]: above tan(π/8), π/4 + atan((t − 1)/(t + 1)); then s + s·z·P(z), z = s²,
/// |s| ≤ tan(π/8), with P a degree-4 polynomial fitted to (atan s − s)/(s z) on that interval
/// (weighted least squares on the relative error; fit error 7e-10, below float rounding).
template <class F>
inline F atan_unit(const F& t) {
    const auto big = t > F(0.41421356f);
    const F s = lane::select(big, (t - F(1.f)) / (t + F(1.f)), t);
    const F z = s * s;
    const F p = F(-0.33333316f) +
                z * (F(0.19998471f) + z * (F(-0.14243539f) + z * (F(0.10593848f) + z * F(-0.060782962f))));
    const F a = s + s * (z * p);
    return lane::select(big, F(kPiOver4) + a, a);
}
/// atan2(y, x) ∈ [−π, π] (0 for y = x = 0; the sign of y kept).
template <class F>
inline F atan2_t(const F& y, const F& x) {
    const F ax = lane::abs(x), ay = lane::abs(y);
    const auto steep = ay > ax;
    const F num = lane::select(steep, ax, ay), den = lane::select(steep, ay, ax);
    const F t = lane::select(den > F(0.f), num / lane::select(den > F(0.f), den, F(1.f)), F(0.f));
    F a = atan_unit<F>(t);
    a = lane::select(steep, F(kPiOver2) - a, a);
    a = lane::select(x < F(0.f), F(kPi) - a, a);
    return lane::copysign(a, y);
}
/// acos c ∈ [0, π] for c clamped to [−1, 1]: atan2(√((1 − c)(1 + c)), c), the sine from the
/// factored form, which keeps its relative accuracy as c → ±1.
template <class F>
inline F acos_t(const F& c) {
    const F x = lane::min(lane::max(c, F(-1.f)), F(1.f));
    return atan2_t<F>(lane::sqrt((F(1.f) - x) * (F(1.f) + x)), x);
}
}  // namespace lane_math
}  // namespace pellucid
