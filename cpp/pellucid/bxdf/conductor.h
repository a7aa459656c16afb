// Conductors: the smooth mirror (delta lobe) and Torrance–Sparrow microfacet reflection with
// optional Kulla–Conty multiple-scattering compensation.
// SPDX-License-Identifier: Apache-2.0
//
// SmoothConductor<Fresnel> ("conductor"):
// | parameter            | type     | default | meaning                                        |
// |----------------------|----------|---------|------------------------------------------------|
// | material             | string   | "none"  | named metal (ior.h); or eta/k (not both)       |
// | eta, k               | spectrum | —       | complex IOR per channel (ConductorFresnel)     |
// | specular_reflectance | spectrum | 1       | multiplier on F (not physical; for artists)     |
// JSON: {"type": "conductor", "material": "Au"}
//
// MicrofacetReflection<Distribution, Fresnel> ("rough_conductor"); RoughConductor = <GGX, ConductorFresnel>:
// | parameter            | type     | default | meaning                                        |
// |----------------------|----------|---------|------------------------------------------------|
// | distribution         | string   | "ggx"   | "ggx" or "beckmann"                            |
// | alpha                | float    | 0.1     | isotropic α (≥ 0; α = roughness², microfacet.h)|
// | alpha_u, alpha_v     | float    | alpha   | anisotropic α along the tangent / bitangent    |
// | material, eta, k     |          |         | as for "conductor"                             |
// | specular_reflectance | spectrum | 1       | multiplier on F                                |
// | shadowing            | string   | "height_correlated" | or "separable" (microfacet.h)      |
// | multiple_scattering  | bool     | false   | Kulla–Conty compensation (GGX, height-correlated only) |
// JSON: {"type": "rough_conductor", "material": "Al", "distribution": "ggx", "alpha_u": 0.05,
//        "alpha_v": 0.3, "multiple_scattering": true}
// Scene-facing parameter rules (roughness r with α = r², clamps, errors): material/conductor.h.
//
// Model no more than needed (docs/materials.md):
//  * Specular collapse: when max(αx, αy) < 1e-3 (Distribution::effectively_smooth()) the rough
//    model IS the smooth mirror: sample() returns the delta lobe and eval()/pdf() return 0. The
//    directional albedo is continuous across the switch (test_bxdf_properties.cpp,
//    ConductorSmoothSwitchIsContinuous).
//  * Kulla–Conty is skipped when the average energy it restores is below 1e-3, i.e. when
//    1 − E_avg(α) < 1e-3 (measured with the GGX table: α < 0.016). Single directions at
//    extreme grazing (μ ≲ α) can still lose more; that sliver is ignored. For anisotropic α the
//    table is read at α = sqrt(αx αy). Beckmann never compensates (no table).
#pragma once
#include <optional>
#include <string>
#include <type_traits>

#include "pellucid/bxdf/bxdf_types.h"
#include "pellucid/bxdf/fresnel.h"
#include "pellucid/bxdf/kulla_conty.h"
#include "pellucid/bxdf/microfacet.h"
#include "pellucid/math/spherical.h"
#include "pellucid/sampling/warp.h"

namespace pellucid {

/// Smallest |cos θ| used in divisions (grazing directions stay finite).
constexpr float kMinCos = 1e-7f;

/// Torrance–Sparrow / Cook–Torrance BRDF value f = D G F / (4 cos θo cos θi) (Torrance & Sparrow
/// 1967; Cook & Torrance 1982, eq. 3; Walter et al. 2007, eq. 20). Without the cos θi of eval().
inline float torrance_sparrow(float D, float G, float F, float cos_o, float cos_i) {
    return D * G * F / (4.f * cos_o * cos_i);
}

/// Torrance–Sparrow without its cos θi factor, over a lane type F.
template <class F>
inline F torrance_sparrow_t(const F& D, const F& G, const F& cos_o, const F& cos_i) {
    return D * G * F(1.f) / (F(4.f) * cos_o * cos_i);
}

/// A reflection pair (wo, wi) seen from the upper hemisphere (both flipped when wo.z < 0): o, i, their
/// half vector wm (+z where there is none), and ok, whether the pair reflects (same side, o + i ≠ 0).
/// The microfacet reflection lobes (the rough conductors, the plastics' coat) share it.
template <class F>
struct ReflectionPairT {
    V3<F> o, i, wm;
    MaskT<F> ok;
    ReflectionPairT(const V3<F>& wo, const V3<F>& wi) {
        const auto flip = wo.z < F(0.f);
        o = lane::select(flip, -wo, wo), i = lane::select(flip, -wi, wi);
        const V3<F> h = o + i;
        ok = wo.z * wi.z > F(0.f) && length2(h) != F(0.f);
        wm = normalize(lane::select(ok, h, V3<F>(F(0.f), F(0.f), F(1.f))));
    }
    /// Torrance–Sparrow D G / (4 cos θo cos θi) times cos θi, without its Fresnel factor.
    template <class Dist>
    F torrance_sparrow_cos(const Dist& d) const {
        const F co = lane::max(o.z, F(kMinCos)), ci = lane::max(i.z, F(kMinCos));
        return torrance_sparrow_t<F>(d.D(wm), d.G(o, i), co, ci) * ci;
    }
    /// The density of wi when wm is sampled from the visible normals of o: D_o(wm) / (4 o·wm)
    /// (Walter et al. 2007, eq. 14); 0 where the pair does not reflect or wm faces away.
    template <class Dist>
    F pdf(const Dist& d) const {
        const F c = dot(o, wm);
        const auto pos = ok && c > F(0.f);
        return lane::select(pos, d.pdf_visible(o, wm) / (F(4.f) * lane::select(pos, c, F(1.f))), F(0.f));
    }
    /// torrance_sparrow_cos(d) into *f and pdf(d) into *pdf, with D(wm) and Λ(o) evaluated once: the
    /// same operations on the same values as the two calls, so the same bits (o is on the upper side
    /// already, so microfacet_detail::visible_pdf's flip leaves it as it is). Dist: GGXT or BeckmannT.
    template <class Dist>
    void torrance_sparrow_cos_pdf(const Dist& d, F* f, F* pdf) const {
        const F D = d.D(wm), lo = d.lambda(o);
        const F co = lane::max(o.z, F(kMinCos)), ci = lane::max(i.z, F(kMinCos));
        *f = torrance_sparrow_t<F>(D, microfacet_detail::smith_g2<F>(d.separable, lo, d.lambda(i)), co, ci) * ci;
        const F c = dot(o, wm);
        const auto pos = ok && c > F(0.f);
        const F visible = lane::select(o.z != F(0.f) && c > F(0.f), F(1.f) / (F(1.f) + lo) / o.z * D * c, F(0.f));
        *pdf = lane::select(pos, visible / (F(4.f) * lane::select(pos, c, F(1.f))), F(0.f));
    }
};

/// A lobe's f·|cos θi| and sampling density at one (wo, wi), evaluated together.
template <class F>
struct EvalPdfT {
    RGB<F> f;
    F pdf;
};

/// The conductor models over a lane type F (simd/lane.h), with exact Fresnel (fresnel_conductor<F>):
/// the packet forms of the path tracer. SmoothConductor<ConductorFresnel> and the rough conductors
/// (GGX without Kulla–Conty compensation, and Beckmann) call their float instantiations, so each
/// model is one source.
template <class F>
struct SmoothConductorT {
    RGB<F> eta, k, scale;

    RGB<F> fresnel(const F& cos_i) const {
        const F c = lane::abs(cos_i);
        return RGB<F>(fresnel_conductor<F>(c, eta.r, k.r), fresnel_conductor<F>(c, eta.g, k.g),
                      fresnel_conductor<F>(c, eta.b, k.b));
    }
    /// Mirror reflection: weight = specular_reflectance · F(|cos θo|), discrete probability 1.
    BxDFSampleT<F> sample(const BxDFContext& ctx, const V3<F>& wo, const F& /*u_lobe*/, const V2<F>& /*u*/) const {
        BxDFSampleT<F> s;
        s.valid = wo.z != F(0.f);
        if (!has_flag(ctx.allowed, BxDFFlags::SpecularReflection)) s.valid = MaskT<F>(false);
        s.wi = V3<F>(lane::neg(wo.x), lane::neg(wo.y), wo.z);
        s.weight = scale * fresnel(wo.z);
        s.pdf = F(1.f);
        s.eta = F(1.f);
        s.lobe = IntT<F>(int32_t(BxDFFlags::SpecularReflection));
        return s;
    }
};

/// Torrance–Sparrow reflection on the lane distribution DistT<F> (GGXT or BeckmannT, microfacet.h).
template <template <class> class DistT, class F>
struct MicrofacetConductorT {
    DistT<F> d;
    SmoothConductorT<F> fr;  ///< η, k and specular_reflectance

    RGB<F> eval(const BxDFContext&, const V3<F>& wo, const V3<F>& wi) const {
        const ReflectionPairT<F> r(wo, wi);
        const RGB<F> f = fr.scale * fr.fresnel(dot(r.o, r.wm)) * r.torrance_sparrow_cos(d);
        return lane::select(r.ok, f, RGB<F>(F(0.f)));
    }
    F pdf(const BxDFContext& ctx, const V3<F>& wo, const V3<F>& wi) const {
        if (!has_flag(ctx.allowed, BxDFFlags::GlossyReflection)) return F(0.f);
        return ReflectionPairT<F>(wo, wi).pdf(d);
    }
    /// eval and pdf in one pass (ReflectionPairT::torrance_sparrow_cos_pdf): the same bits.
    EvalPdfT<F> eval_pdf(const BxDFContext& ctx, const V3<F>& wo, const V3<F>& wi) const {
        const ReflectionPairT<F> r(wo, wi);
        F ts, p;
        r.torrance_sparrow_cos_pdf(d, &ts, &p);
        const RGB<F> f = fr.scale * fr.fresnel(dot(r.o, r.wm)) * ts;
        return {lane::select(r.ok, f, RGB<F>(F(0.f))), has_flag(ctx.allowed, BxDFFlags::GlossyReflection) ? p : F(0.f)};
    }
    BxDFSampleT<F> sample(const BxDFContext& ctx, const V3<F>& wo, const F& /*u_lobe*/, const V2<F>& u) const {
        BxDFSampleT<F> s;
        const auto flip = wo.z < F(0.f);
        const V3<F> o = lane::select(flip, -wo, wo);
        const V3<F> m = d.sample_visible(o, u);
        const V3<F> i = -o + F(2.f) * dot(o, m) * m;  // reflect (math/spherical.h)
        s.wi = lane::select(flip, -i, i);
        const EvalPdfT<F> ep = eval_pdf(ctx, wo, s.wi);
        s.pdf = ep.pdf;
        s.valid = wo.z != F(0.f) && i.z > F(0.f) && s.pdf > F(0.f);
        if (!has_flag(ctx.allowed, BxDFFlags::GlossyReflection)) s.valid = MaskT<F>(false);
        s.weight = ep.f / lane::select(s.valid, s.pdf, F(1.f));
        s.eta = F(1.f);
        s.lobe = IntT<F>(int32_t(BxDFFlags::GlossyReflection));
        return s;
    }
};

template <class F>
using RoughConductorGGXT = MicrofacetConductorT<GGXT, F>;
template <class F>
using RoughConductorBeckmannT = MicrofacetConductorT<BeckmannT, F>;
/// The rough conductor's packet form over DistT (GGXT or BeckmannT) from the path tracer's packet
/// parameters q(k) (path_services.cpp, packet_form: 0–2 η, 3–5 k, 6–8 the reflectance's scale, 9 αx,
/// 10 αy, 11 separable shadowing) on the lanes `where`; the other lanes get α 1.
template <template <class> class DistT, class F, class Q>
inline MicrofacetConductorT<DistT, F> rough_conductor_lanes(const MaskT<F>& where, Q q) {
    return {DistT<F>{lane::select(where, q(9), F(1.f)), lane::select(where, q(10), F(1.f)), q(11) != F(0.f)},
            SmoothConductorT<F>{RGB<F>(q(0), q(1), q(2)), RGB<F>(q(3), q(4), q(5)), RGB<F>(q(6), q(7), q(8))}};
}

/// Ideal mirror: weight = specular_reflectance · F(|cos θo|), discrete probability 1.
template <class Fresnel>
class SmoothConductor {
public:
    explicit SmoothConductor(const Fresnel& fr = Fresnel{}, const Spectrum& specular_reflectance = Spectrum(1.f))
        : m_fr(fr), m_scale(specular_reflectance) {}

    Spectrum eval(const BxDFContext&, const Vec3f&, const Vec3f&) const { return Spectrum(0.f); }
    float pdf(const BxDFContext&, const Vec3f&, const Vec3f&) const { return 0.f; }
    std::optional<BxDFSample> sample(const BxDFContext& ctx, const Vec3f& wo, float u_lobe, const Vec2f& u) const {
        if constexpr (std::is_same_v<Fresnel, ConductorFresnel>) {
            SmoothConductorT<float> l;
            if (lanes(&l)) return to_optional(l.sample(ctx, wo, u_lobe, u));
        }
        if (!has_flag(ctx.allowed, BxDFFlags::SpecularReflection) || wo.z == 0.f) return std::nullopt;
        BxDFSample s;
        s.wi = Vec3f(-wo.x, -wo.y, wo.z);
        s.weight = m_scale * m_fr.eval(std::fabs(wo.z));
        s.pdf = 1.f;
        s.lobe = BxDFFlags::SpecularReflection;
        return s;
    }
    BxDFFlags flags() const { return m_scale.is_black() ? BxDFFlags::None : BxDFFlags::SpecularReflection; }
    std::string to_string() const {
        return "SmoothConductor[" + m_fr.to_string() + ", specular_reflectance=" + m_scale.to_string() + "]";
    }
    /// The packet form's parameters, when the model has one (exact Fresnel; Schlick's has none).
    bool lanes(SmoothConductorT<float>* out) const {
        if constexpr (std::is_same_v<Fresnel, ConductorFresnel>) {
            if (m_fr.schlick) return false;
            *out = SmoothConductorT<float>{m_fr.eta, m_fr.k, m_scale};
            return true;
        }
        return false;
    }

private:
    Fresnel m_fr;
    Spectrum m_scale;
};

/// Torrance–Sparrow microfacet reflection with VNDF sampling; collapses to the mirror when smooth.
template <class Distribution, class Fresnel>
class MicrofacetReflection {
public:
    /// `fresnel_avg`: the Fresnel average Kulla–Conty reads, precomputed (fresnel.h; null: computed here).
    MicrofacetReflection(const Distribution& distrib, const Fresnel& fr,
                         const Spectrum& specular_reflectance = Spectrum(1.f), bool multiscatter = false,
                         const ConductorFresnelAverage* fresnel_avg = nullptr)
        : m_d(distrib), m_fr(fr), m_scale(specular_reflectance) {
        if constexpr (std::is_same_v<Distribution, GGX>) {
            if (multiscatter && !m_d.effectively_smooth()) setup_multiscatter(fresnel_avg);
        }
    }

    /// The packet form (RoughConductorGGXT or RoughConductorBeckmannT): exact Fresnel, rough,
    /// without Kulla–Conty.
    static constexpr bool kHasLanes = std::is_same_v<Fresnel, ConductorFresnel>;
    using Lanes = std::conditional_t<std::is_same_v<Distribution, GGX>, RoughConductorGGXT<float>, RoughConductorBeckmannT<float>>;
    bool lanes(Lanes* out) const {
        if constexpr (kHasLanes) {
            if (m_ms || m_fr.schlick || m_d.effectively_smooth()) return false;
            *out = Lanes{m_d.lanes(), SmoothConductorT<float>{m_fr.eta, m_fr.k, m_scale}};
            return true;
        }
        return false;
    }
    /// The mirror it collapses to when effectively smooth.
    SmoothConductor<Fresnel> smooth() const { return SmoothConductor<Fresnel>(m_fr, m_scale); }

    Spectrum eval(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const {
        if constexpr (kHasLanes) {
            Lanes l;
            if (lanes(&l)) return l.eval(ctx, wo, wi);
        }
        if (m_d.effectively_smooth() || !same_hemisphere(wo, wi)) return Spectrum(0.f);
        Vec3f o = wo.z < 0.f ? -wo : wo, i = wo.z < 0.f ? -wi : wi;
        Vec3f h = o + i;
        if (length2(h) == 0.f) return Spectrum(0.f);
        Vec3f wm = normalize(h);
        float co = std::max(o.z, kMinCos), ci = std::max(i.z, kMinCos);
        Spectrum F = m_fr.eval(dot(o, wm));
        Spectrum f = m_scale * F * (torrance_sparrow(m_d.D(wm), m_d.G(o, i), 1.f, co, ci) * ci);
        if (m_ms) f += ms_lobe(co, ci) * ci;
        return f;
    }
    float pdf(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const {
        if constexpr (kHasLanes) {
            Lanes l;
            if (lanes(&l)) return l.pdf(ctx, wo, wi);
        }
        if (m_d.effectively_smooth() || !has_flag(ctx.allowed, BxDFFlags::GlossyReflection) ||
            !same_hemisphere(wo, wi))
            return 0.f;
        Vec3f o = wo.z < 0.f ? -wo : wo, i = wo.z < 0.f ? -wi : wi;
        Vec3f h = o + i;
        if (length2(h) == 0.f) return 0.f;
        Vec3f wm = normalize(h);
        float c = dot(o, wm);
        float p = c > 0.f ? m_d.pdf_visible(o, wm) / (4.f * c) : 0.f;  // Walter et al. 2007, eq. 14
        if (m_ms) {
            float p_ms = ms_probability(o.z);
            p = (1.f - p_ms) * p + p_ms * i.z * kInvPi;
        }
        return p;
    }
    std::optional<BxDFSample> sample(const BxDFContext& ctx, const Vec3f& wo, float u_lobe,
                                     const Vec2f& u) const {
        if constexpr (kHasLanes) {
            Lanes l;
            if (lanes(&l)) return to_optional(l.sample(ctx, wo, u_lobe, u));
        }
        if (wo.z == 0.f) return std::nullopt;
        if (m_d.effectively_smooth())
            return SmoothConductor<Fresnel>(m_fr, m_scale).sample(ctx, wo, u_lobe, u);
        if (!has_flag(ctx.allowed, BxDFFlags::GlossyReflection)) return std::nullopt;
        Vec3f o = wo.z < 0.f ? -wo : wo, i;
        if (m_ms && u_lobe < ms_probability(o.z)) {
            i = square_to_cosine_hemisphere(u);
        } else {
            i = reflect(o, m_d.sample_visible(o, u));
        }
        if (i.z <= 0.f) return std::nullopt;
        BxDFSample s;
        s.wi = wo.z < 0.f ? -i : i;
        s.pdf = pdf(ctx, wo, s.wi);
        if (!(s.pdf > 0.f)) return std::nullopt;
        s.weight = eval(ctx, wo, s.wi) / s.pdf;
        s.lobe = BxDFFlags::GlossyReflection;
        return s;
    }
    BxDFFlags flags() const {
        if (m_scale.is_black()) return BxDFFlags::None;
        return m_d.effectively_smooth() ? BxDFFlags::SpecularReflection : BxDFFlags::GlossyReflection;
    }
    const Distribution& distribution() const { return m_d; }
    bool multiscatter() const { return m_ms; }
    std::string to_string() const {
        return "MicrofacetReflection[" + m_d.to_string() + ", " + m_fr.to_string() +
               ", specular_reflectance=" + m_scale.to_string() + ", multiscatter=" + (m_ms ? "true" : "false") + "]";
    }

private:
    void setup_multiscatter(const ConductorFresnelAverage* fresnel_avg) {
        const GGXAlbedoTable& t = GGXAlbedoTable::get();
        m_alpha_ms = std::sqrt(m_d.alpha_x() * m_d.alpha_y());
        if (t.average_loss(m_alpha_ms) < 1e-3f) return;  // effect below 1e-3: skip (header comment)
        m_e_avg = t.E_avg(m_alpha_ms);
        m_fms = m_scale * kulla_conty_fms(fresnel_average(m_fr, fresnel_avg), m_e_avg);
        m_ms = true;
    }
    // Kulla–Conty lobe f_ms without the cos θi (kulla_conty.h).
    Spectrum ms_lobe(float co, float ci) const {
        const GGXAlbedoTable& t = GGXAlbedoTable::get();
        float num = (1.f - t.E(co, m_alpha_ms)) * (1.f - t.E(ci, m_alpha_ms));
        return m_fms * (num / (kPi * std::max(1e-6f, 1.f - m_e_avg)));
    }
    // Probability of sampling the cosine lobe: the white missing energy 1 − E(μo).
    float ms_probability(float co) const {
        return clamp(1.f - GGXAlbedoTable::get().E(co, m_alpha_ms), 0.f, 1.f);
    }

    Distribution m_d;
    Fresnel m_fr;
    Spectrum m_scale;
    bool m_ms = false;
    float m_alpha_ms = 0.f, m_e_avg = 1.f;
    Spectrum m_fms{0.f};
};

template <class Distribution>
using RoughConductorT = MicrofacetReflection<Distribution, ConductorFresnel>;
using RoughConductor = RoughConductorT<GGX>;
using RoughConductorBeckmann = RoughConductorT<Beckmann>;
}  // namespace pellucid
