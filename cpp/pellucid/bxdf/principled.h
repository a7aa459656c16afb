// Disney "principled" BRDF (reflection only): Burley 2012, "Physically-Based Shading at Disney",
// SIGGRAPH course notes, §5 and Appendix B. One BxDF; sample() picks a lobe.
// SPDX-License-Identifier: Apache-2.0
//
//   f = (1 − metallic) [ base/π · F_d + F_sheen ] + D_s G_s F_s/(4 cos θo cos θi)
//       + ¼ clearcoat · D_c G_c F_c/(4 cos θo cos θi)
//   F_d     = (1 + (F_D90 − 1)(1 − cos θi)^5)(1 + (F_D90 − 1)(1 − cos θo)^5),
//             F_D90 = 0.5 + 2 roughness cos² θd                                   (§5.3, eq. 3)
//   F_sheen = sheen · lerp(1, C_tint, sheen_tint) · (1 − cos θd)^5                    (§5.5)
//   specular: anisotropic GGX, α = roughness², aspect = sqrt(1 − 0.9 anisotropic),
//             αx = max(1e-3, α/aspect), αy = max(1e-3, α·aspect)                      (§5.4)
//             F_s = Schlick(C_spec0), C_spec0 = lerp(0.08 specular lerp(1, C_tint, specular_tint),
//             base, metallic); G_s = height-correlated Smith (instead of Burley's separable G)
//   clearcoat: GTR1 (γ = 1) with α_c = lerp(0.1, 0.001, clearcoat_gloss), F_c = Schlick(0.04),
//             G_c = Smith GGX with α = 0.25                                         (§5.6, App. B)
// C_tint = base/luminance(base). Omitted: subsurface, transmission (the 2015 variant, principled_bsdf.h).
// Not energy-conserving in general: the retro-reflective diffuse exceeds ρ at grazing angles for
// high roughness (a documented property of the model); the property suite uses base ≤ 0.6.
// Sampling: lobes diffuse (cosine-weighted), specular (GGX visible normals) and clearcoat (GTR1
// half vectors, App. B eq. 5) with probabilities ∝ (1 − metallic, 1, ¼ clearcoat), the diffuse one
// only where the model has a diffuse lobe; lobes outside ctx.allowed get probability 0.
//
// Packet form: Principled2012T<F> writes the whole model once over a lane type F (simd/lane.h);
// Principled's eval, pdf and sample are its float instantiation, and the path tracer shades such
// materials with it (kPacketPrincipled2012, integrator/path_services.h). Every term uses only
// lane operations that IEEE 754 rounds exactly (the library is compiled without contraction), the
// clamps written as the scalar selects; ln α_c² is a parameter computed once at construction, and
// the clear coat's GTR1 normal (pow, sin, cos) is computed one lane at a time by a function compiled
// once (principled2012_gtr1_normal), so every lane type gives the same bits.
//
// | parameter       | type     | default | meaning                          |
// |-----------------|----------|---------|----------------------------------|
// | base_color      | spectrum | 0.8     | albedo / metal colour            |
// | metallic        | float    | 0       | [0, 1]                           |
// | roughness       | float    | 0.5     | [0, 1], α = roughness²           |
// | specular        | float    | 0.5     | [0, 1] (0.5 ↔ F0 = 0.04)          |
// | specular_tint   | float    | 0       | [0, 1]                           |
// | sheen           | float    | 0       | [0, 1]                           |
// | sheen_tint      | float    | 0.5     | [0, 1]                           |
// | clearcoat       | float    | 0       | [0, 1]                           |
// | clearcoat_gloss | float    | 1       | [0, 1]                           |
// | anisotropic     | float    | 0       | [0, 1]                           |
// JSON: {"type": "principled", "base_color": [0.8, 0.2, 0.1], "metallic": 0.0, "roughness": 0.4,
//        "clearcoat": 1.0, "clearcoat_gloss": 0.9}
#pragma once
#include <cstdint>
#include <optional>
#include <string>

#include <type_traits>

#include "pellucid/bxdf/bxdf_types.h"
#include "pellucid/bxdf/microfacet.h"
#include "pellucid/math/lane_types.h"
#include "pellucid/sampling/warp.h"

namespace pellucid {

/// Which Disney model: the 2012 BRDF (this file) or the 2015 BSDF (principled_bsdf.h).
enum class PrincipledVariant : uint8_t { Burley2012, Burley2015 };

/// Parameters of both models; the 2015 fields are read only by PrincipledBSDF.
struct PrincipledInputs {
    Spectrum base_color{0.8f};
    float metallic = 0.f, roughness = 0.5f, specular = 0.5f, specular_tint = 0.f;
    float sheen = 0.f, sheen_tint = 0.5f, clearcoat = 0.f, clearcoat_gloss = 1.f, anisotropic = 0.f;
    // 2015 only.
    float specular_transmission = 0.f;  ///< [0, 1]: blends the dielectric BRDF toward rough glass
    float flatness = 0.f;               ///< [0, 1]: diffuse toward Hanrahan–Krueger subsurface
    float diffuse_transmission = 0.f;   ///< [0, 2], thin only: 0 all reflected, 2 all transmitted
    float eta = 0.f;                    ///< relative IOR; 0 = derived from `specular`
    PrincipledVariant variant = PrincipledVariant::Burley2012;
    bool thin = false;                  ///< 2015 thin sheet (principled_bsdf.h)
};

namespace principled2012_detail {
/// clamp(x, lo, hi) of math/constants.h, per lane (the same selects, so NaN goes through as there).
template <class F>
inline F clamp_t(const F& x, float lo, float hi) {
    return lane::select(x < F(lo), F(lo), lane::select(x > F(hi), F(hi), x));
}
/// (1 − c)^5 with 1 − c clamped to [0, 1] (Schlick 1994, eq. 15; disney::schlick_weight).
template <class F>
inline F schlick_weight(const F& c) {
    const F m = clamp_t<F>(F(1.f) - c, 0.f, 1.f), m2 = m * m;
    return m2 * m2 * m;
}
/// Normalised GTR1 of Burley 2012, App. B eq. 4 (Principled::gtr1), with ln α² given.
template <class F>
inline F gtr1(const F& cos_h, const F& alpha, const F& log_a2) {
    const F a2 = alpha * alpha, t = F(1.f) + (a2 - F(1.f)) * cos_h * cos_h;
    return lane::select(alpha >= F(1.f), F(kInvPi), (a2 - F(1.f)) / (F(kPi) * log_a2 * t));
}
/// The clear coat's GTR1 half vector: cos² θh = (1 − α^{2(1−u.x)})/(1 − α²), φ = 2π u.y (Burley
/// 2012, App. B eq. 5), with libm's pow, cos and sin.
Vec3f principled2012_gtr1_normal(float alpha, const Vec2f& u);
/// A clear coat's GTR1 normal Normal(α, u) (compiled once, libm inside) over a lane type F, one lane
/// at a time (lanes outside `where`: +z), so that every lane type gets its bits.
template <class F, Vec3f (*Normal)(float, const Vec2f&)>
inline V3<F> normal_lanes(const F& alpha, const V2<F>& u, const MaskT<F>& where) {
    if constexpr (std::is_same_v<F, float>) {
        return where ? Normal(alpha, u) : Vec3f(0.f, 0.f, 1.f);
    } else {
        constexpr int W = kLaneWidth<F>;
        alignas(64) float in[3][W], out[3][W];
        alignas(64) bool on[W];
        lane::store(in[0], alpha), lane::store(in[1], u.x), lane::store(in[2], u.y), lane::store(on, where);
        for (int i = 0; i < W; ++i) {
            const Vec3f m = on[i] ? Normal(in[0][i], Vec2f(in[1][i], in[2][i])) : Vec3f(0.f, 0.f, 1.f);
            out[0][i] = m.x, out[1][i] = m.y, out[2][i] = m.z;
        }
        return V3<F>(lane::load_as<F>(out[0]), lane::load_as<F>(out[1]), lane::load_as<F>(out[2]));
    }
}
/// principled2012_gtr1_normal over a lane type F (normal_lanes).
template <class F>
inline V3<F> gtr1_normal_lanes(const F& alpha, const V2<F>& u, const MaskT<F>& where) {
    return normal_lanes<F, principled2012_gtr1_normal>(alpha, u, where);
}
/// r0 + (1 − r0)·w per channel (fresnel_schlick with the weight w given).
template <class F>
inline RGB<F> schlick_rgb(const RGB<F>& r0, const F& w) {
    return RGB<F>(r0.r + (F(1.f) - r0.r) * w, r0.g + (F(1.f) - r0.g) * w, r0.b + (F(1.f) - r0.b) * w);
}
}  // namespace principled2012_detail

/// The Burley 2012 principled BRDF over a lane type F (header comment, "Packet form"): per-lane
/// parameters. Principled holds the float instantiation; the path tracer loads a packet of them per
/// vertex (principled2012_lanes).
template <class F>
struct Principled2012T {
    RGB<F> base, csheen, cspec0;  ///< base colour, sheen colour, C_spec0
    F metallic, roughness, sheen, clearcoat;
    F cc_alpha, cc_log_a2;  ///< α_c and ln α_c²
    F w_diffuse;            ///< the diffuse lobe's unnormalised probability: 1 − metallic, or 0 without one
    GGXT<F> spec;           ///< the specular lobe's anisotropic GGX (height-correlated)

    struct EvalPdf {
        RGB<F> f;
        F pdf;
    };
    /// The lobe probabilities (diffuse, specular, clear coat), normalised.
    void lobe_probs(const BxDFContext& ctx, F p[3]) const {
        const bool diff_ok = has_flag(ctx.allowed, BxDFFlags::Diffuse), gl_ok = has_flag(ctx.allowed, BxDFFlags::Glossy);
        p[0] = diff_ok ? w_diffuse : F(0.f);
        p[1] = gl_ok ? F(1.f) : F(0.f);
        p[2] = gl_ok ? F(0.25f) * clearcoat : F(0.f);
        const F s = p[0] + p[1] + p[2];
        const auto pos = s > F(0.f);
        const F d = lane::select(pos, s, F(1.f));
        for (int k = 0; k < 3; ++k) p[k] = lane::select(pos, p[k] / d, F(0.f));
    }
    /// f·|cos θi| (eval) and the density of sample() (pdf) on the lanes `where` (others: unspecified;
    /// `where` only skips the clear coat where no lane of it has one). Seen from behind, the front
    /// mirrored; pairs on opposite sides give 0.
    EvalPdf eval_pdf(const BxDFContext& ctx, const V3<F>& wo, const V3<F>& wi, const MaskT<F>& where) const {
        using namespace principled2012_detail;
        using M = MaskT<F>;
        const M flip = wo.z < F(0.f);
        const V3<F> o = lane::select(flip, -wo, wo), i = lane::select(flip, -wi, wi);
        const V3<F> hh = o + i;
        const M ok = wo.z * wi.z > F(0.f) && length2(hh) > F(0.f);
        const V3<F> h = normalize(hh);
        // co, ci = max(cos, 1e-7) (std::max's select), cos θd = clamp(wi·h, 0, 1).
        const F co = lane::select(o.z < F(1e-7f), F(1e-7f), o.z), ci = lane::select(i.z < F(1e-7f), F(1e-7f), i.z);
        const F cd = clamp_t<F>(dot(i, h), 0.f, 1.f);
        // Diffuse with retro-reflection and sheen (§5.3, §5.5).
        const F fd90 = F(0.5f) + F(2.f) * roughness * cd * cd;
        const F fd = (F(1.f) + (fd90 - F(1.f)) * schlick_weight<F>(ci)) * (F(1.f) + (fd90 - F(1.f)) * schlick_weight<F>(co));
        const F wd = schlick_weight<F>(cd);
        RGB<F> f = (base * (F(kInvPi) * fd) + csheen * (sheen * wd)) * (F(1.f) - metallic);
        // Specular (§5.4): Schlick's Fresnel at cos θd (|cos θd| = cos θd).
        const F m = clamp_t<F>(F(1.f) - lane::abs(cd), 0.f, 1.f), m2 = m * m, m5 = m2 * m2 * m;
        f += schlick_rgb<F>(cspec0, m5) * (spec.D(h) * spec.G(o, i) / (F(4.f) * co * ci));
        // Clear coat (§5.6).
        const M cc = clearcoat > F(0.f);
        const bool any_cc = lane::any(where && cc);
        F d_cc(0.f);
        if (any_cc) {
            d_cc = gtr1<F>(h.z, cc_alpha, cc_log_a2);
            const F fc = F(0.04f) + (F(1.f) - F(0.04f)) * m5;
            const GGXT<F> coat{F(0.25f), F(0.25f), M(false)};
            f = lane::select(cc, f + RGB<F>(F(0.25f) * clearcoat * d_cc * coat.G(o, i) * fc / (F(4.f) * co * ci)), f);
        }
        // The density: Σ p_k pdf_k over the lobes of probability > 0.
        F p[3];
        lobe_probs(ctx, p);
        const F c = dot(o, h), jac = F(4.f) * c;
        const M facing = c > F(0.f);
        F pdf = F(0.f);
        pdf = pdf + lane::select(p[0] > F(0.f), p[0] * (i.z * F(kInvPi)), F(0.f));
        pdf = pdf + lane::select(p[1] > F(0.f), p[1] * lane::select(facing, spec.pdf_visible(o, h) / jac, F(0.f)), F(0.f));
        if (any_cc)
            pdf = pdf + lane::select(p[2] > F(0.f), p[2] * lane::select(facing, d_cc * h.z / jac, F(0.f)), F(0.f));
        EvalPdf out;
        out.f = lane::select(ok, f * ci, RGB<F>(F(0.f)));
        out.pdf = lane::select(ok && M(has_flag(ctx.allowed, BxDFFlags::Reflection)), pdf, F(0.f));
        return out;
    }
    /// Lobe choice by u_lobe against the cumulative lobe probabilities, on the lanes `where`
    /// (others: not valid).
    BxDFSampleT<F> sample(const BxDFContext& ctx, const V3<F>& wo, const F& u_lobe, const V2<F>& u,
                          const MaskT<F>& where) const {
        using namespace principled2012_detail;
        using M = MaskT<F>;
        F p[3];
        lobe_probs(ctx, p);
        const M flip = wo.z < F(0.f);
        const V3<F> o = lane::select(flip, -wo, wo);
        const M is_d = u_lobe < p[0], is_s = !is_d && u_lobe < p[0] + p[1], is_c = !is_d && !is_s;
        const F p_lobe = lane::select(is_d, p[0], lane::select(is_s, p[1], p[2]));
        const M go = where && wo.z != F(0.f) && M(has_flag(ctx.allowed, BxDFFlags::Reflection)) && !(p_lobe <= F(0.f));
        // Each lobe's direction where some lane of `where` chose it (so that a lane's outputs, valid
        // or not, never depend on the other lanes).
        const V3<F> up(F(0.f), F(0.f), F(1.f));
        const V3<F> wd = lane::any(where && is_d) ? square_to_cosine_hemisphere<F>(u) : up;
        V3<F> ws = up, wc = up;
        if (lane::any(where && is_s)) {
            const V3<F> ms = spec.sample_visible(o, u);
            ws = -o + F(2.f) * dot(o, ms) * ms;
        }
        if (lane::any(where && is_c)) {
            const V3<F> mc = gtr1_normal_lanes<F>(cc_alpha, u, where && is_c);
            wc = -o + F(2.f) * dot(o, mc) * mc;
        }
        const V3<F> i = lane::select(is_d, wd, lane::select(is_s, ws, wc));
        const M ok = go && !(i.z <= F(0.f));
        const V3<F> wi = lane::select(flip, -i, i);
        const EvalPdf ep = eval_pdf(ctx, wo, wi, where);
        return reflection_sample_from_eval<F>(wi, ep.f, ep.pdf, ok, is_d);
    }
};

/// The path tracer's packet parameters of a Burley 2012 principled BRDF (kPrincipled2012Params
/// floats): 0–2 base, 3–5 sheen colour, 6–8 C_spec0, 9 metallic, 10 roughness, 11 sheen,
/// 12 clearcoat, 13 α_c, 14 ln α_c², 15 w_diffuse, 16 αx, 17 αy.
inline constexpr int kPrincipled2012Params = 18;
inline void principled2012_packet_params(const Principled2012T<float>& l, float* q) {
    for (int c = 0; c < 3; ++c) q[c] = l.base[c], q[3 + c] = l.csheen[c], q[6 + c] = l.cspec0[c];
    q[9] = l.metallic, q[10] = l.roughness, q[11] = l.sheen, q[12] = l.clearcoat, q[13] = l.cc_alpha;
    q[14] = l.cc_log_a2, q[15] = l.w_diffuse, q[16] = l.spec.ax, q[17] = l.spec.ay;
}
/// The packet form from packet parameters q(k) on the lanes `where`; the other lanes (other models)
/// get a black diffuse material of α 1 without a clear coat.
template <class F, class Q>
inline Principled2012T<F> principled2012_lanes(const MaskT<F>& where, Q q) {
    auto at = [&](int k, float other) { return lane::select(where, q(k), F(other)); };
    return {RGB<F>(at(0, 0.f), at(1, 0.f), at(2, 0.f)),
            RGB<F>(at(3, 1.f), at(4, 1.f), at(5, 1.f)),
            RGB<F>(at(6, 0.04f), at(7, 0.04f), at(8, 0.04f)),
            at(9, 0.f), at(10, 1.f), at(11, 0.f), at(12, 0.f),
            at(13, 0.1f), at(14, -4.6051702f), at(15, 1.f),
            GGXT<F>{at(16, 1.f), at(17, 1.f), MaskT<F>(false)}};
}

class Principled {
public:
    explicit Principled(const PrincipledInputs& p = PrincipledInputs{});
    Spectrum eval(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const {
        return m_l.eval_pdf(ctx, wo, wi, true).f;
    }
    float pdf(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const {
        return m_l.eval_pdf(ctx, wo, wi, true).pdf;
    }
    std::optional<BxDFSample> sample(const BxDFContext& ctx, const Vec3f& wo, float u_lobe, const Vec2f& u) const {
        return to_optional(m_l.sample(ctx, wo, u_lobe, u, true));
    }
    BxDFFlags flags() const;
    std::string to_string() const;
    /// The packet form's parameters (the float instantiation eval, pdf and sample run).
    const Principled2012T<float>& lanes() const { return m_l; }

    /// GTR1 ("Berry") distribution, Burley 2012 App. B eq. 4, normalised: ∫ D cos θh dω = 1.
    static float gtr1(float cos_h, float alpha);

private:
    Principled2012T<float> m_l;
    // The parameters that to_string() reports and m_l holds only through the colours and α.
    float m_specular, m_specular_tint, m_sheen_tint, m_clearcoat_gloss, m_anisotropic;
};
}  // namespace pellucid
