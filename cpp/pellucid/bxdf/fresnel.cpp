// Conductor Fresnel and the hemispherical Fresnel averages (quadrature).
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/bxdf/fresnel.h"

#include <complex>
#include <cstring>

#include "pellucid/bxdf/quadrature.h"

namespace pellucid {

double fresnel_conductor_1(double cos_i, double eta, double k) {
    cos_i = std::min(1.0, std::max(0.0, cos_i));
    if (eta == 0.0 && k == 0.0) return 1.0;  // degenerate input: treat as a perfect mirror
    using C = std::complex<double>;
    C n(eta, k);
    double sin2_i = 1.0 - cos_i * cos_i;
    // n·cos θt = sqrt(n² − sin² θi) (principal root: Re ≥ 0, the transmitted wave decays).
    C n_cos_t = std::sqrt(n * n - C(sin2_i, 0.0));
    C cos_t = n_cos_t / n;
    C r_parl = (n * cos_i - cos_t) / (n * cos_i + cos_t);
    C r_perp = (cos_i - n_cos_t) / (cos_i + n_cos_t);
    double r = 0.5 * (std::norm(r_parl) + std::norm(r_perp));
    return std::isfinite(r) ? std::min(1.0, std::max(0.0, r)) : 1.0;
}

float fresnel_dielectric_average(float eta) {
    // 2∫₀¹ F(μ) μ dμ. For η < 1, F = 1 below the critical cosine μc = sqrt(1 − η²), so that part
    // integrates to μc² exactly and the smooth part is integrated separately.
    if (eta == 1.f) return 0.f;
    double mu_c = eta < 1.f ? std::sqrt(std::max(0.0, 1.0 - double(eta) * eta)) : 0.0;
    double sum = mu_c * mu_c;
    // Substituting μ = μc + (1 − μc) t² removes the √(μ − μc) singularity of F at the critical
    // angle, so the 32-point rule converges fully.
    double w = 1.0 - mu_c;
    sum += 2.0 * integrate_gauss_legendre(
                     [&](double t) {
                         double mu = mu_c + w * t * t;
                         return fresnel_dielectric_d(mu, eta) * mu * 2.0 * w * t;
                     },
                     0.0, 1.0);
    return float(std::min(1.0, sum));
}

Spectrum fresnel_conductor_average(const Spectrum& eta, const Spectrum& k) {
    Spectrum r;
    for (int c = 0; c < 3; ++c)
        r[c] = float(2.0 * integrate_gauss_legendre(
                               [&](double mu) { return fresnel_conductor_1(mu, eta[c], k[c]) * mu; }, 0.0, 1.0));
    return r;
}

namespace {
bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool same_bits(const Spectrum& a, const Spectrum& b) {
    return same_bits(a.r, b.r) && same_bits(a.g, b.g) && same_bits(a.b, b.b);
}
}  // namespace

DielectricFresnelAverage DielectricFresnelAverage::of(float eta) {
    return DielectricFresnelAverage{eta, fresnel_dielectric_average(eta)};
}
float DielectricFresnelAverage::get(float e) const {
    return same_bits(e, eta) ? value : fresnel_dielectric_average(e);
}

ConductorFresnelAverage ConductorFresnelAverage::of(const ConductorFresnel& f) {
    return ConductorFresnelAverage{f, f.average(), true};
}
Spectrum ConductorFresnelAverage::get(const ConductorFresnel& f) const {
    const bool same = valid && f.schlick == fresnel.schlick && same_bits(f.eta, fresnel.eta) &&
                      same_bits(f.k, fresnel.k) && same_bits(f.r0, fresnel.r0);
    return same ? value : f.average();
}
}  // namespace pellucid
