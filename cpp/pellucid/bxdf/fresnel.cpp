// Conductor Fresnel and the hemispherical Fresnel averages (quadrature).
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/bxdf/fresnel.h"

#include <array>
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

namespace {
// Textured materials rebuild their BxDF at every hit (material/textured.cpp), but an IOR is almost
// never textured: the last quadrature's input and result, kept per thread, make it run once a
// material instead of once a hit. Keys compare bit for bit (a NaN key never matches).
template <class Key, class Value>
struct LastValue {
    Key key;
    Value value;
    bool valid = false;
    template <class F>
    Value get(const Key& k, F&& compute) {
        if (valid && std::memcmp(&key, &k, sizeof(Key)) == 0) return value;
        value = compute();
        key = k;
        valid = true;
        return value;
    }
};
float fresnel_dielectric_average_uncached(float eta);
}  // namespace

float fresnel_dielectric_average(float eta) {
    thread_local LastValue<float, float> last;
    return last.get(eta, [&] { return fresnel_dielectric_average_uncached(eta); });
}

namespace {
float fresnel_dielectric_average_uncached(float eta) {
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
}  // namespace

Spectrum fresnel_conductor_average(const Spectrum& eta, const Spectrum& k) {
    thread_local LastValue<std::array<float, 6>, Spectrum> last;
    const std::array<float, 6> key{eta[0], eta[1], eta[2], k[0], k[1], k[2]};
    return last.get(key, [&] {
        Spectrum r;
        for (int c = 0; c < 3; ++c)
            r[c] = float(2.0 * integrate_gauss_legendre(
                                   [&](double mu) { return fresnel_conductor_1(mu, eta[c], k[c]) * mu; },
                                   0.0, 1.0));
        return r;
    });
}
}  // namespace pellucid
