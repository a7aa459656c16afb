// Disney principled BRDF.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/bxdf/principled.h"

#include "pellucid/bxdf/disney_common.h"
#include "pellucid/bxdf/fresnel.h"
#include "pellucid/math/spherical.h"
#include "pellucid/sampling/warp.h"

namespace pellucid {
namespace {
using disney::lerp;
using disney::schlick_weight;
using disney::unit;

GGX make_spec(float roughness, float anisotropic) {
    float a = sqr(roughness), aspect = std::sqrt(1.f - 0.9f * anisotropic);
    return GGX(std::max(1e-3f, a / aspect), std::max(1e-3f, a * aspect));
}
}  // namespace

Principled::Principled(const PrincipledParams& p) : m_p(p), m_spec(1.f) {
    m_p.base_color = clamp_zero(p.base_color);
    for (float* v : {&m_p.metallic, &m_p.roughness, &m_p.specular, &m_p.specular_tint, &m_p.sheen,
                     &m_p.sheen_tint, &m_p.clearcoat, &m_p.clearcoat_gloss, &m_p.anisotropic})
        *v = unit(*v);
    float lum = m_p.base_color.luminance();
    Spectrum tint = lum > 0.f ? m_p.base_color / lum : Spectrum(1.f);
    m_cspec0 = lerp(m_p.specular * 0.08f * lerp(Spectrum(1.f), tint, m_p.specular_tint), m_p.base_color, m_p.metallic);
    m_csheen = lerp(Spectrum(1.f), tint, m_p.sheen_tint);
    m_spec = make_spec(m_p.roughness, m_p.anisotropic);
    m_cc_alpha = lerp(0.1f, 0.001f, m_p.clearcoat_gloss);
}

float Principled::gtr1(float cos_h, float alpha) {
    if (alpha >= 1.f) return kInvPi;
    float a2 = alpha * alpha, t = 1.f + (a2 - 1.f) * cos_h * cos_h;
    return (a2 - 1.f) / (kPi * std::log(a2) * t);
}

Spectrum Principled::eval(const BxDFContext&, const Vec3f& wo, const Vec3f& wi) const {
    if (!same_hemisphere(wo, wi)) return Spectrum(0.f);
    Vec3f o = wo.z < 0.f ? -wo : wo, i = wo.z < 0.f ? -wi : wi;
    Vec3f hh = o + i;
    if (!(length2(hh) > 0.f)) return Spectrum(0.f);
    Vec3f h = normalize(hh);
    float co = std::max(o.z, 1e-7f), ci = std::max(i.z, 1e-7f), cd = clamp(dot(i, h), 0.f, 1.f);
    // Diffuse with retro-reflection and sheen (§5.3, §5.5).
    float fd90 = 0.5f + 2.f * m_p.roughness * cd * cd;
    float fd = (1.f + (fd90 - 1.f) * schlick_weight(ci)) * (1.f + (fd90 - 1.f) * schlick_weight(co));
    Spectrum f = (m_p.base_color * (kInvPi * fd) + m_csheen * (m_p.sheen * schlick_weight(cd))) * (1.f - m_p.metallic);
    // Specular (§5.4).
    Spectrum fs = fresnel_schlick(cd, m_cspec0);
    f += fs * (m_spec.D(h) * m_spec.G(o, i) / (4.f * co * ci));
    // Clearcoat (§5.6).
    if (m_p.clearcoat > 0.f) {
        float fc = fresnel_schlick(cd, 0.04f);
        f += Spectrum(0.25f * m_p.clearcoat * gtr1(h.z, m_cc_alpha) * m_cc_g.G(o, i) * fc / (4.f * co * ci));
    }
    return f * ci;
}

void Principled::lobe_probs(const BxDFContext& ctx, float p[3]) const {
    bool diff_ok = has_flag(ctx.allowed, BxDFFlags::Diffuse), gl_ok = has_flag(ctx.allowed, BxDFFlags::Glossy);
    bool has_diffuse = m_p.metallic < 1.f && (!m_p.base_color.is_black() || m_p.sheen > 0.f);
    p[0] = diff_ok && has_diffuse ? 1.f - m_p.metallic : 0.f;
    p[1] = gl_ok ? 1.f : 0.f;
    p[2] = gl_ok ? 0.25f * m_p.clearcoat : 0.f;
    float s = p[0] + p[1] + p[2];
    for (int k = 0; k < 3; ++k) p[k] = s > 0.f ? p[k] / s : 0.f;
}

float Principled::lobe_pdf(int lobe, const Vec3f& o, const Vec3f& i) const {
    if (lobe == 0) return i.z * kInvPi;
    Vec3f h = normalize(o + i);
    float c = dot(o, h);
    if (!(c > 0.f)) return 0.f;
    if (lobe == 1) return m_spec.pdf_visible(o, h) / (4.f * c);
    return gtr1(h.z, m_cc_alpha) * h.z / (4.f * c);
}

float Principled::pdf(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const {
    if (!same_hemisphere(wo, wi) || !has_flag(ctx.allowed, BxDFFlags::Reflection)) return 0.f;
    Vec3f o = wo.z < 0.f ? -wo : wo, i = wo.z < 0.f ? -wi : wi;
    if (!(length2(o + i) > 0.f)) return 0.f;
    float p[3], sum = 0.f;
    lobe_probs(ctx, p);
    for (int k = 0; k < 3; ++k)
        if (p[k] > 0.f) sum += p[k] * lobe_pdf(k, o, i);
    return sum;
}

std::optional<BxDFSample> Principled::sample(const BxDFContext& ctx, const Vec3f& wo, float u_lobe,
                                             const Vec2f& u) const {
    if (wo.z == 0.f || !has_flag(ctx.allowed, BxDFFlags::Reflection)) return std::nullopt;
    float p[3];
    lobe_probs(ctx, p);
    Vec3f o = wo.z < 0.f ? -wo : wo, i;
    int lobe = u_lobe < p[0] ? 0 : (u_lobe < p[0] + p[1] ? 1 : 2);
    if (p[lobe] <= 0.f) return std::nullopt;
    if (lobe == 0) {
        i = square_to_cosine_hemisphere(u);
    } else if (lobe == 1) {
        i = reflect(o, m_spec.sample_visible(o, u));
    } else {
        // GTR1 half vector: cos² θh = (1 − α^{2(1−u)})/(1 − α²) (Burley 2012, App. B eq. 5).
        float a2 = m_cc_alpha * m_cc_alpha;
        float c2 = (1.f - std::pow(a2, 1.f - u.x)) / (1.f - a2);
        float ct = safe_sqrt(c2), st = safe_sqrt(1.f - c2);
        i = reflect(o, spherical_direction(st, ct, 2.f * kPi * u.y));
    }
    if (i.z <= 0.f) return std::nullopt;
    BxDFSample s;
    s.wi = wo.z < 0.f ? -i : i;
    s.pdf = pdf(ctx, wo, s.wi);
    if (!(s.pdf > 0.f)) return std::nullopt;
    s.weight = eval(ctx, wo, s.wi) / s.pdf;
    s.lobe = lobe == 0 ? BxDFFlags::DiffuseReflection : BxDFFlags::GlossyReflection;
    return s;
}

BxDFFlags Principled::flags() const {
    BxDFFlags f = BxDFFlags::GlossyReflection;
    if (m_p.metallic < 1.f && (!m_p.base_color.is_black() || m_p.sheen > 0.f)) f |= BxDFFlags::DiffuseReflection;
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
