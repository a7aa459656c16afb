// Pearson χ² goodness-of-fit machinery shared by the statistical tests.
// Follows the procedure in ../shared/REFERENCE.md §2.1–2.3: cells sorted by expected count, cells with
// expected < 5 pooled, p = 1 − P(dof/2, χ²/2), reject if p < α_Šidák.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

namespace pellucid::test {

/// Regularised lower incomplete gamma P(a, x) (Numerical Recipes §6.2: series for x < a+1, else
/// continued fraction).
inline double gamma_p(double a, double x) {
    if (x <= 0.0) return 0.0;
    double gln = std::lgamma(a);
    if (x < a + 1.0) {
        double ap = a, sum = 1.0 / a, del = sum;
        for (int n = 0; n < 100000; ++n) {
            ap += 1.0;
            del *= x / ap;
            sum += del;
            if (std::fabs(del) < std::fabs(sum) * 1e-15) break;
        }
        return sum * std::exp(-x + a * std::log(x) - gln);
    }
    double b = x + 1.0 - a, c = 1.0 / 1e-300, d = 1.0 / b, h = d;
    for (int i = 1; i < 100000; ++i) {
        double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::fabs(d) < 1e-300) d = 1e-300;
        c = b + an / c;
        if (std::fabs(c) < 1e-300) c = 1e-300;
        d = 1.0 / d;
        double del = d * c;
        h *= del;
        if (std::fabs(del - 1.0) < 1e-15) break;
    }
    return 1.0 - std::exp(-x + a * std::log(x) - gln) * h;
}

/// Šidák-corrected per-test significance for `tests` tests at family-wise level alpha.
inline double sidak_alpha(double alpha, int tests) {
    return 1.0 - std::pow(1.0 - alpha, 1.0 / double(tests));
}

struct Chi2Result {
    double statistic = 0.0;
    int dof = 0;
    double p_value = 0.0;
    std::string message;
};

/// Pearson χ² of observed counts against expected counts (same length). Cells with expected 0 but
/// observed > 1e-5·N fail immediately (p = 0).
inline Chi2Result chi2_test(const std::vector<double>& observed, const std::vector<double>& expected,
                            double min_expected = 5.0) {
    Chi2Result r;
    std::vector<size_t> idx(expected.size());
    std::iota(idx.begin(), idx.end(), size_t(0));
    std::sort(idx.begin(), idx.end(), [&](size_t a, size_t b) { return expected[a] < expected[b]; });
    double n_total = std::accumulate(observed.begin(), observed.end(), 0.0);
    double pooled_obs = 0.0, pooled_exp = 0.0;
    int terms = 0;
    for (size_t k : idx) {
        if (expected[k] == 0.0) {
            if (observed[k] > 1e-5 * n_total) {
                std::ostringstream os;
                os << "cell " << k << " has expected 0 but observed " << observed[k];
                r.message = os.str();
                r.p_value = 0.0;
                return r;
            }
            continue;
        }
        if (expected[k] < min_expected) {
            pooled_obs += observed[k];
            pooled_exp += expected[k];
            if (pooled_exp >= min_expected) {
                r.statistic += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
                ++terms;
                pooled_obs = pooled_exp = 0.0;
            }
            continue;
        }
        double d = observed[k] - expected[k];
        r.statistic += d * d / expected[k];
        ++terms;
    }
    if (pooled_exp > 0.0) {
        r.statistic += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
        ++terms;
    }
    r.dof = terms - 1;
    if (r.dof < 1) {
        r.message = "fewer than two χ² terms";
        r.p_value = 0.0;
        return r;
    }
    r.p_value = 1.0 - gamma_p(r.dof / 2.0, r.statistic / 2.0);
    std::ostringstream os;
    os << "chi2=" << r.statistic << " dof=" << r.dof << " p=" << r.p_value;
    r.message = os.str();
    return r;
}

/// Integrate f over [x0,x1]×[y0,y1] with a res×res midpoint rule (f smooth inside the cell).
template <class F>
double integrate_2d(F&& f, double x0, double x1, double y0, double y1, int res = 8) {
    double hx = (x1 - x0) / res, hy = (y1 - y0) / res, sum = 0.0;
    for (int i = 0; i < res; ++i)
        for (int j = 0; j < res; ++j) sum += f(x0 + (i + 0.5) * hx, y0 + (j + 0.5) * hy);
    return sum * hx * hy;
}
/// n-point Gauss–Legendre nodes/weights on [−1, 1] (Newton on P_n; Numerical Recipes §4.6).
inline void gauss_legendre(int n, std::vector<double>& x, std::vector<double>& w) {
    x.assign(n, 0.0);
    w.assign(n, 0.0);
    for (int i = 0; i < (n + 1) / 2; ++i) {
        double z = std::cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 1.0;
        for (int it = 0; it < 100; ++it) {
            double p0 = 1.0, p1 = 0.0;
            for (int j = 1; j <= n; ++j) {
                double p2 = p1;
                p1 = p0;
                p0 = ((2.0 * j - 1.0) * z * p1 - (j - 1.0) * p2) / j;
            }
            dp = n * (z * p0 - p1) / (z * z - 1.0);
            double dz = p0 / dp;
            z -= dz;
            if (std::fabs(dz) < 1e-15) break;
        }
        x[i] = -z;
        x[n - 1 - i] = z;
        w[i] = w[n - 1 - i] = 2.0 / ((1.0 - z * z) * dp * dp);
    }
}

/// Integrate f over [x0,x1]×[y0,y1] with an n×n tensor Gauss–Legendre rule (accurate for smooth f,
/// e.g. a microfacet lobe spanning a few χ² cells).
template <class F>
double integrate_2d_gauss(F&& f, double x0, double x1, double y0, double y1, int n = 6) {
    thread_local std::vector<double> gx, gw;
    thread_local int cached = -1;
    if (cached != n) {
        gauss_legendre(n, gx, gw);
        cached = n;
    }
    double hx = 0.5 * (x1 - x0), hy = 0.5 * (y1 - y0), mx = 0.5 * (x0 + x1), my = 0.5 * (y0 + y1), sum = 0.0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) sum += gw[i] * gw[j] * f(mx + hx * gx[i], my + hy * gx[j]);
    return sum * hx * hy;
}
}  // namespace pellucid::test
