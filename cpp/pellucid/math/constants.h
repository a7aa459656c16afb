// Numeric constants and floating-point error helpers.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cmath>
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>

namespace pellucid {
constexpr float kPi = 3.14159265358979323846f;
constexpr float kInvPi = 0.31830988618379067154f;
constexpr float kInv2Pi = 0.15915494309189533577f;
constexpr float kInv4Pi = 0.07957747154594766788f;
constexpr float kPiOver2 = 1.57079632679489661923f;
constexpr float kPiOver4 = 0.78539816339744830962f;
constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;
constexpr float kInfinity = std::numeric_limits<float>::infinity();
constexpr float kMachineEpsilon = std::numeric_limits<float>::epsilon() * 0.5f;

/// Conservative bound (1+ε)^n − 1 on the relative error of n chained float operations
/// (Higham 2002, §3.1; pbrt-v4 §6.8.1 uses the same γ_n).
constexpr float gamma(int n) { return (n * kMachineEpsilon) / (1 - n * kMachineEpsilon); }

inline float next_float_up(float v) {
    if (std::isinf(v) && v > 0.f) return v;
    if (v == -0.f) v = 0.f;
    uint32_t ui;
    std::memcpy(&ui, &v, sizeof(float));
    ui = v >= 0 ? ui + 1 : ui - 1;
    std::memcpy(&v, &ui, sizeof(float));
    return v;
}
inline float next_float_down(float v) {
    if (std::isinf(v) && v < 0.f) return v;
    if (v == 0.f) v = -0.f;
    uint32_t ui;
    std::memcpy(&ui, &v, sizeof(float));
    ui = v > 0 ? ui - 1 : ui + 1;
    std::memcpy(&v, &ui, sizeof(float));
    return v;
}
template <class T>
constexpr T clamp(T v, T lo, T hi) { return v < lo ? lo : (v > hi ? hi : v); }
inline float safe_sqrt(float x) { return std::sqrt(std::max(0.f, x)); }  // NaN → 0, as fmax
inline float safe_acos(float x) { return std::acos(clamp(x, -1.f, 1.f)); }
inline float sqr(float x) { return x * x; }
inline float radians(float deg) { return deg * (kPi / 180.f); }
inline float degrees(float rad) { return rad * (180.f / kPi); }
}  // namespace pellucid
