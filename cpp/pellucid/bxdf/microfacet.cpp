// The double-precision inverse error function (the tests' reference for microfacet_detail::erfinv_t).
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/bxdf/microfacet.h"

namespace pellucid {

double erfinv(double x) {
    if (!(x > -1.0)) return -INFINITY;
    if (!(x < 1.0)) return INFINITY;
    // Giles 2010, "Approximating the erfinv function", GPU Computing Gems, single-precision branch
    // polynomials as the starting point.
    double w = -std::log((1.0 - x) * (1.0 + x)), p;
    if (w < 5.0) {
        w -= 2.5;
        p = 2.81022636e-08;
        p = 3.43273939e-07 + p * w;
        p = -3.5233877e-06 + p * w;
        p = -4.39150654e-06 + p * w;
        p = 0.00021858087 + p * w;
        p = -0.00125372503 + p * w;
        p = -0.00417768164 + p * w;
        p = 0.246640727 + p * w;
        p = 1.50140941 + p * w;
    } else {
        w = std::sqrt(w) - 3.0;
        p = -0.000200214257;
        p = 0.000100950558 + p * w;
        p = 0.00134934322 + p * w;
        p = -0.00367342844 + p * w;
        p = 0.00573950773 + p * w;
        p = -0.0076224613 + p * w;
        p = 0.00943887047 + p * w;
        p = 1.00167406 + p * w;
        p = 2.83297682 + p * w;
    }
    double y = p * x;
    // Two Newton steps on erf(y) − x: d/dy erf = 2/√π e^{−y²}.
    for (int i = 0; i < 2; ++i) {
        double d = 2.0 / std::sqrt(M_PI) * std::exp(-y * y);
        if (!(d > 0.0)) break;
        y -= (std::erf(y) - x) / d;
    }
    return y;
}
}  // namespace pellucid
