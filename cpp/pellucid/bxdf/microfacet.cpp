// Beckmann Λ and exact visible-normal sampling; inverse error function.
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

float Beckmann::lambda(const Vec3f& w) const {
    if (w.z == 0.f) return kInfinity;
    double den = std::sqrt(double(m_ax) * m_ax * w.x * w.x + double(m_ay) * m_ay * w.y * w.y);
    if (den == 0.0) return 0.f;
    double a = std::fabs(double(w.z)) / den;
    double l = 0.5 * (std::exp(-a * a) / (a * std::sqrt(M_PI)) - std::erfc(a));
    return float(std::max(0.0, l));
}

namespace {
// Unit-roughness Beckmann, incident direction at angle θ in the xz-plane (azimuth 0). Visible-slope
// density ∝ (cos θ − x̃ sin θ) e^{−x̃²−ỹ²}/π for x̃ < cot θ (Heitz & d'Eon 2014, eq. 9 in slope
// space). Its x̃ marginal, scaled by cos θ, has the CDF
//   C(x) = cos θ (1 + erf x)/2 + sin θ e^{−x²}/(2√π),   C'(x) = (cos θ − x sin θ) e^{−x²}/√π,
// whose value at x = cot θ is cos θ (1 + Λ(θ)).
double sample_beckmann_slope_x(double cos_t, double sin_t, double u) {
    const double inv_sqrt_pi = 1.0 / std::sqrt(M_PI);
    auto cdf = [&](double x) {
        return cos_t * 0.5 * (1.0 + std::erf(x)) + sin_t * 0.5 * inv_sqrt_pi * std::exp(-x * x);
    };
    double lo = -8.0, hi = sin_t > 0.0 ? std::min(8.0, cos_t / sin_t) : 8.0;
    double target = u * cdf(hi);
    double x = clamp(erfinv(2.0 * u - 1.0), lo, hi);  // exact at normal incidence
    for (int it = 0; it < 64; ++it) {
        double f = cdf(x) - target;
        if (f > 0.0) hi = x; else lo = x;
        double d = (cos_t - x * sin_t) * std::exp(-x * x) * inv_sqrt_pi;
        double xn = d > 0.0 ? x - f / d : 0.5 * (lo + hi);
        if (!(xn > lo && xn < hi)) xn = 0.5 * (lo + hi);
        if (std::fabs(xn - x) < 1e-9 || hi - lo < 1e-9) { x = xn; break; }
        x = xn;
    }
    return x;
}
}  // namespace

Vec3f Beckmann::sample_visible(const Vec3f& wo, const Vec2f& u) const {
    Vec3f w = wo.z < 0.f ? -wo : wo;
    // Stretch to the unit-roughness configuration (Heitz & d'Eon 2014, §4 step 1).
    Vec3f ws = normalize(Vec3f(m_ax * w.x, m_ay * w.y, w.z));
    double cos_t = std::max(0.f, ws.z), sin_t = std::sqrt(std::max(0.0, 1.0 - cos_t * cos_t));
    double cos_p = 1.0, sin_p = 0.0;
    double rxy = std::sqrt(double(ws.x) * ws.x + double(ws.y) * ws.y);
    if (rxy > 0.0) {
        cos_p = ws.x / rxy;
        sin_p = ws.y / rxy;
    }
    // Sample the two slopes, rotate to the azimuth of wo, unstretch (steps 2–4).
    double sx = sample_beckmann_slope_x(cos_t, sin_t, u.x);
    double sy = erfinv(clamp(2.0 * double(u.y) - 1.0, -1.0 + 1e-12, 1.0 - 1e-12));
    double tx = cos_p * sx - sin_p * sy, ty = sin_p * sx + cos_p * sy;
    tx *= m_ax;
    ty *= m_ay;
    if (!std::isfinite(tx) || !std::isfinite(ty)) return Vec3f(0.f, 0.f, 1.f);
    Vec3d m = glm::normalize(Vec3d(-tx, -ty, 1.0));
    return Vec3f(float(m.x), float(m.y), float(m.z));
}
}  // namespace pellucid
