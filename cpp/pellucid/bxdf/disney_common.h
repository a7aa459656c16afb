// Small helpers shared by the two Disney models (principled.cpp, Burley 2012; principled_bsdf.cpp,
// Burley 2015).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cmath>

#include "pellucid/math/constants.h"
#include "pellucid/math/spectrum.h"

namespace pellucid::disney {
/// (1 − cos)^5, the Schlick Fresnel weight (Schlick 1994, eq. 15), with cos clamped to [0, 1].
inline float schlick_weight(float c) {
    float m = clamp(1.f - c, 0.f, 1.f), m2 = m * m;
    return m2 * m2 * m;
}
inline float lerp(float a, float b, float t) { return a + (b - a) * t; }
inline Spectrum lerp(const Spectrum& a, const Spectrum& b, float t) { return a + (b - a) * t; }
/// A [0, 1] parameter: clamped, and NaN read as 0.
inline float unit(float x) { return std::isfinite(x) ? clamp(x, 0.f, 1.f) : 0.f; }
}  // namespace pellucid::disney
