// Disney principled BRDF.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/bxdf/principled.h"

#include <cmath>

#include "pellucid/bxdf/disney_common.h"
#include "pellucid/math/spherical.h"

namespace pellucid {
namespace {
using disney::lerp;
using disney::unit;
}  // namespace

Vec3f principled2012_detail::principled2012_gtr1_normal(float alpha, const Vec2f& u) {
    const float a2 = alpha * alpha;
    const float c2 = (1.f - std::pow(a2, 1.f - u.x)) / (1.f - a2);
    const float ct = safe_sqrt(c2), st = safe_sqrt(1.f - c2);
    return spherical_direction(st, ct, 2.f * kPi * u.y);
}

Principled::Principled(const PrincipledParams& p) : m_p(p) {
    m_p.base_color = clamp_zero(p.base_color);
    for (float* v : {&m_p.metallic, &m_p.roughness, &m_p.specular, &m_p.specular_tint, &m_p.sheen,
                     &m_p.sheen_tint, &m_p.clearcoat, &m_p.clearcoat_gloss, &m_p.anisotropic})
        *v = unit(*v);
    const float lum = m_p.base_color.luminance();
    const Spectrum tint = lum > 0.f ? m_p.base_color / lum : Spectrum(1.f);
    m_l.base = m_p.base_color;
    m_l.cspec0 = lerp(m_p.specular * 0.08f * lerp(Spectrum(1.f), tint, m_p.specular_tint), m_p.base_color, m_p.metallic);
    m_l.csheen = lerp(Spectrum(1.f), tint, m_p.sheen_tint);
    m_l.metallic = m_p.metallic;
    m_l.roughness = m_p.roughness;
    m_l.sheen = m_p.sheen;
    m_l.clearcoat = m_p.clearcoat;
    m_l.cc_alpha = lerp(0.1f, 0.001f, m_p.clearcoat_gloss);
    m_l.cc_log_a2 = std::log(m_l.cc_alpha * m_l.cc_alpha);
    const bool has_diffuse = m_p.metallic < 1.f && (!m_p.base_color.is_black() || m_p.sheen > 0.f);
    m_l.w_diffuse = has_diffuse ? 1.f - m_p.metallic : 0.f;
    // Specular α (§5.4): α = roughness², aspect = sqrt(1 − 0.9 anisotropic).
    const float a = sqr(m_p.roughness), aspect = std::sqrt(1.f - 0.9f * m_p.anisotropic);
    m_l.spec = GGX(std::max(1e-3f, a / aspect), std::max(1e-3f, a * aspect)).lanes();
}

float Principled::gtr1(float cos_h, float alpha) {
    if (alpha >= 1.f) return kInvPi;
    return principled2012_detail::gtr1<float>(cos_h, alpha, std::log(alpha * alpha));
}

BxDFFlags Principled::flags() const {
    BxDFFlags f = BxDFFlags::GlossyReflection;
    if (m_l.w_diffuse > 0.f) f |= BxDFFlags::DiffuseReflection;
    return f;
}

std::string Principled::to_string() const {
    auto n = [](const char* k, float v) { return std::string(", ") + k + "=" + std::to_string(v); };
    return "Principled[base_color=" + m_p.base_color.to_string() + n("metallic", m_p.metallic) +
           n("roughness", m_p.roughness) + n("specular", m_p.specular) + n("specular_tint", m_p.specular_tint) +
           n("sheen", m_p.sheen) + n("sheen_tint", m_p.sheen_tint) + n("clearcoat", m_p.clearcoat) +
           n("clearcoat_gloss", m_p.clearcoat_gloss) + n("anisotropic", m_p.anisotropic) + "]";
}
}  // namespace pellucid
