// Smooth and rough plastic.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/bxdf/plastic.h"

#include "pellucid/sampling/warp.h"

namespace pellucid {

std::string to_string(PlasticVariant v) { return v == PlasticVariant::Coupled ? "coupled" : "sum"; }

PlasticBase::PlasticBase(float eta, const Spectrum& kd, const Spectrum& ks, PlasticVariant variant)
    : m_eta(eta > 0.f && std::isfinite(eta) ? eta : 1.f), m_kd(kd), m_ks(ks), m_variant(variant) {
    if (m_variant == PlasticVariant::Sum) {
        m_diffuse_scale = m_kd;
        return;
    }
    float f_dri = 1.f - (1.f - fresnel_dielectric_average(m_eta)) / (m_eta * m_eta);
    for (int c = 0; c < 3; ++c)
        m_diffuse_scale[c] = m_kd[c] / (m_eta * m_eta * std::max(1e-6f, 1.f - m_kd[c] * f_dri));
}

Spectrum PlasticBase::diffuse(float cos_o, float cos_i) const {
    if (m_variant == PlasticVariant::Sum) return m_diffuse_scale * (kInvPi * cos_i);
    float t = (1.f - fresnel_dielectric(cos_i, m_eta)) * (1.f - fresnel_dielectric(cos_o, m_eta));
    return m_diffuse_scale * (t * kInvPi * cos_i);
}

float PlasticBase::coat_probability(float cos_o) const {
    float F = fresnel_dielectric(cos_o, m_eta);
    float s = F * m_ks.average();
    float d = (m_variant == PlasticVariant::Coupled ? (1.f - F) : 1.f) * m_kd.average();
    return s + d > 0.f ? s / (s + d) : 0.f;
}

std::string PlasticBase::params() const {
    return "eta=" + std::to_string(m_eta) + ", diffuse_reflectance=" + m_kd.to_string() +
           ", specular_reflectance=" + m_ks.to_string() + ", variant=" + pellucid::to_string(m_variant);
}

// ---------------------------------------------------------------------------------------------
Spectrum SmoothPlastic::eval(const BxDFContext&, const Vec3f& wo, const Vec3f& wi) const {
    if (!same_hemisphere(wo, wi)) return Spectrum(0.f);
    return m_base.diffuse(std::fabs(wo.z), std::fabs(wi.z));
}
float SmoothPlastic::pdf(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const {
    if (!same_hemisphere(wo, wi) || !has_flag(ctx.allowed, BxDFFlags::DiffuseReflection)) return 0.f;
    float p_coat = has_flag(ctx.allowed, BxDFFlags::Specular) ? m_base.coat_probability(std::fabs(wo.z)) : 0.f;
    return (1.f - p_coat) * std::fabs(wi.z) * kInvPi;
}
std::optional<BxDFSample> SmoothPlastic::sample(const BxDFContext& ctx, const Vec3f& wo, float u_lobe,
                                                const Vec2f& u) const {
    if (wo.z == 0.f || !has_flag(ctx.allowed, BxDFFlags::Reflection)) return std::nullopt;
    float co = std::fabs(wo.z);
    bool spec_ok = has_flag(ctx.allowed, BxDFFlags::Specular), diff_ok = has_flag(ctx.allowed, BxDFFlags::Diffuse);
    float p_coat = spec_ok ? (diff_ok ? m_base.coat_probability(co) : 1.f) : 0.f;
    BxDFSample s;
    if (u_lobe < p_coat) {
        s.wi = Vec3f(-wo.x, -wo.y, wo.z);
        s.pdf = p_coat;
        s.weight = m_base.ks() * (fresnel_dielectric(co, m_base.eta()) / p_coat);
        s.lobe = BxDFFlags::SpecularReflection;
        return s;
    }
    if (!diff_ok) return std::nullopt;
    s.wi = square_to_cosine_hemisphere(u);
    if (wo.z < 0.f) s.wi.z = -s.wi.z;
    s.pdf = pdf(ctx, wo, s.wi);
    if (!(s.pdf > 0.f)) return std::nullopt;
    s.weight = eval(ctx, wo, s.wi) / s.pdf;
    s.lobe = BxDFFlags::DiffuseReflection;
    return s;
}
BxDFFlags SmoothPlastic::flags() const {
    BxDFFlags f = BxDFFlags::None;
    if (!m_base.ks().is_black() && m_base.eta() != 1.f) f |= BxDFFlags::SpecularReflection;
    if (!m_base.diffuse(1.f, 1.f).is_black()) f |= BxDFFlags::DiffuseReflection;
    return f;
}

// ---------------------------------------------------------------------------------------------
template <class D>
Spectrum RoughPlastic<D>::eval(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const {
    if (smooth()) return SmoothPlastic(m_base).eval(ctx, wo, wi);
    if (!same_hemisphere(wo, wi)) return Spectrum(0.f);
    return m_coat.eval(ctx, wo, wi) + m_base.diffuse(std::fabs(wo.z), std::fabs(wi.z));
}
template <class D>
float RoughPlastic<D>::pdf(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const {
    if (smooth()) return SmoothPlastic(m_base).pdf(ctx, wo, wi);
    if (!same_hemisphere(wo, wi)) return 0.f;
    bool spec_ok = has_flag(ctx.allowed, BxDFFlags::Glossy), diff_ok = has_flag(ctx.allowed, BxDFFlags::Diffuse);
    float p_coat = spec_ok ? (diff_ok ? m_base.coat_probability(std::fabs(wo.z)) : 1.f) : 0.f;
    float p = p_coat > 0.f ? p_coat * m_coat.pdf(ctx, wo, wi) : 0.f;
    return p + (diff_ok ? (1.f - p_coat) * std::fabs(wi.z) * kInvPi : 0.f);
}
template <class D>
std::optional<BxDFSample> RoughPlastic<D>::sample(const BxDFContext& ctx, const Vec3f& wo, float u_lobe,
                                                  const Vec2f& u) const {
    if (smooth()) return SmoothPlastic(m_base).sample(ctx, wo, u_lobe, u);
    if (wo.z == 0.f || !has_flag(ctx.allowed, BxDFFlags::Reflection)) return std::nullopt;
    bool spec_ok = has_flag(ctx.allowed, BxDFFlags::Glossy), diff_ok = has_flag(ctx.allowed, BxDFFlags::Diffuse);
    float p_coat = spec_ok ? (diff_ok ? m_base.coat_probability(std::fabs(wo.z)) : 1.f) : 0.f;
    Vec3f wi;
    if (u_lobe < p_coat) {
        auto s = m_coat.sample(ctx, wo, 0.5f, u);
        if (!s) return std::nullopt;
        wi = s->wi;
    } else {
        if (!diff_ok) return std::nullopt;
        wi = square_to_cosine_hemisphere(u);
        if (wo.z < 0.f) wi.z = -wi.z;
    }
    BxDFSample s;
    s.wi = wi;
    s.pdf = pdf(ctx, wo, wi);
    if (!(s.pdf > 0.f)) return std::nullopt;
    s.weight = eval(ctx, wo, wi) / s.pdf;
    s.lobe = u_lobe < p_coat ? BxDFFlags::GlossyReflection : BxDFFlags::DiffuseReflection;
    return s;
}
template <class D>
BxDFFlags RoughPlastic<D>::flags() const {
    if (smooth()) return SmoothPlastic(m_base).flags();
    BxDFFlags f = BxDFFlags::None;
    if (!m_base.ks().is_black() && m_base.eta() != 1.f) f |= BxDFFlags::GlossyReflection;
    if (!m_base.diffuse(1.f, 1.f).is_black()) f |= BxDFFlags::DiffuseReflection;
    return f;
}

template class RoughPlastic<GGX>;
template class RoughPlastic<Beckmann>;
}  // namespace pellucid
