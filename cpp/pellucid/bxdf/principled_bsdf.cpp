// Disney principled BSDF (Burley 2015); definitions and references in principled_bsdf.h.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/bxdf/principled_bsdf.h"

#include <cmath>

#include "pellucid/bxdf/disney_common.h"
#include "pellucid/bxdf/fresnel.h"
#include "pellucid/math/spherical.h"
#include "pellucid/sampling/warp.h"

namespace pellucid {
namespace {
using disney::lerp;
using disney::unit;
using principled_detail::allows;
}  // namespace

// The double instantiation of principled_half_d (principled_bsdf.h), rounded to float.
principled_detail::PrincipledHalf principled_detail::principled_half(const Vec3f& wo, const Vec3f& wi, float eta) {
    // The half vector in double: wo·h and wi·h of nearly orthogonal vectors otherwise lose most
    // digits (as in RoughDielectric), which breaks the transmission's η² symmetry in the tails.
    const PrincipledHalfD<double> d = principled_half_d<double>(Vec3P<double>(wo.x, wo.y, wo.z),
                                                                Vec3P<double>(wi.x, wi.y, wi.z), double(eta));
    PrincipledHalf out;
    out.h = Vec3f(float(d.h.x), float(d.h.y), float(d.h.z));
    out.dot_o = float(d.dot_o), out.dot_i = float(d.dot_i), out.F = float(d.F), out.denom = float(d.denom);
    out.etap = float(d.etap);
    out.ok = d.ok != 0.0;
    return out;
}

Vec3f principled_detail::principled_gtr1_normal(float alpha, const Vec2f& u) {
    const float a2 = alpha * alpha;
    const float c2 = (1.f - std::pow(a2, 1.f - u.y)) / (1.f - a2);
    return spherical_direction(safe_sqrt(1.f - c2), safe_sqrt(c2), 2.f * kPi * u.x);
}

float PrincipledBSDF::eta_from_specular(float specular) {
    return 2.f / (1.f - std::sqrt(0.08f * std::max(specular, 0.f))) - 1.f;
}

Vec2f PrincipledBSDF::alpha_from_roughness(float roughness, float anisotropic) {
    float r2 = sqr(roughness), s = std::sqrt(1.f - 0.9f * anisotropic);
    return Vec2f(std::max(1e-3f, r2 / s), std::max(1e-3f, r2 * s));
}

// Incident side: cos_i ≥ 0 sees η, the other side 1/η. From the denser side Schlick's weight takes
// the transmitted cosine (Schlick 1994 is stated for the less dense side).
float PrincipledBSDF::schlick(float r0, float cos_i, float eta) { return principled_detail::schlick<float>(r0, cos_i, eta); }
Spectrum PrincipledBSDF::schlick(const Spectrum& r0, float cos_i, float eta) {
    return principled_detail::schlick<float>(r0, cos_i, eta);
}

PrincipledBSDF::PrincipledBSDF(const PrincipledInputs& p) : m_spec(1.f), m_trans(1.f) {
    m_thin = p.thin;
    m_base = clamp_zero(p.base_color);
    for (int c = 0; c < 3; ++c)
        if (!std::isfinite(m_base[c])) m_base[c] = 0.f;
    float lum = m_base.luminance();
    m_tint = lum > 0.f ? m_base / lum : Spectrum(1.f);
    m_metallic = m_thin ? 0.f : unit(p.metallic);
    m_roughness = unit(p.roughness);
    m_spec_trans = unit(p.specular_transmission);
    m_spec_tint = unit(p.specular_tint);
    m_sheen = unit(p.sheen);
    m_sheen_tint = unit(p.sheen_tint);
    m_flatness = unit(p.flatness);
    m_clearcoat = m_thin ? 0.f : unit(p.clearcoat);
    m_cc_alpha = lerp(0.1f, 0.001f, unit(p.clearcoat_gloss));
    m_cc_log_a2 = std::log(m_cc_alpha * m_cc_alpha);
    m_diff_trans = m_thin ? 0.5f * clamp(std::isfinite(p.diffuse_transmission) ? p.diffuse_transmission : 0.f, 0.f, 2.f)
                          : 0.f;
    // η: given, or from `specular` (header comment); a refracting lobe needs η ≠ 1.
    bool refracts = !m_thin && m_spec_trans > 0.f;
    if (p.eta > 0.f && std::isfinite(p.eta)) {
        m_eta = p.eta == 1.f && refracts ? 1.001f : p.eta;
    } else {
        float s = unit(p.specular);
        if (s == 0.f && refracts) s = 1e-3f;
        m_eta = eta_from_specular(s);
    }
    m_w_brdf = (1.f - m_metallic) * (1.f - m_spec_trans);
    m_w_bsdf = (1.f - m_metallic) * m_spec_trans;
    float aniso = unit(p.anisotropic);
    Vec2f a = alpha_from_roughness(m_roughness, aniso);
    m_spec = GGX(a.x, a.y);
    // Thin transmission: roughness × (0.65η − 0.35) (Burley 2015, Fig. 15); α = r'² is even in r'.
    Vec2f at = alpha_from_roughness((0.65f * m_eta - 0.35f) * m_roughness, aniso);
    m_trans = GGX(at.x, at.y);
}

// ---- interface ------------------------------------------------------------------------------
Spectrum PrincipledBSDF::eval(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const {
    if (has_lanes()) return lanes().eval_pdf(ctx, wo, wi, true).f;
    if (m_thin) return thin_lanes().eval_pdf(ctx, wo, wi, true).f;
    return solid_lanes().eval_pdf(ctx, wo, wi, true).f;
}
float PrincipledBSDF::pdf(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const {
    if (has_lanes()) return lanes().eval_pdf(ctx, wo, wi, true).pdf;
    if (m_thin) return thin_lanes().eval_pdf(ctx, wo, wi, true).pdf;
    return solid_lanes().eval_pdf(ctx, wo, wi, true).pdf;
}
std::optional<BxDFSample> PrincipledBSDF::sample(const BxDFContext& ctx, const Vec3f& wo, float u_lobe,
                                                 const Vec2f& u) const {
    if (has_lanes()) return to_optional(lanes().sample(ctx, wo, u_lobe, u, true));
    if (m_thin) return to_optional(thin_lanes().sample(ctx, wo, u_lobe, u, true));
    return to_optional(solid_lanes().sample(ctx, wo, u_lobe, u, true));
}

BxDFFlags PrincipledBSDF::flags() const {
    BxDFFlags f = BxDFFlags::None;
    if (m_thin) {
        if (m_spec_trans > 0.f) f |= BxDFFlags::GlossyReflection | BxDFFlags::GlossyTransmission;
        if ((1.f - m_spec_trans) * (1.f - m_diff_trans) > 0.f) f |= BxDFFlags::DiffuseReflection;
        if ((1.f - m_spec_trans) * m_diff_trans > 0.f) f |= BxDFFlags::DiffuseTransmission;
        return f;
    }
    f = BxDFFlags::GlossyReflection;
    if (m_w_brdf > 0.f) f |= BxDFFlags::DiffuseReflection;
    if (m_w_bsdf > 0.f) f |= BxDFFlags::GlossyTransmission;
    return f;
}

std::string PrincipledBSDF::to_string() const {
    auto n = [](const char* k, float v) { return std::string(", ") + k + "=" + std::to_string(v); };
    std::string s = std::string("PrincipledBSDF[") + (m_thin ? "thin, " : "") + "base_color=" + m_base.to_string() +
                    n("roughness", m_roughness) + n("eta", m_eta) + n("specular_transmission", m_spec_trans) +
                    n("specular_tint", m_spec_tint) + n("sheen", m_sheen) + n("sheen_tint", m_sheen_tint) +
                    n("flatness", m_flatness) + ", " + m_spec.to_string();
    if (m_thin) s += n("diffuse_transmission", 2.f * m_diff_trans);
    else s += n("metallic", m_metallic) + n("clearcoat", m_clearcoat) + n("clearcoat_alpha", m_cc_alpha);
    return s + "]";
}
}  // namespace pellucid
