// Smooth, thin and rough dielectric BxDFs.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/bxdf/dielectric.h"

#include <cmath>
#include <type_traits>

#include "pellucid/bxdf/kulla_conty.h"
#include "pellucid/sampling/warp.h"

namespace pellucid {
namespace {

// Selection probabilities (pr, pt) of reflection and transmission for the allowed lobes.
void lobe_probabilities(const BxDFContext& ctx, float R, float T, float& pr, float& pt) {
    pr = has_flag(ctx.allowed, BxDFFlags::Reflection) ? R : 0.f;
    pt = has_flag(ctx.allowed, BxDFFlags::Transmission) ? T : 0.f;
}
BxDFFlags interface_flags(bool refl, bool trans, BxDFFlags kind) {
    BxDFFlags f = BxDFFlags::None;
    if (refl) f |= BxDFFlags::Reflection | kind;
    if (trans) f |= BxDFFlags::Transmission | kind;
    return f;
}
}  // namespace

// ---------------------------------------------------------------------------------------------
SmoothDielectric::SmoothDielectric(float eta, const Spectrum& r, const Spectrum& t)
    : m_eta(eta > 0.f && std::isfinite(eta) ? eta : 1.f), m_r(r), m_t(t) {}

std::optional<BxDFSample> SmoothDielectric::sample(const BxDFContext& ctx, const Vec3f& wo, float u_lobe,
                                                   const Vec2f& u) const {
    return to_optional(lanes().sample(ctx, wo, u_lobe, u));
}

BxDFFlags SmoothDielectric::flags() const {
    return interface_flags(m_eta != 1.f && !m_r.is_black(), !m_t.is_black(), BxDFFlags::Specular);
}
std::string SmoothDielectric::to_string() const {
    return "SmoothDielectric[eta=" + std::to_string(m_eta) + ", specular_reflectance=" + m_r.to_string() +
           ", specular_transmittance=" + m_t.to_string() + "]";
}

// ---------------------------------------------------------------------------------------------
ThinDielectric::ThinDielectric(float eta, const Spectrum& r, const Spectrum& t)
    : m_eta(eta > 0.f && std::isfinite(eta) ? eta : 1.f), m_r(r), m_t(t) {}

std::optional<BxDFSample> ThinDielectric::sample(const BxDFContext& ctx, const Vec3f& wo, float u_lobe,
                                                 const Vec2f& u) const {
    return to_optional(lanes().sample(ctx, wo, u_lobe, u));
}
BxDFFlags ThinDielectric::flags() const {
    return interface_flags(m_eta != 1.f && !m_r.is_black(), !m_t.is_black(), BxDFFlags::Specular);
}
std::string ThinDielectric::to_string() const {
    return "ThinDielectric[eta=" + std::to_string(m_eta) + ", specular_reflectance=" + m_r.to_string() +
           ", specular_transmittance=" + m_t.to_string() + "]";
}

// ---------------------------------------------------------------------------------------------
template <class D>
RoughDielectric<D>::RoughDielectric(const D& d, float eta, const Spectrum& r, const Spectrum& t, bool multiscatter,
                                    const DielectricFresnelAverage* fresnel_avg)
    : m_d(d), m_eta(valid_eta(eta)), m_r(r), m_t(t) {
    if constexpr (std::is_same_v<D, GGX>) {
        if (multiscatter && !is_smooth()) setup_multiscatter(fresnel_avg);
    }
}

template <class D>
DielectricFresnelAverage RoughDielectric<D>::multiscatter_fresnel_average(float eta) {
    return DielectricFresnelAverage::of(less_dense_eta(valid_eta(eta)));
}

// Kulla–Conty set-up (dielectric.h header comment): losses, skip rule and the reciprocal split.
template <class D>
void RoughDielectric<D>::setup_multiscatter(const DielectricFresnelAverage* fresnel_avg) {
    const GGXDielectricAlbedoTable& t = GGXDielectricAlbedoTable::get();
    m_alpha_ms = std::sqrt(m_d.alpha_x() * m_d.alpha_y());
    float loss_e = 1.f - t.E_avg(m_alpha_ms, m_eta), loss_i = 1.f - t.E_avg(m_alpha_ms, 1.f / m_eta);
    if (std::max(loss_e, loss_i) < 1e-3f) return;  // effect below 1e-3: skip (header comment)
    loss_e = std::max(loss_e, 1e-6f);
    loss_i = std::max(loss_i, 1e-6f);
    // The less dense side L transmits like an average smooth interface, x_L = 1 − F_avg(η_ld); the
    // denser side D follows from x_L (1 − Ē_L) = η_ld² x_D (1 − Ē_D) (header comment).
    float eta_ld = less_dense_eta(m_eta);
    int L = m_eta >= 1.f ? 0 : 1, Dn = 1 - L;
    float loss[2] = {loss_e, loss_i};
    m_x[L] = 1.f - fresnel_average(eta_ld, fresnel_avg);
    m_x[Dn] = m_x[L] * loss[L] / (eta_ld * eta_ld * loss[Dn]);
    if (m_x[Dn] > 1.f) {
        m_x[Dn] = 1.f;
        m_x[L] = eta_ld * eta_ld * loss[Dn] / loss[L];
    }
    m_inv_loss[0] = kInvPi / loss_e;
    m_inv_loss[1] = kInvPi / loss_i;
    m_ms = true;
}

template <class D>
float RoughDielectric<D>::ms_E(const Vec3f& w) const {
    return GGXDielectricAlbedoTable::get().E(std::fabs(w.z), m_alpha_ms, w.z > 0.f ? m_eta : 1.f / m_eta);
}

template <class D>
Spectrum RoughDielectric<D>::ms_eval(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const {
    if (wo.z == 0.f || wi.z == 0.f) return Spectrum(0.f);
    int so = wo.z > 0.f ? 0 : 1, si = wi.z > 0.f ? 0 : 1;
    float x = so == si ? 1.f - m_x[so] : m_x[so];
    float f = x * (1.f - ms_E(wo)) * (1.f - ms_E(wi)) * m_inv_loss[si] * std::fabs(wi.z);
    f = std::max(f, 0.f);
    if (so == si) return m_r * f;
    if (ctx.mode == TransportMode::Radiance) {
        float etap = so == 0 ? m_eta : 1.f / m_eta;  // η(wi side)/η(wo side)
        f /= etap * etap;
    }
    return m_t * f;
}

// Probability of sampling the compensation lobe from wo (its missing energy 1 − E(μo)), and in
// *p_trans the probability that it then transmits (x of wo's side, restricted to ctx.allowed).
template <class D>
float RoughDielectric<D>::ms_probability(const BxDFContext& ctx, const Vec3f& wo, float* p_trans) const {
    float x = m_x[wo.z > 0.f ? 0 : 1];
    float pr = has_flag(ctx.allowed, BxDFFlags::Reflection) ? 1.f - x : 0.f;
    float pt = has_flag(ctx.allowed, BxDFFlags::Transmission) ? x : 0.f;
    if (!(pr + pt > 0.f)) return 0.f;
    *p_trans = pt / (pr + pt);
    return clamp(1.f - ms_E(wo), 0.f, 1.f);
}

DielectricHalf dielectric_half(const Vec3f& wo, const Vec3f& wi, float eta) {
    const DielectricHalfD<double> h = dielectric_half_d<double>(
        Vec3P<double>(wo.x, wo.y, wo.z), Vec3P<double>(wi.x, wi.y, wi.z), double(eta));
    DielectricHalf out;
    out.wm = Vec3f(float(h.wm.x), float(h.wm.y), float(h.wm.z));
    out.dot_o = float(h.dot_o), out.dot_i = float(h.dot_i);
    out.R = float(h.R), out.T = float(h.T), out.denom = float(h.denom), out.etap2 = float(h.etap2);
    out.ok = h.ok != 0.0;
    return out;
}

void dielectric_fresnel_pair(float cos_i, float eta, float* R, float* T) {
    const double Fd = fresnel_dielectric_d(cos_i, eta);
    *R = float(Fd), *T = float(1.0 - Fd);
}

template <class D>
typename RoughDielectric<D>::EvalPdf RoughDielectric<D>::eval_pdf(const BxDFContext& ctx, const Vec3f& wo,
                                                                  const Vec3f& wi) const {
    const auto ep = lanes().eval_pdf(ctx, wo, wi, true);
    return EvalPdf{ep.f, ep.pdf};
}

template <class D>
Spectrum RoughDielectric<D>::eval(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const {
    if (is_smooth()) return Spectrum(0.f);
    Spectrum f = eval_pdf(ctx, wo, wi).f;
    if (m_ms) f += ms_eval(ctx, wo, wi);
    return f;
}
template <class D>
float RoughDielectric<D>::pdf(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const {
    if (is_smooth()) return 0.f;
    float p = eval_pdf(ctx, wo, wi).pdf;
    if (m_ms && wo.z != 0.f && wi.z != 0.f) {
        float p_trans = 0.f, p_ms = ms_probability(ctx, wo, &p_trans);
        float q = same_hemisphere(wo, wi) ? 1.f - p_trans : p_trans;
        p = (1.f - p_ms) * p + p_ms * q * std::fabs(wi.z) * kInvPi;
    }
    return p;
}

template <class D>
std::optional<BxDFSample> RoughDielectric<D>::sample(const BxDFContext& ctx, const Vec3f& wo, float u_lobe,
                                                     const Vec2f& u) const {
    if (is_smooth()) return SmoothDielectric(m_eta, m_r, m_t).sample(ctx, wo, u_lobe, u);
    if (wo.z == 0.f) return std::nullopt;
    BxDFSample s;
    if (m_ms) {
        float p_trans = 0.f, p_ms = ms_probability(ctx, wo, &p_trans);
        if (u_lobe < p_ms) {
            // Compensation lobe: cosine-weighted on the chosen side.
            bool trans = u_lobe / p_ms < p_trans;
            s.wi = square_to_cosine_hemisphere(u);
            if ((wo.z > 0.f) == trans) s.wi.z = -s.wi.z;
            if (s.wi.z == 0.f) return std::nullopt;
            if (trans) s.eta = wo.z > 0.f ? m_eta : 1.f / m_eta;
            s.lobe = trans ? BxDFFlags::GlossyTransmission : BxDFFlags::GlossyReflection;
            s.pdf = pdf(ctx, wo, s.wi);
            if (!(s.pdf > 0.f)) return std::nullopt;
            s.weight = eval(ctx, wo, s.wi) / s.pdf;
            return s;
        }
        u_lobe = std::min((u_lobe - p_ms) / (1.f - p_ms), kOneMinusEpsilon);
    }
    if (!m_ms) return to_optional(lanes().sample(ctx, wo, u_lobe, u, true));
    Vec3f wm = m_d.sample_visible(wo, u);
    float R, T, pr, pt;
    dielectric_fresnel_pair(dot(wo, wm), m_eta, &R, &T);
    lobe_probabilities(ctx, R, T, pr, pt);
    if (!(pr + pt > 0.f)) return std::nullopt;
    if (u_lobe < pr / (pr + pt)) {
        s.wi = reflect(wo, wm);
        if (!same_hemisphere(wo, s.wi)) return std::nullopt;
        s.lobe = BxDFFlags::GlossyReflection;
    } else {
        float etap;
        if (!refract(wo, wm, m_eta, &etap, &s.wi) || s.wi.z * wo.z >= 0.f) return std::nullopt;
        s.eta = etap;
        s.lobe = BxDFFlags::GlossyTransmission;
    }
    s.pdf = pdf(ctx, wo, s.wi);
    if (!(s.pdf > 0.f)) return std::nullopt;
    s.weight = eval(ctx, wo, s.wi) / s.pdf;
    return s;
}

template <class D>
BxDFFlags RoughDielectric<D>::flags() const {
    if (is_smooth()) return SmoothDielectric(m_eta, m_r, m_t).flags();
    return interface_flags(!m_r.is_black(), !m_t.is_black(), BxDFFlags::Glossy);
}
template <class D>
std::string RoughDielectric<D>::to_string() const {
    return "RoughDielectric[" + m_d.to_string() + ", eta=" + std::to_string(m_eta) +
           ", specular_reflectance=" + m_r.to_string() + ", specular_transmittance=" + m_t.to_string() +
           ", multiscatter=" + (m_ms ? "true" : "false") + "]";
}

template class RoughDielectric<GGX>;
template class RoughDielectric<Beckmann>;
}  // namespace pellucid
