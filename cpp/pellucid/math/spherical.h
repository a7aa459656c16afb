// Trigonometry of directions in the local shading frame (z = normal), reflect and refract.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <algorithm>
#include <cmath>

#include "pellucid/math/constants.h"
#include "pellucid/math/lane_types.h"
#include "pellucid/math/vec.h"

namespace pellucid {
inline float cos_theta(const Vec3f& w) { return w.z; }
inline float cos2_theta(const Vec3f& w) { return w.z * w.z; }
inline float abs_cos_theta(const Vec3f& w) { return std::fabs(w.z); }
inline float sin2_theta(const Vec3f& w) { return std::max(0.f, 1.f - w.z * w.z); }
inline float sin_theta(const Vec3f& w) { return std::sqrt(sin2_theta(w)); }
inline float tan2_theta(const Vec3f& w) { return sin2_theta(w) / cos2_theta(w); }
inline float cos_phi(const Vec3f& w) {
    float st = sin_theta(w);
    return st == 0.f ? 1.f : clamp(w.x / st, -1.f, 1.f);
}
inline float sin_phi(const Vec3f& w) {
    float st = sin_theta(w);
    return st == 0.f ? 0.f : clamp(w.y / st, -1.f, 1.f);
}
inline bool same_hemisphere(const Vec3f& a, const Vec3f& b) { return a.z * b.z > 0.f; }

/// Mirror reflection of wo about n (both pointing away from the surface).
inline Vec3f reflect(const Vec3f& wo, const Vec3f& n) { return -wo + 2.f * dot(wo, n) * n; }

/// Refraction of wi (pointing away from the surface) through a boundary with normal n and relative
/// IOR eta = η_t/η_i (Snell: η_i sin θi = η_t sin θt). If wi lies below n, the interface is
/// flipped. Returns false on total internal reflection. etap receives the η actually used.
template <class F>
inline MaskT<F> refract(const V3<F>& wi, V3<F> n, F eta, F* etap, V3<F>* wt) {
    // Over a lane type F; the float instantiation is refract() below. Where the result is false
    // (total internal reflection) *wt is not a direction.
    F cos_i = dot(n, wi);
    const auto back = cos_i < F(0.f);
    eta = lane::select(back, F(1.f) / eta, eta);
    cos_i = lane::select(back, lane::neg(cos_i), cos_i);
    n = lane::select(back, -n, n);
    const F x = F(1.f) - cos_i * cos_i;
    const F sin2_i = lane::select(F(0.f) < x, x, F(0.f));
    const F sin2_t = sin2_i / (eta * eta);
    const F y = F(1.f) - sin2_t;
    const F cos_t = lane::sqrt(lane::select(F(0.f) < y, y, F(0.f)));
    *wt = -wi / eta + (cos_i / eta - cos_t) * n;
    if (etap) *etap = eta;
    return !(sin2_t >= F(1.f));
}
inline bool refract(const Vec3f& wi, Vec3f n, float eta, float* etap, Vec3f* wt) {
    Vec3f w;
    float e;
    if (!refract<float>(wi, n, eta, &e, &w)) return false;
    *wt = w;
    if (etap) *etap = e;
    return true;
}

/// Unit direction from spherical coordinates (z up).
inline Vec3f spherical_direction(float sin_t, float cos_t, float phi) {
    return Vec3f(clamp(sin_t, -1.f, 1.f) * std::cos(phi), clamp(sin_t, -1.f, 1.f) * std::sin(phi),
                 clamp(cos_t, -1.f, 1.f));
}
}  // namespace pellucid
