// Distance sampling and transmittance in grid media: delta tracking and ratio tracking over the
// coarse majorant grid, walked by a 3D DDA. Included by medium/medium.h (use that header).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <algorithm>
#include <cmath>

namespace pellucid {
namespace detail {

inline float dot3(const Spectrum& a, const Spectrum& b) { return a.r * b.r + a.g * b.g + a.b * b.b; }

/// A ray in grid space ([0, 1]³), clipped to the unit cube and to [0, tmax).
struct GridRay {
    Vec3f o{0.f}, d{0.f};
    float t0 = 0.f, t1 = 0.f;  ///< the clipped parameter range (same t as the world ray)
    float len = 1.f;           ///< world length per unit t: |ray.d|
    bool hit = false;
};

inline GridRay to_grid(const GridMedium& m, const Ray& ray) {
    GridRay r;
    r.o = Vec3f(m.world_to_grid * Vec4f(ray.o, 1.f));
    r.d = Vec3f(m.world_to_grid * Vec4f(ray.d, 0.f));
    r.len = length(ray.d);
    float t0 = 0.f, t1 = ray.tmax;
    for (int a = 0; a < 3; ++a) {  // slab test (Kay & Kajiya 1986)
        if (r.d[a] == 0.f) {
            if (r.o[a] < 0.f || r.o[a] > 1.f) return r;
            continue;
        }
        const float inv = 1.f / r.d[a];
        float ta = (0.f - r.o[a]) * inv, tb = (1.f - r.o[a]) * inv;
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    r.t0 = t0;
    r.t1 = t1;
    r.hit = t0 < t1 && std::isfinite(t1);
    return r;
}

/// Visit, in order along the ray, the pieces [ta, tb) of [r.t0, r.t1) that lie in one majorant
/// block, with the block's majorant density: v(ta, tb, majorant) returns false to stop. A 3D DDA
/// over the blocks (Amanatides & Woo 1987, "A fast voxel traversal algorithm for ray tracing").
template <class Visit>
void for_each_majorant_segment(const DensityGrid& g, const GridRay& r, Visit&& v) {
    const int B = DensityGrid::kMajorantBlock;
    const int n[3] = {g.nx(), g.ny(), g.nz()};
    int cell[3], step[3], last[3];
    float next[3], delta[3];
    const Vec3f p = r.o + r.d * (0.5f * (r.t0 + std::min(r.t1, r.t0 + 1e-4f * (r.t1 - r.t0))));
    for (int a = 0; a < 3; ++a) {
        const float size = float(B) / float(n[a]);  // block width in grid space
        last[a] = g.coarse(a) - 1;
        cell[a] = std::clamp(int(std::floor(std::clamp(p[a], 0.f, 1.f) / size)), 0, last[a]);
        if (r.d[a] > 0.f) {
            step[a] = 1;
            next[a] = ((cell[a] + 1) * size - r.o[a]) / r.d[a];
            delta[a] = size / r.d[a];
        } else if (r.d[a] < 0.f) {
            step[a] = -1;
            next[a] = (cell[a] * size - r.o[a]) / r.d[a];
            delta[a] = -size / r.d[a];
        } else {
            step[a] = 0;
            next[a] = kInfinity;
            delta[a] = kInfinity;
        }
    }
    float ta = r.t0;
    for (int guard = g.coarse(0) + g.coarse(1) + g.coarse(2) + 3; guard > 0; --guard) {
        const int a = next[0] < next[1] ? (next[0] < next[2] ? 0 : 2) : (next[1] < next[2] ? 1 : 2);
        const float tb = std::min(next[a], r.t1);
        if (tb > ta && !v(ta, tb, g.majorant(cell[0], cell[1], cell[2]))) return;
        if (tb >= r.t1) return;
        ta = tb;
        cell[a] += step[a];
        if (cell[a] < 0 || cell[a] > last[a]) return;
        next[a] += delta[a];
    }
}
}  // namespace detail

/// Delta tracking with null collisions against the block majorant μ̄ = d̄_block · max_c σt_c (one
/// grey majorant for the three channels; Woodcock et al. 1965; Novák et al. 2014, §3). Tentative
/// collisions are exponential in μ̄; at one, the channel c* ~ channel_pmf(beta) decides: a real
/// collision with probability σt_c*(x)/μ̄, else a null collision. In the null-scattering path
/// integral (Miller et al. 2019, eqs. 13–16) every channel's contribution of the walk is
/// Π_nulls σn_c(x_i) times σs_c(x) (collision) or 1 (passing), with σn = μ̄ − σt, and the
/// one-sample balance heuristic over c* divides it by Σ_c p_c Π(σn_c/μ̄)·(σt_c(x)/μ̄), so with
/// r_c = Π_nulls σn_c/μ̄:
///   collision: weight = r ⊙ σs(x) / Σ p_c r_c σt_c(x),   emitted = r ⊙ σt(x) ⊙ Le / (same);
///   passing:   weight = r / Σ p_c r_c.
/// For grey σt every r_c is equal: weight = albedo on a collision and 1 when passing.
template <class Uniform>
MediumEvent sample_distance(const GridMedium& m, const Ray& ray, const Spectrum& beta, Uniform& u) {
    MediumEvent e;
    e.weight = Spectrum(1.f);
    const detail::GridRay r = detail::to_grid(m, ray);
    const Spectrum st = m.sigma_t * r.len;
    const float st_max = st.max_component();
    if (!r.hit || !(st_max > 0.f)) return e;
    const Spectrum pmf = channel_pmf(beta);
    const int c = sample_channel(pmf, detail::draw(u()));
    Spectrum ratio(1.f);
    detail::for_each_majorant_segment(*m.grid, r, [&](float ta, float tb, float dmaj) {
        const float mu = dmaj * st_max;
        if (!(mu > 0.f)) return true;
        for (float t = ta;;) {
            t -= std::log1p(-detail::draw(u())) / mu;
            if (!(t < tb)) return true;
            const Spectrum sig = st * m.grid->density(r.o + r.d * t);
            Spectrum pr = sig / mu;
            for (int k = 0; k < 3; ++k) pr[k] = std::min(pr[k], 1.f);
            if (detail::draw(u()) < pr[c]) {
                const float den = detail::dot3(pmf, ratio * pr) * mu;
                e.scattered = true;
                e.t = t;
                e.weight = den > 0.f ? ratio * sig * m.albedo / den : Spectrum(0.f);
                e.emitted = den > 0.f ? ratio * sig * m.le / den : Spectrum(0.f);
                return false;
            }
            ratio = ratio * (Spectrum(1.f) - pr);
            ratio /= ratio.max_component();  // the weights are ratios: keep r away from underflow
        }
    });
    if (!e.scattered) {
        const float den = detail::dot3(pmf, ratio);
        e.weight = den > 0.f ? ratio / den : Spectrum(0.f);
    }
    return e;
}

/// Ratio tracking (Cramer 1978; Novák et al. 2014, eq. 9): T_c = Π over tentative collisions of
/// (1 − σt_c(x_i)/μ̄), one unbiased estimate for all three channels. With Tracking::Delta: delta
/// tracking in channel c* ~ channel_pmf(beta), 0 on a real collision, else r / Σ p_c r_c with r as
/// in sample_distance (for grey σt: 0 or 1).
template <class Uniform>
Spectrum transmittance(const GridMedium& m, const Ray& ray, const Spectrum& beta, Uniform& u) {
    const detail::GridRay r = detail::to_grid(m, ray);
    const Spectrum st = m.sigma_t * r.len;
    const float st_max = st.max_component();
    if (!r.hit || !(st_max > 0.f)) return Spectrum(1.f);
    const bool delta = m.tracking == Tracking::Delta;
    const Spectrum pmf = channel_pmf(beta);
    const int c = delta ? sample_channel(pmf, detail::draw(u())) : 0;
    Spectrum tr(1.f);
    bool absorbed = false;
    detail::for_each_majorant_segment(*m.grid, r, [&](float ta, float tb, float dmaj) {
        const float mu = dmaj * st_max;
        if (!(mu > 0.f)) return true;
        for (float t = ta;;) {
            t -= std::log1p(-detail::draw(u())) / mu;
            if (!(t < tb)) return true;
            Spectrum pr = st * m.grid->density(r.o + r.d * t) / mu;
            for (int k = 0; k < 3; ++k) pr[k] = std::min(pr[k], 1.f);
            if (delta && detail::draw(u()) < pr[c]) {
                absorbed = true;
                return false;
            }
            tr = tr * (Spectrum(1.f) - pr);
            if (delta) tr /= tr.max_component();
            else if (tr.is_black()) return false;
        }
    });
    if (absorbed) return Spectrum(0.f);
    if (!delta) return tr;
    const float den = detail::dot3(pmf, tr);
    return den > 0.f ? tr / den : Spectrum(0.f);
}
}  // namespace pellucid
