// Multiple importance sampling heuristics (Veach 1997, §9.2.4 eq. 9.13 and 9.15).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cmath>

namespace pellucid {
inline float balance_heuristic(float pdf_a, float pdf_b) {
    return pdf_a + pdf_b > 0.f ? pdf_a / (pdf_a + pdf_b) : 0.f;
}
/// Power heuristic with β = 2; robust to infinite pdf_a (delta lobes give weight 1).
inline float power_heuristic(float pdf_a, float pdf_b) {
    if (std::isinf(pdf_a)) return 1.f;
    float a = pdf_a * pdf_a, b = pdf_b * pdf_b;
    return a + b > 0.f ? a / (a + b) : 0.f;
}
}  // namespace pellucid
