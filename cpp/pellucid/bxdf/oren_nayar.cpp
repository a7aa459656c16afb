// Oren–Nayar (classic) and EON rough diffuse BRDFs.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/bxdf/oren_nayar.h"

#include "pellucid/sampling/warp.h"

namespace pellucid {
namespace {
constexpr float kC1 = 0.5f - 2.f / (3.f * kPi);           // EON eq. for A_F
constexpr float kC2 = 2.f / 3.f - 28.f / (15.f * kPi);    // EON eq. for Ē_F
}  // namespace

OrenNayar::OrenNayar(const Spectrum& reflectance, float roughness, OrenNayarVariant variant)
    : m_variant(variant), m_r(reflectance) {
    if (m_variant == OrenNayarVariant::Classic) {
        float s2 = sqr(roughness >= 0.f && std::isfinite(roughness) ? roughness : 0.f);
        m_rough = std::sqrt(s2);
        m_a = 1.f - 0.5f * s2 / (s2 + 0.33f);
        m_b = 0.45f * s2 / (s2 + 0.09f);
        return;
    }
    m_rough = std::isfinite(roughness) ? clamp(roughness, 0.f, 1.f) : 0.f;
    m_a = 1.f / (1.f + kC1 * m_rough);
    m_b = m_rough * m_a;
    if (m_rough > 0.f) {
        m_eavg = eon_average_albedo(m_rough);
        for (int c = 0; c < 3; ++c)
            m_rho_ms[c] = m_r[c] * m_r[c] * m_eavg / (1.f - m_r[c] * (1.f - m_eavg));
    }
}

float OrenNayar::eon_albedo(float mu, float r) {
    double m = clamp(double(mu), 1e-7, 1.0), a = 1.0 / (1.0 + kC1 * r), b = r * a;
    double si = std::sqrt(std::max(0.0, 1.0 - m * m));
    double g = si * (std::acos(m) - si * m) + (2.0 / 3.0) * ((si / m) * (1.0 - si * si * si) - si);
    return float(a + b / M_PI * g);
}
float OrenNayar::eon_average_albedo(float r) { return (1.f + kC2 * r) / (1.f + kC1 * r); }

Spectrum OrenNayar::eval(const BxDFContext&, const Vec3f& wo, const Vec3f& wi) const {
    if (!same_hemisphere(wo, wi)) return Spectrum(0.f);
    float co = std::fabs(wo.z), ci = std::fabs(wi.z);
    float s = dot(wo, wi) - wo.z * wi.z;  // sin θi sin θo cos(φi − φo)
    if (m_variant == OrenNayarVariant::Classic) {
        float term = std::max(0.f, s) / std::max(std::max(co, ci), 1e-7f);
        return m_r * (kInvPi * ci * (m_a + m_b * term));
    }
    float t = s > 0.f ? std::max(std::max(co, ci), 1e-7f) : 1.f;
    Spectrum f = m_r * (kInvPi * ci * (m_a + m_b * (s / t)));
    if (m_rough > 0.f) {
        float ms = (1.f - eon_albedo(co, m_rough)) * (1.f - eon_albedo(ci, m_rough)) /
                   std::max(1e-6f, 1.f - m_eavg);
        f += m_rho_ms * (kInvPi * ci * std::max(0.f, ms));
    }
    return clamp_zero(f);
}

float OrenNayar::pdf(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const {
    if (!has_flag(ctx.allowed, BxDFFlags::DiffuseReflection) || !same_hemisphere(wo, wi)) return 0.f;
    return square_to_cosine_hemisphere_pdf(Vec3f(wi.x, wi.y, std::fabs(wi.z)));
}

std::optional<BxDFSample> OrenNayar::sample(const BxDFContext& ctx, const Vec3f& wo, float, const Vec2f& u) const {
    if (!has_flag(ctx.allowed, BxDFFlags::Reflection) || wo.z == 0.f) return std::nullopt;
    Vec3f wi = square_to_cosine_hemisphere(u);
    if (wo.z < 0.f) wi.z = -wi.z;
    float p = square_to_cosine_hemisphere_pdf(Vec3f(wi.x, wi.y, std::fabs(wi.z)));
    if (!(p > 0.f)) return std::nullopt;
    BxDFSample s;
    s.wi = wi;
    s.pdf = p;
    s.weight = eval(ctx, wo, wi) / p;
    if (m_rough == 0.f) s.weight = m_r;  // σ = 0 / r = 0: exactly Lambertian
    s.lobe = BxDFFlags::DiffuseReflection;
    return s;
}

std::string OrenNayar::to_string() const {
    return std::string("OrenNayar[variant=") + (m_variant == OrenNayarVariant::Classic ? "classic" : "eon") +
           ", reflectance=" + m_r.to_string() +
           (m_variant == OrenNayarVariant::Classic ? ", sigma=" : ", roughness=") + std::to_string(m_rough) + "]";
}
}  // namespace pellucid
