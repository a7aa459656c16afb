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
float r0_of_eta(float eta) { return sqr((eta - 1.f) / (eta + 1.f)); }

/// Separable masking–shadowing G1(wo)·G1(wi) (Heitz 2014, eq. 98).
float g_separable(const GGX& d, const Vec3f& wo, const Vec3f& wi, const Vec3f& h) {
    const GGXT<float> l = d.lanes();
    return principled_detail::g1<float>(l, wo, h) * principled_detail::g1<float>(l, wi, h);
}
}  // namespace

principled_detail::PrincipledHalf principled_detail::principled_half(const Vec3f& wo, const Vec3f& wi, float eta) {
    PrincipledHalf out;
    const Vec3d hh = Vec3d(wo) + Vec3d(wi);
    const double hl = glm::length(hh);
    if (!(hl > 0.0)) return out;
    const Vec3d hd = hh / (hh.z < 0.0 ? -hl : hl);
    const double dot_od = glm::dot(Vec3d(wo), hd), dot_id = glm::dot(Vec3d(wi), hd);
    out.h = Vec3f(hd);
    out.dot_o = float(dot_od), out.dot_i = float(dot_id);
    out.F = float(fresnel_dielectric_d(dot_od, eta));
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
    m_sqrt_base = Spectrum(std::sqrt(m_base.r), std::sqrt(m_base.g), std::sqrt(m_base.b));
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

Spectrum PrincipledBSDF::diffuse_sheen(float co, float ci, float cos_d, float w_diffuse, float w_sheen) const {
    return principled_detail::diffuse_sheen<float>(m_base, m_tint, m_roughness, m_flatness, m_sheen, m_sheen_tint, co, ci,
                                                   cos_d, w_diffuse, w_sheen, true);
}

// ---- solid ----------------------------------------------------------------------------------
PrincipledBSDF::EvalPdf PrincipledBSDF::eval_pdf_solid(const BxDFContext& ctx, const Vec3f& wo,
                                                       const Vec3f& wi) const {
    EvalPdf out;
    float co = wo.z, ci = wi.z;
    if (co == 0.f || ci == 0.f) return out;
    // (With a transmission lobe: the opaque solid is the packet form, PrincipledBSDFT.)
    bool front = co > 0.f;
    bool reflect = co * ci > 0.f;
    // η' = η(wi side)/η(wo side) for transmission.
    double etap_d = front ? double(m_eta) : 1.0 / double(m_eta);
    float etap = float(etap_d);
    // Half vector (generalised for transmission, Walter et al. 2007 eq. 16), oriented to +z, in
    // double: wo·h and wi·h of nearly orthogonal vectors otherwise lose most digits (as in
    // RoughDielectric), which breaks the transmission's η² symmetry in the tails.
    Vec3d hh = reflect ? Vec3d(wo) + Vec3d(wi) : Vec3d(wo) + Vec3d(wi) * etap_d;
    double hl = glm::length(hh);
    if (!(hl > 0.0)) return out;
    Vec3d hd = hh / (hh.z < 0.0 ? -hl : hl);
    Vec3f h(hd);
    double dot_od = glm::dot(Vec3d(wo), hd), dot_id = glm::dot(Vec3d(wi), hd);
    float dot_o = float(dot_od), dot_i = float(dot_id);
    float s = front ? 1.f : -1.f;
    // The microfacet must face wo's side and, for reflection, wi's side too (for transmission wi
    // lies on the other side of it).
    bool compatible = dot_o * s > 0.f && (reflect ? dot_i * s > 0.f : dot_i * s < 0.f);
    // F at wo·h; for transmission from the denser side evaluated from the other side (the same
    // value, better conditioned near the critical angle; as RoughDielectric).
    bool from_wi = !reflect && ((co > 0.f) != (m_eta >= 1.f));
    float F = float(fresnel_dielectric_d(from_wi ? dot_id : dot_od, m_eta));

    // Lobe probabilities (header comment): the specular group is split at h by F.
    float pr = allows(ctx, BxDFFlags::GlossyReflection) ? (front ? 1.f - m_w_bsdf * (1.f - F) : F) : 0.f;
    float pt = m_w_bsdf > 0.f && allows(ctx, BxDFFlags::GlossyTransmission)
                   ? (front ? m_w_bsdf * (1.f - F) : 1.f - F) : 0.f;
    float g_spec = pr + pt > 0.f ? 1.f : 0.f;
    float p_cc = front && m_clearcoat > 0.f && allows(ctx, BxDFFlags::GlossyReflection) ? 0.25f * m_clearcoat : 0.f;
    float p_d = front && m_w_brdf > 0.f && allows(ctx, BxDFFlags::DiffuseReflection) ? m_w_brdf : 0.f;
    float total = g_spec + p_cc + p_d;
    float inv_total = total > 0.f ? 1.f / total : 0.f;
    float p_r = g_spec > 0.f ? pr / (pr + pt) * inv_total : 0.f;
    float p_t = g_spec > 0.f ? pt / (pr + pt) * inv_total : 0.f;
    p_cc *= inv_total;
    p_d *= inv_total;

    float aco = std::fabs(co), aci = std::fabs(ci);
    float D = m_spec.D(h), G = compatible ? g_separable(m_spec, wo, wi, h) : 0.f;
    float vis = compatible ? m_spec.pdf_visible(wo, h) : 0.f;
    if (reflect) {
        float jac = 1.f / (4.f * std::fabs(dot_i));  // dωh/dωi of reflection
        // Specular reflection with the blended Fresnel (front) or the bare interface (back).
        if (compatible && F > 0.f) {
            Spectrum Fp;
            if (front) {
                float eta_it = dot_o >= 0.f ? m_eta : 1.f / m_eta;
                Fp = Spectrum((1.f - m_metallic) * (1.f - m_spec_tint) * F);
                if (m_metallic > 0.f) Fp += schlick(m_base, dot_o, m_eta) * m_metallic;
                if (m_spec_tint > 0.f)
                    Fp += schlick(m_tint * r0_of_eta(eta_it), dot_o, m_eta) * ((1.f - m_metallic) * m_spec_tint);
            } else {
                Fp = Spectrum(m_w_bsdf * F);
            }
            out.f += Fp * (D * G / (4.f * aco));
        }
        out.pdf += p_r * vis * jac;
        if (front) {
            if (m_clearcoat > 0.f) {
                float Dc = principled_detail::gtr1<float>(h.z, m_cc_alpha, m_cc_log_a2);
                if (compatible) {
                    float Fc = schlick(0.04f, dot_o, m_eta);
                    out.f += Spectrum(0.25f * m_clearcoat * Fc * Dc * g_separable(GGX(0.25f), wo, wi, h) * aci);
                }
                out.pdf += p_cc * Dc * h.z * jac;
            }
            // Diffuse weighted by w_brdf, sheen by (1 − m), both only where w_brdf > 0.
            if (m_w_brdf > 0.f) out.f += diffuse_sheen(aco, aci, dot_i, m_w_brdf, 1.f - m_metallic);
            out.pdf += p_d * aci * kInvPi;
        }
        return out;
    }
    if (!compatible) return out;
    float denom = float(sqr(dot_od + etap_d * dot_id));
    if (!(denom > 0.f)) return out;
    if (m_w_bsdf > 0.f && F < 1.f) {
        // Walter et al. 2007, eq. 21 × |cos θi|; Radiance divides by η'² (bxdf_types.h).
        float ft = m_w_bsdf * (1.f - F) * D * G * etap * etap * std::fabs(dot_o * dot_i) / (aco * denom);
        if (ctx.mode == TransportMode::Radiance) ft /= etap * etap;
        out.f += m_sqrt_base * ft;
    }
    out.pdf += p_t * vis * etap * etap * std::fabs(dot_i) / denom;  // eq. 17
    return out;
}

std::optional<BxDFSample> PrincipledBSDF::sample_solid(const BxDFContext& ctx, const Vec3f& wo, float u_lobe,
                                                       const Vec2f& u) const {
    float co = wo.z;
    if (co == 0.f) return std::nullopt;
    bool front = co > 0.f;
    bool spec_ok = allows(ctx, BxDFFlags::GlossyReflection) ||
                   (m_w_bsdf > 0.f && allows(ctx, BxDFFlags::GlossyTransmission));
    float g_spec = spec_ok ? 1.f : 0.f;
    float p_cc = front && m_clearcoat > 0.f && allows(ctx, BxDFFlags::GlossyReflection) ? 0.25f * m_clearcoat : 0.f;
    float p_d = front && m_w_brdf > 0.f && allows(ctx, BxDFFlags::DiffuseReflection) ? m_w_brdf : 0.f;
    float total = g_spec + p_cc + p_d;
    if (!(total > 0.f)) return std::nullopt;
    float x = u_lobe * total;
    BxDFSample s;
    if (x < p_d) {
        s.wi = square_to_cosine_hemisphere(u);
        s.lobe = BxDFFlags::DiffuseReflection;
    } else if (x < p_d + p_cc) {
        Vec3f m = principled_detail::principled_gtr1_normal(m_cc_alpha, u);
        s.wi = reflect(wo, m);
        if (!(dot(wo, m) > 0.f && s.wi.z > 0.f)) return std::nullopt;
        s.lobe = BxDFFlags::GlossyReflection;
    } else {
        Vec3f m = m_spec.sample_visible(wo, u);  // upper hemisphere, visible from wo's side
        float F = fresnel_dielectric(dot(wo, m), m_eta);
        float pr = allows(ctx, BxDFFlags::GlossyReflection) ? (front ? 1.f - m_w_bsdf * (1.f - F) : F) : 0.f;
        float pt = m_w_bsdf > 0.f && allows(ctx, BxDFFlags::GlossyTransmission)
                       ? (front ? m_w_bsdf * (1.f - F) : 1.f - F) : 0.f;
        if (!(pr + pt > 0.f)) return std::nullopt;
        float v = std::min((x - p_d - p_cc) / g_spec, kOneMinusEpsilon);
        if (v * (pr + pt) < pr) {
            s.wi = reflect(wo, m);
            if (!(s.wi.z * co > 0.f)) return std::nullopt;
            s.lobe = BxDFFlags::GlossyReflection;
        } else {
            float etap;
            if (!refract(wo, m, m_eta, &etap, &s.wi) || !(s.wi.z * co < 0.f)) return std::nullopt;
            s.eta = etap;
            s.lobe = BxDFFlags::GlossyTransmission;
        }
    }
    EvalPdf ep = eval_pdf_solid(ctx, wo, s.wi);
    if (!(ep.pdf > 0.f)) return std::nullopt;
    s.pdf = ep.pdf;
    s.weight = ep.f / ep.pdf;
    return s;
}

// ---- interface ------------------------------------------------------------------------------
Spectrum PrincipledBSDF::eval(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const {
    if (has_lanes()) return lanes().eval_pdf(ctx, wo, wi, true).f;
    if (m_thin) return thin_lanes().eval_pdf(ctx, wo, wi, true).f;
    return eval_pdf_solid(ctx, wo, wi).f;
}
float PrincipledBSDF::pdf(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const {
    if (has_lanes()) return lanes().eval_pdf(ctx, wo, wi, true).pdf;
    if (m_thin) return thin_lanes().eval_pdf(ctx, wo, wi, true).pdf;
    return eval_pdf_solid(ctx, wo, wi).pdf;
}
std::optional<BxDFSample> PrincipledBSDF::sample(const BxDFContext& ctx, const Vec3f& wo, float u_lobe,
                                                 const Vec2f& u) const {
    if (has_lanes()) return to_optional(lanes().sample(ctx, wo, u_lobe, u, true));
    if (m_thin) return to_optional(thin_lanes().sample(ctx, wo, u_lobe, u, true));
    return sample_solid(ctx, wo, u_lobe, u);
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
