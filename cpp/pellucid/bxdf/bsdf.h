// BSDF: a BxDF placed on a surface (shading frame + geometric normal). The only place that converts
// between world and local directions; integrators never see local coordinates.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <algorithm>
#include <cmath>
#include <optional>

#include "pellucid/bxdf/bxdf.h"
#include "pellucid/math/frame.h"

namespace pellucid {

/// Which shadowing term soften_terminator() applies.
///  - Chiang: Chiang et al. 2019, "Taming the Shadow Terminator", eq. 4.
///  - Estevez: Conty Estevez, Lecocq and Stein 2019, "A Microfacet-Based Shadowing Function to Solve
///    the Bump Terminator Problem" (Ray Tracing Gems, ch. 12): a GGX Smith G1 of the light direction
///    about n0, 2/(1 + √(1 + α²·tan²θ)), whose roughness grows with the perturbation:
///    α² = min(0.125·tan²θ(ns about n0), 1). Mitsuba 3's bumpmap and normalmap use it.
enum class TerminatorModel : uint8_t { Chiang, Estevez };

/// A light leak through a shading normal: the shading and geometric normals disagree on which side
/// wo or wi (world wo_w, wi_w; local wo, wi) lies. Such directions are never sampled, and evaluate
/// to 0. Over a lane type F, for BSDF below and the packet kernel alike.
template <class F>
inline MaskT<F> shading_leaks(const V3<F>& ng, const V3<F>& wo_w, const V3<F>& wi_w, const V3<F>& wo, const V3<F>& wi) {
    return dot(wo_w, ng) * wo.z <= F(0.f) || dot(wi_w, ng) * wi.z <= F(0.f);
}

/// The factor soften_terminator() applies to f for the light direction `light` (local; light_w in
/// world) seen from `other` (local): Estevez's where `estevez`, else Chiang's (none in
/// transmission). n0 is the unperturbed and ns the perturbed shading normal. Over a lane type F, for
/// BSDF below and the packet kernel alike.
template <class F>
inline F terminator_factor(const MaskT<F>& estevez, const V3<F>& other, const V3<F>& light, const V3<F>& light_w,
                           const V3<F>& n0, const V3<F>& ns) {
    // Chiang et al. 2019, eq. 4: g = min(1, |n0·l| / (|ns·l|·|n0·ns|)), then −g³ + g² + g.
    const F cos_s = lane::abs(light.z), cos_0 = lane::abs(dot(n0, light_w)), n0_ns = lane::abs(dot(n0, ns));
    const F den = cos_s * n0_ns;
    const auto soft = !(other.z * light.z <= F(0.f)) && den > F(0.f);
    const F r = cos_0 / lane::select(soft, den, F(1.f));
    const F g = lane::select(r < F(1.f), r, F(1.f));
    const F chiang = lane::select(soft, g * (F(1.f) + g * (F(1.f) - g)), F(1.f));
    if (!lane::any(estevez)) return chiang;
    // Conty Estevez et al. 2019: the GGX G1 with α² = min(tan²θ_d/8, 1), θ_d the angle between the
    // shading and the unperturbed normal, of the light direction about n0. α² is clamped to [0, 1]:
    // where ns = n0, dot(n0, ns)² rounds above 1 and 1 − c_n² is a negative rounding error. G1 is
    // written 2|c_l| / (|c_l| + √(c_l² + α²(1 − c_l²))) (the form 2/(1 + √(1 + α² tan²θ_l)) times
    // |c_l|/|c_l|), which divides by no c_l²: finite and in [0, 1] down to grazing light.
    const F c_n = dot(n0, ns), c_l = dot(n0, light_w);
    const F c_n2 = c_n * c_n, c_l2 = c_l * c_l;
    const auto lit = c_l2 > F(0.f), tilted = c_n2 > F(0.f);
    const F a = F(0.125f) * (F(1.f) - c_n2) / lane::select(tilted, c_n2, F(1.f));
    const F a01 = lane::select(F(0.f) < a, lane::select(F(1.f) < a, F(1.f), a), F(0.f));
    const F alpha2 = lane::select(tilted, a01, F(1.f));
    const F t = F(1.f) - c_l2;
    const F abs_c = lane::abs(c_l);
    // (At most 1: √(c_l²) can round below |c_l| where c_l² is subnormal.)
    const F g1 = F(2.f) * abs_c / (abs_c + lane::sqrt(c_l2 + alpha2 * lane::select(F(0.f) < t, t, F(0.f))));
    const F est = lane::select(lit, lane::select(g1 < F(1.f), g1, F(1.f)), F(0.f));
    return lane::select(estevez, est, chiang);
}

class BSDF {
public:
    /// Owns a copy of bxdf.
    BSDF(const BxDF& bxdf, const Frame& shading, const Normal3f& ng)
        : m_own(bxdf), m_bxdf(&*m_own), m_frame(shading), m_ng(ng) {}
    /// Refers to *bxdf, which must outlive the BSDF: a material's prebuilt BxDF (Scene::bsdf), so
    /// that an untextured hit copies nothing.
    static BSDF borrowing(const BxDF* bxdf, const Frame& shading, const Normal3f& ng) { return BSDF(bxdf, shading, ng); }
    BSDF(const BSDF& o)
        : m_own(o.m_own), m_bxdf(m_own ? &*m_own : o.m_bxdf), m_frame(o.m_frame), m_ng(o.m_ng), m_n0(o.m_n0),
          m_soften(o.m_soften), m_terminator(o.m_terminator) {}
    BSDF& operator=(const BSDF& o) {
        if (this != &o) {
            m_own = o.m_own;
            m_bxdf = m_own ? &*m_own : o.m_bxdf;
            m_frame = o.m_frame;
            m_ng = o.m_ng;
            m_n0 = o.m_n0;
            m_soften = o.m_soften;
            m_terminator = o.m_terminator;
        }
        return *this;
    }

    /// Soften the shadow terminator of a perturbed (bumped or normal-mapped) shading normal:
    /// reflection is scaled by Chiang et al. 2019 ("Taming the Shadow Terminator", eq. 4),
    /// G = min(1, |n0·wi| / (|ns·wi|·|n0·ns|)), factor −G³ + G² + G, with n0 the unperturbed normal.
    /// It is 1 where the two normals agree and falls smoothly to 0 where light grazes the
    /// unperturbed surface. G is a shadowing term of the *light* direction: wi under radiance
    /// transport, wo under importance transport, so that the adjoint relation
    /// eval(Importance, wo, wi)/|ng·wi| = eval(Radiance, wi, wo)/|ng·wo| (Veach 1997, eq. 5.14)
    /// holds with it too. The factor is in [0, 1]: it only removes energy (it is not
    /// energy-preserving by design), and is exactly 1 where the shading normal is n0.
    /// With TerminatorModel::Estevez the factor is that term instead (see the enum), for the same
    /// light direction, and for transmission too.
    void soften_terminator(const Normal3f& n0, TerminatorModel model = TerminatorModel::Chiang) {
        m_soften = true;
        m_n0 = n0;
        m_terminator = model;
    }

    BxDFFlags flags() const { return pellucid::flags(*m_bxdf); }
    const BxDF& bxdf() const { return *m_bxdf; }
    /// The shading frame (after any bump or normal map); whether the terminator is softened, about
    /// which unperturbed normal and by which model.
    const Frame& frame() const { return m_frame; }
    bool softens() const { return m_soften; }
    const Normal3f& terminator_normal() const { return m_n0; }
    TerminatorModel terminator_model() const { return m_terminator; }

    /// f·|cos θi| for world directions; 0 where the shading and geometric hemispheres disagree
    /// (a light leak through a shading normal). With pdf_out, also pdf(wo_w, wi_w, mode) from the
    /// same change of frame and dispatch (next-event estimation needs both; ~1.5 % on the box).
    Spectrum eval(const Vec3f& wo_w, const Vec3f& wi_w, TransportMode mode = TransportMode::Radiance,
                  float* pdf_out = nullptr) const {
        Vec3f wo = m_frame.to_local(wo_w), wi = m_frame.to_local(wi_w);
        if (pdf_out) *pdf_out = 0.f;
        if (wo.z == 0.f || leaks(wo_w, wi_w, wo, wi)) return Spectrum(0.f);
        const BxDFContext ctx{mode, BxDFFlags::All};
        Spectrum f = visit_bxdf(*m_bxdf, [&](const auto& x) {
            if (pdf_out) *pdf_out = x.pdf(ctx, wo, wi);
            return x.eval(ctx, wo, wi);
        });
        if (mode == TransportMode::Importance) f *= shading_correction(wo_w, wi_w, wo, wi);
        if (m_soften) f *= mode == TransportMode::Radiance ? terminator(wo, wi, wi_w) : terminator(wi, wo, wo_w);
        return f;
    }
    float pdf(const Vec3f& wo_w, const Vec3f& wi_w, TransportMode mode = TransportMode::Radiance) const {
        Vec3f wo = m_frame.to_local(wo_w), wi = m_frame.to_local(wi_w);
        if (wo.z == 0.f || leaks(wo_w, wi_w, wo, wi)) return 0.f;  // as sample(): leaking directions are never produced
        return pellucid::pdf(*m_bxdf, BxDFContext{mode, BxDFFlags::All}, wo, wi);
    }
    /// Sample wi (world space). Returns nullopt for wo on the horizon, failed, zero-pdf,
    /// zero-weight or leaking samples.
    std::optional<BxDFSample> sample(const Vec3f& wo_w, float u_lobe, const Vec2f& u,
                                     TransportMode mode = TransportMode::Radiance) const {
        Vec3f wo = m_frame.to_local(wo_w);
        if (wo.z == 0.f) return std::nullopt;
        auto s = pellucid::sample(*m_bxdf, BxDFContext{mode, BxDFFlags::All}, wo, u_lobe, u);
        if (!s || !(s->pdf > 0.f) || s->weight.is_black() || s->wi.z == 0.f) return std::nullopt;
        Vec3f wi_local = s->wi;
        s->wi = m_frame.to_world(wi_local);
        if (leaks(wo_w, s->wi, wo, wi_local)) return std::nullopt;
        if (mode == TransportMode::Importance) s->weight *= shading_correction(wo_w, s->wi, wo, wi_local);
        if (m_soften)
            s->weight *= mode == TransportMode::Radiance ? terminator(wo, wi_local, s->wi) : terminator(wi_local, wo, wo_w);
        return s;
    }
    Vec3f to_local(const Vec3f& v) const { return m_frame.to_local(v); }
    Vec3f to_world(const Vec3f& v) const { return m_frame.to_world(v); }

private:
    BSDF(const BxDF* bxdf, const Frame& shading, const Normal3f& ng) : m_bxdf(bxdf), m_frame(shading), m_ng(ng) {}
    // Shading and geometric normals must agree on which side each direction is on.
    bool leaks(const Vec3f& wo_w, const Vec3f& wi_w, const Vec3f& wo, const Vec3f& wi) const {
        return shading_leaks<float>(m_ng, wo_w, wi_w, wo, wi);
    }
    // Veach 1997, eq. 5.17: adjoint BSDF correction for shading normals under importance transport.
    float shading_correction(const Vec3f& wo_w, const Vec3f& wi_w, const Vec3f& wo, const Vec3f& wi) const {
        float num = std::fabs(wo.z * dot(wi_w, m_ng));
        float den = std::fabs(wi.z * dot(wo_w, m_ng));
        return den > 0.f ? num / den : 0.f;
    }

    // The soften_terminator() factor (terminator_factor) for the light direction `light`.
    float terminator(const Vec3f& other, const Vec3f& light, const Vec3f& light_w) const {
        return terminator_factor<float>(m_terminator == TerminatorModel::Estevez, other, light, light_w, m_n0, m_frame.n);
    }

    std::optional<BxDF> m_own;  ///< the BxDF, when this BSDF owns it
    const BxDF* m_bxdf;         ///< &*m_own, or the borrowed BxDF
    Frame m_frame;
    Normal3f m_ng;
    Normal3f m_n0{0.f};
    bool m_soften = false;
    TerminatorModel m_terminator = TerminatorModel::Chiang;
};
}  // namespace pellucid
