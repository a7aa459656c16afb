// Fixed-order Gauss–Legendre quadrature used for the Fresnel averages and the albedo tables.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>

namespace pellucid {

/// 32-point Gauss–Legendre nodes x_i ∈ (−1, 1) and weights w_i, computed once by Newton's method
/// on P₃₂ (Press et al., Numerical Recipes, §4.6 "gauleg"); exact for polynomials of degree ≤ 63.
struct GaussLegendre32 {
    std::array<double, 32> x{}, w{};
};
const GaussLegendre32& gauss_legendre_32();

/// ∫_a^b f(x) dx with the 32-point rule.
template <class F>
double integrate_gauss_legendre(F&& f, double a, double b) {
    const GaussLegendre32& q = gauss_legendre_32();
    double half = 0.5 * (b - a), mid = 0.5 * (a + b), sum = 0.0;
    for (int i = 0; i < 32; ++i) sum += q.w[i] * f(mid + half * q.x[i]);
    return sum * half;
}
}  // namespace pellucid
