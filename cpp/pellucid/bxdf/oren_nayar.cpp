// Oren–Nayar (classic) and EON rough diffuse BRDFs.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/bxdf/oren_nayar.h"

#include "pellucid/sampling/warp.h"

namespace pellucid {
namespace {
constexpr float kC1 = 0.5f - 2.f / (3.f * kPi);           // EON eq. for A_F
constexpr float kC2 = 2.f / 3.f - 28.f / (15.f * kPi);    // EON eq. for Ē_F
}  // namespace

OrenNayar::OrenNayar(const Spectrum& reflectance, float roughness, OrenNayarVariant variant) : m_variant(variant) {
    OrenNayarT<float>& l = m_l;
    l.r = reflectance;
    l.eavg = 1.f;
    l.rho_ms = Spectrum(0.f);
    l.classic = m_variant == OrenNayarVariant::Classic;
    if (l.classic) {
        float s2 = sqr(roughness >= 0.f && std::isfinite(roughness) ? roughness : 0.f);
        l.rough = std::sqrt(s2);
        l.a = 1.f - 0.5f * s2 / (s2 + 0.33f);
        l.b = 0.45f * s2 / (s2 + 0.09f);
        return;
    }
    l.rough = std::isfinite(roughness) ? clamp(roughness, 0.f, 1.f) : 0.f;
    l.a = 1.f / (1.f + kC1 * l.rough);
    l.b = l.rough * l.a;
    if (l.rough > 0.f) {
        l.eavg = eon_average_albedo(l.rough);
        for (int c = 0; c < 3; ++c) l.rho_ms[c] = l.r[c] * l.r[c] * l.eavg / (1.f - l.r[c] * (1.f - l.eavg));
    }
}

float eon_albedo(float mu, float r) {
    double m = clamp(double(mu), 1e-7, 1.0), a = 1.0 / (1.0 + kC1 * r), b = r * a;
    double si = std::sqrt(std::max(0.0, 1.0 - m * m));
    double g = si * (std::acos(m) - si * m) + (2.0 / 3.0) * ((si / m) * (1.0 - si * si * si) - si);
    return float(a + b / M_PI * g);
}
float OrenNayar::eon_average_albedo(float r) { return (1.f + kC2 * r) / (1.f + kC1 * r); }

std::string OrenNayar::to_string() const {
    return std::string("OrenNayar[variant=") + (m_variant == OrenNayarVariant::Classic ? "classic" : "eon") +
           ", reflectance=" + m_l.r.to_string() +
           (m_variant == OrenNayarVariant::Classic ? ", sigma=" : ", roughness=") + std::to_string(m_l.rough) + "]";
}
}  // namespace pellucid
