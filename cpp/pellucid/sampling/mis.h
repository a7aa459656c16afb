// Multiple importance sampling heuristics (Veach 1997, §9.2.4 eq. 9.13 and 9.15).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cmath>

#include "pellucid/math/constants.h"
#include "pellucid/simd/lane.h"

namespace pellucid {
inline float balance_heuristic(float pdf_a, float pdf_b) {
    return pdf_a + pdf_b > 0.f ? pdf_a / (pdf_a + pdf_b) : 0.f;
}
/// Power heuristic with β = 2; robust to infinite pdf_a (delta lobes give weight 1). Over a lane
/// type F (simd/lane.h); power_heuristic(float, float) is its float instantiation.
template <class F>
inline F power_heuristic(const F& pdf_a, const F& pdf_b) {
    const F a = pdf_a * pdf_a, b = pdf_b * pdf_b, sum = a + b;
    const F w = lane::select(sum > F(0.f), a / lane::select(sum > F(0.f), sum, F(1.f)), F(0.f));
    return lane::select(pdf_a == F(kInfinity), F(1.f), w);
}
inline float power_heuristic(float pdf_a, float pdf_b) { return power_heuristic<float>(pdf_a, pdf_b); }

/// The MIS weight of emission found by BSDF sampling (a surface emitter or a light at infinity)
/// against the light-sampling strategy that could have produced the same direction with density
/// light_pdf: 1 after a delta bounce or without NEE, 0 under "nee" (light sampling alone accounts
/// for non-delta directions), else the power heuristic.
template <class F>
inline F bsdf_hit_weight(bool use_mis, bool use_nee, const MaskT<F>& specular, const F& bsdf_pdf, const F& light_pdf) {
    if (!use_nee) return F(1.f);
    return lane::select(specular, F(1.f), use_mis ? power_heuristic<F>(bsdf_pdf, light_pdf) : F(0.f));
}
}  // namespace pellucid
