// Gauss–Legendre nodes and weights.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/bxdf/quadrature.h"

#include <cmath>

namespace pellucid {
namespace {
GaussLegendre32 make_gauss_legendre_32() {
    // Roots of P_n by Newton from the Chebyshev-like guess cos(π(i − 1/4)/(n + 1/2)); the weight is
    // 2 / ((1 − x²) P_n'(x)²) (Abramowitz & Stegun 25.4.29).
    constexpr int n = 32;
    GaussLegendre32 q;
    for (int i = 0; i < n / 2; ++i) {
        double x = std::cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 0.0;
        for (int it = 0; it < 100; ++it) {
            double p0 = 1.0, p1 = 0.0;
            for (int j = 1; j <= n; ++j) {
                double p2 = p1;
                p1 = p0;
                p0 = ((2.0 * j - 1.0) * x * p1 - (j - 1.0) * p2) / j;
            }
            dp = n * (x * p0 - p1) / (x * x - 1.0);
            double dx = p0 / dp;
            x -= dx;
            if (std::fabs(dx) < 1e-15) break;
        }
        double w = 2.0 / ((1.0 - x * x) * dp * dp);
        q.x[i] = -x;
        q.x[n - 1 - i] = x;
        q.w[i] = q.w[n - 1 - i] = w;
    }
    return q;
}
}  // namespace

const GaussLegendre32& gauss_legendre_32() {
    static const GaussLegendre32 q = make_gauss_legendre_32();
    return q;
}
}  // namespace pellucid
