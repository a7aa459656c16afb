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

Principled::Principled(const PrincipledInputs& p) {
    PrincipledInputs c = p;
    c.base_color = clamp_zero(p.base_color);
    for (float* v : {&c.metallic, &c.roughness, &c.specular, &c.specular_tint, &c.sheen, &c.sheen_tint, &c.clearcoat,
                     &c.clearcoat_gloss, &c.anisotropic})
        *v = unit(*v);
    m_specular = c.specular, m_specular_tint = c.specular_tint, m_sheen_tint = c.sheen_tint;
    m_clearcoat_gloss = c.clearcoat_gloss, m_anisotropic = c.anisotropic;
    const float lum = c.base_color.luminance();
    const Spectrum tint = lum > 0.f ? c.base_color / lum : Spectrum(1.f);
    m_l.base = c.base_color;
    m_l.cspec0 = lerp(c.specular * 0.08f * lerp(Spectrum(1.f), tint, c.specular_tint), c.base_color, c.metallic);
    m_l.csheen = lerp(Spectrum(1.f), tint, c.sheen_tint);
    m_l.metallic = c.metallic;
    m_l.roughness = c.roughness;
    m_l.sheen = c.sheen;
    m_l.clearcoat = c.clearcoat;
    m_l.cc_alpha = lerp(0.1f, 0.001f, c.clearcoat_gloss);
    m_l.cc_log_a2 = std::log(m_l.cc_alpha * m_l.cc_alpha);
    const bool has_diffuse = c.metallic < 1.f && (!c.base_color.is_black() || c.sheen > 0.f);
    m_l.w_diffuse = has_diffuse ? 1.f - c.metallic : 0.f;
    // Specular α (§5.4): α = roughness², aspect = sqrt(1 − 0.9 anisotropic).
    const float a = sqr(c.roughness), aspect = std::sqrt(1.f - 0.9f * c.anisotropic);
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
    return "Principled[base_color=" + m_l.base.to_string() + n("metallic", m_l.metallic) +
           n("roughness", m_l.roughness) + n("specular", m_specular) + n("specular_tint", m_specular_tint) +
           n("sheen", m_l.sheen) + n("sheen_tint", m_sheen_tint) + n("clearcoat", m_l.clearcoat) +
           n("clearcoat_gloss", m_clearcoat_gloss) + n("anisotropic", m_anisotropic) + "]";
}
}  // namespace pellucid
