// Caustic-chain proposals: a direction-sampling technique that the path tracer mixes with BSDF
// sampling at diffuse and glossy vertices, aimed at the caustic a glossy glass sphere casts from a
// delta light (docs/scene-format.md, integrator `glints`).
// SPDX-License-Identifier: Apache-2.0
//
// Light refracted twice through a sphere of small roughness α reaches a diffuse or rough vertex x
// only along a chain x → p1 (enter) → p2 (leave) → light, which the path tracer finds by a direction
// sampled at x that happens to reach p1 at the angle that refracts toward p2, and light sampling at
// p2 (a delta light allows no MIS). Such directions cover a small solid angle, and the few paths that
// find them carry the caustic's value over that probability: the heavy tail of bench/README.md's
// `principled`. The proposal samples x's direction about the chains' entry points instead:
//
//  * each normal of the chain passes through the centre, so a specular chain lies in the plane of
//    the centre, x and the light. With the sphere as the unit circle, x at (X, 0) and p1 at angle
//    ψ, the chain's exit direction is two refractions away (Snell's law in vector form), and the
//    entry angles are the roots of sin(exit, light) on the arc x sees, |ψ| < acos(1/X): at most two
//    are kept;
//  * for a directional light the roots depend only on η, 1/X and the light's angle from x's axis,
//    so a table per η holds them (glint_table), with the proposal's widths; a point light's roots
//    are searched at each vertex (glint_roots);
//  * about each root the direction is drawn with an anisotropic GGX slope distribution (Walter et
//    al. 2007, eq. 33 for its density in slope space): pdf(ω) = P22(s)/cos³ θ, θ the angle from the
//    root's direction ω*. Its widths are α_eff/|dΘ/dθ| in the plane (Θ the exit direction's angle,
//    θ the direction's from x: the lobe's tolerance carried back through the chain) and
//    α_eff sin θ / sin Θ across it (turning the direction about the axis through the centre and x
//    turns the whole chain about it), α_eff = 2α, each clamped to [1e-4, 0.3].
//
// The estimator stays unbiased: at a vertex with valid proposals the direction comes from the
// mixture (1 − q) BSDF + q proposals (q split evenly over them), its weight is
// f·|cos θ| / ((1 − q) pdf_bsdf + Σ q_k pdf_k), and emission found by it keeps the BSDF's MIS weight
// against light sampling (those weights sum to one whichever technique drew the direction). A
// proposed direction on the other side of x's surface from wo ends the path: the proposals' density
// there counts as zero. The proposal need not hit a chain exactly (an interpolated root costs
// variance only); its density is the one it samples.
#pragma once
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "pellucid/math/constants.h"
#include "pellucid/math/frame.h"
#include "pellucid/math/lane_atan.h"
#include "pellucid/math/lane_types.h"
#include "pellucid/sampling/warp.h"

namespace pellucid {
class Scene;

/// One (sphere, delta light) pair whose caustic the proposal aims at.
struct GlintPair {
    float cx = 0.f, cy = 0.f, cz = 0.f, r = 1.f;  ///< the sphere
    float alpha = 0.01f;                          ///< its lobes' roughness (√(αx αy))
    float eta = 1.5f;                             ///< its relative IOR, in [1.01, 1.9]
    bool directional = true;                      ///< l: the unit direction toward the light; else its position
    float lx = 0.f, ly = 0.f, lz = 1.f;
    int32_t table = -1;  ///< a directional pair's root table in GlintSetup::tables (its offset), else −1
};

/// The root tables: for a directional light, the chain's entry angles depend only on η, 1/X (X the
/// distance of x from the centre in radii) and the light's angle θ from x's axis, so one table per η
/// holds them at kGlintTableA × kGlintTableT nodes: for each of two roots its fraction ψ/ψm of the
/// visible arc (NaN where there is none) and its widths for α_eff = 1 (1/|dΘ/dθ| in the plane and
/// sin θ/sin Θ across it). The proposal takes the bilinear interpolation of the four nodes about x
/// (the nearest node's root where some lack it): no root search at render time. An interpolated root
/// is close to the chain's but need not be on it; the proposal's density is the one it samples either way.
constexpr int kGlintTableA = 64, kGlintTableT = 128, kGlintNode = 6;

/// The pairs of a scene and the mixture weight q of their proposals.
struct GlintSetup {
    static constexpr int kMaxPairs = 8;
    /// Spheres of a transmissive material whose lobes have 1e-3 ≤ α ≤ kMaxAlpha: rougher lobes are
    /// found well by BSDF sampling, smoother ones are delta lobes that light sampling never evaluates.
    static constexpr float kMaxAlpha = 0.05f;
    std::vector<GlintPair> pairs;  ///< at most kMaxPairs
    std::vector<float> tables;     ///< the root tables (kGlintTableA · kGlintTableT · kGlintNode floats each)
    float q = 0.1f;                ///< the proposals' share of a vertex's directions
};

/// The root table of relative IOR η (kGlintTableA · kGlintTableT · kGlintNode floats at `out`): at
/// each node glint_roots (a scan of 48 points, 20 bisection steps) and glint_widths.
void glint_table(float eta, float* out);

/// The pairs of `scene` (none unless integrator.glints): its spheres of an untextured two-sided
/// rough dielectric or transmissive principled solid with GlintSetup's α and 1.01 ≤ η ≤ 1.9, times its
/// point, spot and directional lights outside them, the first kMaxPairs; and their root tables.
GlintSetup make_glint_setup(const Scene& scene);

/// A proposal at a vertex: the direction ω* toward an entry point, a frame about it and its widths.
/// (No default member initialisers: the path tracer keeps an array of them a vertex, which a scene
/// without pairs never reads; none() is the invalid proposal.)
template <class F>
struct GlintFrameT {
    MaskT<F> valid;
    V3<F> w, e1, e2;
    F sigma, sigma2;  ///< the widths along e1 and e2
    static GlintFrameT none() {
        return {MaskT<F>(false), V3<F>(F(0.f), F(0.f), F(1.f)), V3<F>(F(1.f), F(0.f), F(0.f)), V3<F>(F(0.f), F(1.f), F(0.f)),
                F(1.f), F(1.f)};
    }
};

/// The specular chain from x = (X, 0) in the unit circle's plane, entering at p1 = (cos ψ, sin ψ)
/// (ψ ∈ (−π/2, π/2)), refracting in (relative IOR η) and out at p2 (sphere_detail::chain).
template <class F>
struct GlintChainT {
    F mis;                 ///< sin(exit direction, light direction), signed
    F d0x, d0y, d2x, d2y;  ///< the unit directions x → p1 and out of p2
    MaskT<F> ok;           ///< x sees p1, no total internal reflection, and the exit faces the light
};
/// The chain for a light direction (Lx, Ly) (directional) or position (Lx, Ly) in radii.
template <class F>
GlintChainT<F> glint_chain(const F& X, const F& Lx, const F& Ly, bool directional, float eta_f, const F& psi) {
    const F eta(eta_f), inv_eta(1.f / eta_f);
    GlintChainT<F> ch;
    F cp, sp;
    const F turns = psi * F(0.5f * kInvPi);  // ψ as a turn in [0, 1)
    detail::sincos_two_pi<F>(lane::select(turns < F(0.f), turns + F(1.f), turns), &cp, &sp);
    F d0x = cp - X, d0y = sp;
    const F i0 = F(1.f) / lane::sqrt(d0x * d0x + d0y * d0y);
    d0x = d0x * i0, d0y = d0y * i0;
    // Refraction in at p1 (normal (cp, sp)) and out at p2 = p1 + t d1 (normal p2), Snell's law in
    // vector form: t = η' d + (η' cos θi − cos θt) n with n facing the incident side.
    const F ci = lane::neg(d0x * cp + d0y * sp);
    const F k1 = F(1.f) - inv_eta * inv_eta * (F(1.f) - ci * ci);
    const F a1 = inv_eta * ci - lane::sqrt(lane::max(k1, F(0.f)));
    const F d1x = inv_eta * d0x + a1 * cp, d1y = inv_eta * d0y + a1 * sp;
    const F t = F(-2.f) * (cp * d1x + sp * d1y);
    const F p2x = cp + t * d1x, p2y = sp + t * d1y;
    const F c2 = d1x * p2x + d1y * p2y;
    const F k2 = F(1.f) - eta * eta * (F(1.f) - c2 * c2);
    const F a2 = eta * c2 - lane::sqrt(lane::max(k2, F(0.f)));
    const F d2x = eta * d1x - a2 * p2x, d2y = eta * d1y - a2 * p2y;
    F wx = Lx, wy = Ly;
    if (!directional) {
        wx = Lx - p2x, wy = Ly - p2y;
        const F iw = F(1.f) / lane::sqrt(wx * wx + wy * wy);
        wx = wx * iw, wy = wy * iw;
    }
    ch.mis = d2x * wy - d2y * wx;
    ch.ok = ci > F(0.f) && k2 > F(0.f) && d2x * wx + d2y * wy > F(0.f);
    ch.d0x = d0x, ch.d0y = d0y, ch.d2x = d2x, ch.d2y = d2y;
    return ch;
}

/// Up to two roots ψ/ψm of the chain's mismatch on the arc (−ψm, ψm), ψm = 0.999 acos(1/X), by a scan of
/// kScan points for sign changes and bisection of the first two (NaN where there is none).
template <class F, int kScan = 24, int kSteps = 16>
void glint_roots(const F& X, const F& Lx, const F& Ly, bool directional, float eta, const MaskT<F>& on, F root[2]) {
    using M = MaskT<F>;
    const F psim = lane_math::acos_t<F>(F(1.f) / X) * F(0.999f);
    F lo_b[2] = {F(0.f), F(0.f)}, hi_b[2] = {F(0.f), F(0.f)};
    M found[2] = {M(false), M(false)};
    F prev_psi = lane::neg(psim);
    GlintChainT<F> prev = glint_chain<F>(X, Lx, Ly, directional, eta, prev_psi);
    for (int k = 1; k <= kScan; ++k) {
        const F psi = psim * F(float(2 * k - kScan) / float(kScan));
        const GlintChainT<F> cur = glint_chain<F>(X, Lx, Ly, directional, eta, psi);
        const M change = on && prev.ok && cur.ok && (prev.mis < F(0.f)) != (cur.mis < F(0.f));
        const M first = change && !found[0], second = change && found[0] && !found[1];
        lo_b[0] = lane::select(first, prev_psi, lo_b[0]), hi_b[0] = lane::select(first, psi, hi_b[0]);
        lo_b[1] = lane::select(second, prev_psi, lo_b[1]), hi_b[1] = lane::select(second, psi, hi_b[1]);
        found[1] = found[1] || second, found[0] = found[0] || first;
        prev = cur, prev_psi = psi;
    }
    for (int b = 0; b < 2; ++b) {
        F lo = lo_b[b], hi = hi_b[b];
        const M lo_neg = glint_chain<F>(X, Lx, Ly, directional, eta, lo).mis < F(0.f);
        for (int it = 0; it < kSteps; ++it) {
            const F mid = (lo + hi) * F(0.5f);
            const M to_lo = (glint_chain<F>(X, Lx, Ly, directional, eta, mid).mis < F(0.f)) == lo_neg;
            lo = lane::select(to_lo, mid, lo), hi = lane::select(to_lo, hi, mid);
        }
        root[b] = lane::select(found[b], (lo + hi) * F(0.5f) / psim, F(std::numeric_limits<float>::quiet_NaN()));
    }
}

/// A root's widths for α_eff = 1 (glint_frames): 1/|dΘ/dθ| in the plane, by central differences of
/// ±1e-3 ψm, and sin θ/sin Θ across it; false where the chain or a neighbour does not exist.
template <class F>
MaskT<F> glint_widths(const F& X, const F& Lx, const F& Ly, bool directional, float eta, const F& psi, const F& psim,
                      F* ft, F* fs) {
    const F h = F(1e-3f) * psim;
    const GlintChainT<F> c0 = glint_chain<F>(X, Lx, Ly, directional, eta, psi);
    const GlintChainT<F> ca = glint_chain<F>(X, Lx, Ly, directional, eta, psi - h);
    const GlintChainT<F> cb = glint_chain<F>(X, Lx, Ly, directional, eta, psi + h);
    const F dTheta = ca.d2x * cb.d2y - ca.d2y * cb.d2x, dtheta = ca.d0x * cb.d0y - ca.d0y * cb.d0x;
    *ft = lane::abs(dtheta) / lane::max(lane::abs(dTheta), F(1e-12f));
    *fs = lane::abs(c0.d0y) / lane::max(lane::abs(c0.d2y), F(1e-6f));
    return c0.ok && ca.ok && cb.ok;
}

/// Up to two proposals of pair `g` at the points x outside its sphere: the directions from x to
/// entry points p1 whose specular chain x → p1 → p2 → light (two refractions) exists, found in the
/// plane of the centre, x and the light (the chain stays in it: each normal passes through the
/// centre). For a directional light the roots and widths come from the pair's table (`tables` +
/// g.table); for a point light from glint_roots and glint_widths. Valid where x is outside and a
/// root was found (with its neighbours, for a point light). The widths: in the plane, α_eff / |dΘ/dθ| (Θ the exit
/// direction's angle, θ the direction's from x); across it, α_eff sin θ / sin Θ (a turn about the
/// axis through the centre and x turns the whole chain); α_eff = 2α.
template <class F>
void glint_frames(const GlintPair& g, const float* tables, const V3<F>& x, GlintFrameT<F> out[2]) {
    using M = MaskT<F>;
    using I = IntT<F>;
    const F inv_r(1.f / g.r);
    const V3<F> c(F(g.cx), F(g.cy), F(g.cz));
    const V3<F> v = x - c;
    const F d = length(v);
    const M outside = d > F(g.r * 1.001f);
    const V3<F> ea = v * (F(1.f) / lane::select(outside, d, F(1.f)));
    const V3<F> ell = g.directional ? V3<F>(F(g.lx), F(g.ly), F(g.lz)) : V3<F>(F(g.lx), F(g.ly), F(g.lz)) - c;
    const F la = dot(ell, ea);
    const V3<F> lp = ell - ea * la;
    const F lpl = length(lp);
    V3<F> t0, b0;
    coordinate_system<F>(ea, t0, b0);
    const M inplane = lpl > F(1e-6f) * length(ell);
    const V3<F> eb = lane::select(inplane, lp * (F(1.f) / lane::select(inplane, lpl, F(1.f))), t0);
    const F X = lane::select(outside, d * inv_r, F(2.f));
    const F Lx = g.directional ? la : la * inv_r, Ly = g.directional ? lpl : lpl * inv_r;
    const F psim = lane_math::acos_t<F>(F(1.f) / X) * F(0.999f);
    auto chain = [&](const F& psi) { return glint_chain<F>(X, Lx, Ly, g.directional, g.eta, psi); };
    const V3<F> e2 = cross(ea, eb);
    const F a_eff(2.f * g.alpha);
    // The frame about the direction toward the entry point at ψ, with the widths α_eff·(ft, fs).
    auto frame_at = [&](GlintFrameT<F>& o, const M& ok, const F& psi, const F& ft, const F& fs) {
        F cp, sp;
        const F turns = psi * F(0.5f * kInvPi);
        detail::sincos_two_pi<F>(lane::select(turns < F(0.f), turns + F(1.f), turns), &cp, &sp);
        o.w = normalize(lane::select(ok, ea * (cp - X) + eb * sp, V3<F>(F(0.f), F(0.f), F(1.f))));
        o.e2 = e2;
        o.e1 = cross(e2, o.w);
        o.sigma = lane::select(ok, lane::min(F(0.3f), lane::max(F(1e-4f), a_eff * ft)), F(1.f));
        o.sigma2 = lane::select(ok, lane::min(F(0.3f), lane::max(F(1e-4f), a_eff * fs)), F(1.f));
        o.valid = ok;
    };
    if (g.directional && tables) {
        const float* tab = tables + g.table;
        // Node coordinates: a = 1/X at (i + ½)/kGlintTableA, θ at j π/(kGlintTableT − 1).
        const F fa = lane::min(lane::max(F(float(kGlintTableA)) / X - F(0.5f), F(0.f)), F(float(kGlintTableA - 1) - 1e-3f));
        const F ft = lane::min(lane::max(lane_math::atan2_t<F>(Ly, Lx) * F(float(kGlintTableT - 1) * kInvPi), F(0.f)),
                               F(float(kGlintTableT - 1) - 1e-3f));
        const F ia = lane::floor(fa), it = lane::floor(ft);
        const F wa = fa - ia, wt = ft - it;
        const I i0 = lane::to_int(ia), j0 = lane::to_int(it);
        const I i1 = lane::min(i0 + I(1), I(kGlintTableA - 1)), j1 = lane::min(j0 + I(1), I(kGlintTableT - 1));
        const I n00 = (i0 * I(kGlintTableT) + j0) * I(kGlintNode), n10 = (i1 * I(kGlintTableT) + j0) * I(kGlintNode);
        const I n01 = (i0 * I(kGlintTableT) + j1) * I(kGlintNode), n11 = (i1 * I(kGlintTableT) + j1) * I(kGlintNode);
        const F w00 = (F(1.f) - wa) * (F(1.f) - wt), w10 = wa * (F(1.f) - wt), w01 = (F(1.f) - wa) * wt, w11 = wa * wt;
        // The nearest node (where some of the four lack the root).
        const I nn = lane::select(lane::int_mask(wa < F(0.5f)), lane::select(lane::int_mask(wt < F(0.5f)), n00, n01),
                                  lane::select(lane::int_mask(wt < F(0.5f)), n10, n11));
        for (int b = 0; b < 2; ++b) {
            auto bilinear = [&](int f) {
                const I o(3 * b + f);
                return w00 * lane::gather(tab, n00 + o) + w10 * lane::gather(tab, n10 + o) + w01 * lane::gather(tab, n01 + o) +
                       w11 * lane::gather(tab, n11 + o);
            };
            const F ub = bilinear(0);
            const M all4 = ub == ub;  // (NaN ≠ NaN: some node lacks the root)
            auto value = [&](int f, const F& bil) { return lane::select(all4, bil, lane::gather(tab, nn + I(3 * b + f))); };
            const F u = value(0, ub);
            const M ok = outside && u == u;
            frame_at(out[b], ok, lane::select(ok, u, F(0.f)) * psim, value(1, bilinear(1)), value(2, bilinear(2)));
        }
        return;
    }
    F root[2];
    glint_roots<F>(X, Lx, Ly, g.directional, g.eta, outside, root);
    for (int b = 0; b < 2; ++b) {
        const M has = outside && root[b] == root[b];
        const F psi = lane::select(has, root[b], F(0.f)) * psim;
        F ft, fs;
        const M ok = has && glint_widths<F>(X, Lx, Ly, g.directional, g.eta, psi, psim, &ft, &fs);
        frame_at(out[b], ok, psi, ft, fs);
    }
}


/// The proposal's density (solid angle) at the unit directions w: P22(tan θ)/cos³ θ with P22 the
/// GGX slope density of width σ, θ the angle from the chord (0 beyond 90°, and where the frame is
/// invalid).
template <class F>
F glint_pdf(const GlintFrameT<F>& f, const V3<F>& w) {
    const F c = dot(w, f.w);
    const auto ok = f.valid && c > F(0.f);
    const F cs = lane::select(ok, c, F(1.f));
    const F s1 = dot(w, f.e1) / (cs * f.sigma), s2 = dot(w, f.e2) / (cs * f.sigma2);
    const F den = F(1.f) + s1 * s1 + s2 * s2;
    return lane::select(ok, F(1.f) / (F(kPi) * f.sigma * f.sigma2 * den * den * cs * cs * cs), F(0.f));
}

/// A direction drawn from the proposal with u ∈ [0, 1)²: the slope (σ1 cos φ, σ2 sin φ)·√(u/(1 − u))
/// (the inverse of the anisotropic GGX slope CDF), φ = 2π v.
template <class F>
V3<F> glint_sample(const GlintFrameT<F>& f, const V2<F>& u) {
    const F r = lane::sqrt(u.x / (F(1.f) - u.x));
    F cp, sp;
    detail::sincos_two_pi<F>(u.y, &cp, &sp);
    return normalize(f.w + f.e1 * (r * cp * f.sigma) + f.e2 * (r * sp * f.sigma2));
}
}  // namespace pellucid
