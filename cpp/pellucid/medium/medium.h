// Participating media and the functions the path tracer calls inside them (THE INTEGRATOR CONTRACT).
// SPDX-License-Identifier: Apache-2.0
//
// A medium fills the space a shape bounds (its `interior`) or surrounds (its `exterior`); the
// integrator tracks which medium each ray segment runs through (docs/media.md). Along a segment
// from ray.o to ray.o + ray.tmax·ray.d inside one medium it calls:
//
//   MediumEvent e = sample_distance(medium, ray, beta, u);
//       Samples where the path next interacts with the medium (distance sampling, by one colour
//       channel chosen in proportion to beta, with the balance-heuristic weight over the three
//       channels). Then:  L += beta ⊙ e.emitted;  beta ⊙= e.weight;  and
//         e.scattered: a real collision at x = ray.o + e.t·ray.d: scatter with phase_of(medium)
//                      (wo = −ray.d normalised), next-event estimation from x;
//         otherwise:   the path reaches the end of the segment (the surface hit, or escapes when
//                      ray.tmax is infinite) with the updated beta.
//       On a collision, weight is σs/σt-like (the albedo for grey media): 0 in every channel for a
//       medium that only absorbs, where the integrator may end the path (after adding emitted).
//   Spectrum tr = transmittance(medium, ray, beta, u);
//       An unbiased estimate of the transmittance exp(−∫σt ds) over the segment [0, ray.tmax),
//       per channel, for shadow rays: exact for homogeneous media; ratio tracking for grids, or
//       delta tracking with `tracking: "delta"` (beta then picks the tracked channel).
//   const PhaseFunction& phase_of(medium)   the medium's phase function (medium/phase.h).
//
// `beta` is the path throughput (only its proportions are used; a black or non-finite beta falls
// back to equal channel probabilities). `u` is any callable returning uniform floats in [0, 1):
// the caller owns the random numbers (e.g. `[&] { return sampler.get_1d(); }` or a PCG32 seeded per
// path), so determinism is the integrator's. Tracking in grids draws an unbounded number of them.
// No function allocates, none calls a virtual function; dispatch is std::visit over Medium.
#pragma once
#include <cmath>
#include <memory>
#include <string>
#include <variant>

#include "pellucid/math/lane_exp_log.h"
#include "pellucid/math/lane_types.h"
#include "pellucid/math/ray.h"
#include "pellucid/math/spectrum.h"
#include "pellucid/math/transform.h"
#include "pellucid/medium/density_grid.h"
#include "pellucid/medium/phase.h"

namespace pellucid {

/// What sample_distance returns.
struct MediumEvent {
    bool scattered = false;  ///< true: a real collision at ray parameter t; false: passed the segment
    float t = 0.f;           ///< ray parameter of the collision (scattered only)
    Spectrum weight{0.f};    ///< multiply the path throughput by this (either case)
    Spectrum emitted{0.f};   ///< radiance the medium emits toward the ray origin: L += beta ⊙ emitted
};

/// Shadow-ray transmittance estimator of grid media (the homogeneous one is exact).
enum class Tracking : uint8_t { Ratio, Delta };

/// Constant coefficients (units: 1 / scene unit). Emission: the source term is σt·Le, so an
/// infinite medium of albedo a glows with radiance Le/(1 − a) (docs/media.md).
struct HomogeneousMedium {
    Spectrum sigma_a{0.f}, sigma_s{0.f};  ///< already multiplied by `scale`
    Spectrum le{0.f};                     ///< emitted radiance parameter (0: none)
    PhaseFunction phase = IsotropicPhase{};
    std::string name;
    Spectrum sigma_t() const { return sigma_a + sigma_s; }
    std::string to_string() const;
};

/// σt(x) = density(x)·sigma_t with a constant albedo; density from a DensityGrid on the unit cube
/// that to_world places in the scene; zero density outside it.
struct GridMedium {
    std::shared_ptr<const DensityGrid> grid;
    Mat4f world_to_grid{1.f};   ///< inverse of the medium's to_world
    Spectrum sigma_t{1.f};      ///< per unit density, already multiplied by `scale`
    Spectrum albedo{1.f};       ///< σs/σt
    Spectrum le{0.f};
    PhaseFunction phase = IsotropicPhase{};
    Tracking tracking = Tracking::Ratio;
    std::string name;
    std::string to_string() const;
};

/// The closed list of media (STYLE.md house rule 4).
using Medium = std::variant<HomogeneousMedium, GridMedium>;

inline const PhaseFunction& phase_of(const Medium& m) {
    return std::visit([](const auto& x) -> const PhaseFunction& { return x.phase; }, m);
}
inline const std::string& name_of(const Medium& m) {
    return std::visit([](const auto& x) -> const std::string& { return x.name; }, m);
}
inline std::string to_string(const Medium& m) {
    return std::visit([](const auto& x) { return x.to_string(); }, m);
}

// ---- channel selection and its one-sample MIS ---------------------------------------------------

/// Probability of tracking each colour channel: proportional to the throughput beta (Mitsuba 3's
/// volpath and pbrt-v4 choose by throughput too), or 1/3 each when beta is black or not finite.
inline Spectrum channel_pmf(const Spectrum& beta) {
    const float s = beta.r + beta.g + beta.b;
    if (!(s > 0.f) || !std::isfinite(s) || beta.has_negative()) return Spectrum(1.f / 3.f);
    return beta / s;
}
/// The channel u ∈ [0, 1) picks from pmf.
inline int sample_channel(const Spectrum& pmf, float u) {
    if (u < pmf.r) return 0;
    return u < pmf.r + pmf.g ? 1 : 2;
}
/// Balance-heuristic weights of the one-sample model over channel strategies (Veach 1997, §9.2.4;
/// Miller et al. 2019, "A null-scattering path integral formulation of light transport", §5.2):
/// w_c = p_c·pdf_c / Σ_k p_k·pdf_k; they sum to 1 where any p_k·pdf_k > 0, else all are 0.
inline Spectrum channel_mis_weights(const Spectrum& pmf, const Spectrum& pdfs) {
    const Spectrum m = pmf * pdfs;
    const float s = m.r + m.g + m.b;
    return s > 0.f ? m / s : Spectrum(0.f);
}

namespace detail {
inline float draw(float u) { return std::min(u, kOneMinusEpsilon); }
/// One channel of Beer–Lambert, exp(−σ·t), 1 where σ ≤ 0 (t = ∞ included: the exponent is taken
/// as 0 there, never 0·∞): by lane_math::exp_t, so that packets (homogeneous_step, the path
/// kernel's shadow rays) give the float instantiation's bits.
template <class F>
inline F beer_channel(const F& sigma, const F& t) {
    const auto has = sigma > F(0.f);
    return lane::select(has, lane_math::exp_t(lane::neg(sigma) * lane::select(has, t, F(0.f))), F(1.f));
}
/// exp(−σ·t) per channel, with exp(−0·∞) = 1.
inline Spectrum beer(const Spectrum& sigma, float t) {
    Spectrum r;
    for (int c = 0; c < 3; ++c) r[c] = beer_channel<float>(sigma[c], t);
    return r;
}
}  // namespace detail

// ---- homogeneous --------------------------------------------------------------------------------

/// One step of exponential distance sampling in a homogeneous medium, over a lane type F (float for
/// one path, a packet for one path a lane): channel c* ~ channel_pmf(beta) picked by u_channel,
/// t = −ln(1 − u_t)/σt_c* (pbrt-v3 §15.2.1, eq. 15.10). The estimate of the segment's radiance
///   L = ∫₀^tmax T(s) (σs Ls(s) + σt Le) ds + T(tmax) L_end,   T(s) = exp(−σt s)
/// divides by the mixture pdf over channels, p_mix(t) = Σ_c p_c σt_c T_c(t) for a collision and
/// P_mix = Σ_c p_c T_c(tmax) for passing, i.e. the balance heuristic over the channel strategies:
///   collision: weight = σs ⊙ T(t) / p_mix(t),  emitted = σt ⊙ Le ⊙ T(t) / p_mix(t);
///   passing:   weight = T(tmax) / P_mix.
/// With grey σt this is weight = albedo on a collision and 1 when passing. st, ss and le are σt·|d|,
/// σs·|d| and Le per channel; tmax is +∞ for a ray that hits nothing. The logarithm and the
/// exponentials are lane_math's, so float and every packet give the same bits (the path kernel
/// takes its lanes in homogeneous media as packets, the float instantiation is sample_distance's).
template <class F>
struct HomogeneousStepT {
    MaskT<F> scattered;
    F t;                        ///< the collision's ray parameter (where scattered)
    F weight[3], emitted[3];    ///< as MediumEvent's (emitted 0 where not scattered)
};
template <class F>
inline HomogeneousStepT<F> homogeneous_step(const F* st, const F* ss, const F* le, const F* beta, const F& u_channel,
                                            const F& u_t, const F& tmax) {
    // channel_pmf(beta) and sample_channel.
    const F s = (beta[0] + beta[1]) + beta[2];
    const auto uniform = !(s > F(0.f)) || !(s < F(kInfinity)) || beta[0] < F(0.f) || beta[1] < F(0.f) || beta[2] < F(0.f);
    F pmf[3];
    for (int c = 0; c < 3; ++c) pmf[c] = lane::select(uniform, F(1.f / 3.f), beta[c] / lane::select(uniform, F(1.f), s));
    const auto c0 = u_channel < pmf[0];
    const auto c1 = !c0 && u_channel < pmf[0] + pmf[1];
    auto pick = [&](const F* v) { return lane::select(c0, v[0], lane::select(c1, v[1], v[2])); };
    const F stc = pick(st);
    const auto pos = stc > F(0.f);
    const F t = lane::select(pos, lane::neg(lane_math::log1p_t(lane::neg(u_t))) / lane::select(pos, stc, F(1.f)), F(kInfinity));
    HomogeneousStepT<F> e;
    e.scattered = t < tmax;
    e.t = t;
    // The transmittances up to the collision, or over the segment (exp(−0·∞) = 1), and the
    // densities of the channel strategies: σt ⊙ T(t) for a collision, T(tmax) for passing.
    const F d = lane::select(e.scattered, t, tmax);
    F tr[3], p[3], m[3];
    for (int c = 0; c < 3; ++c) {
        tr[c] = detail::beer_channel<F>(st[c], d);
        p[c] = lane::select(e.scattered, st[c] * tr[c], tr[c]);
        m[c] = pmf[c] * p[c];
    }
    // channel_mis_weights: w_c = p_c·pdf_c / Σ_k p_k·pdf_k, and k = w_c*/(p_c*·pdf_c*).
    const F sum = (m[0] + m[1]) + m[2];
    const auto sum_pos = sum > F(0.f);
    F w[3];
    for (int c = 0; c < 3; ++c) w[c] = lane::select(sum_pos, m[c] / lane::select(sum_pos, sum, F(1.f)), F(0.f));
    const F q = pick(pmf) * pick(p);
    const auto q_pos = q > F(0.f);
    const F k = lane::select(q_pos, pick(w) / lane::select(q_pos, q, F(1.f)), F(0.f));
    for (int c = 0; c < 3; ++c) {
        e.weight[c] = lane::select(e.scattered, (ss[c] * tr[c]) * k, tr[c] * k);
        e.emitted[c] = lane::select(e.scattered, ((st[c] * le[c]) * tr[c]) * k, F(0.f));
    }
    return e;
}

/// Distance sampling in a homogeneous medium: homogeneous_step for one path, its two uniforms
/// drawn from u in order (the channel's, then the distance's).
template <class Uniform>
MediumEvent sample_distance(const HomogeneousMedium& m, const Ray& ray, const Spectrum& beta, Uniform& u) {
    const float len = length(ray.d);
    const Spectrum st = m.sigma_t() * len, ss = m.sigma_s * len;
    const float u_channel = detail::draw(u());
    const float u_t = detail::draw(u());
    const float stv[3] = {st.r, st.g, st.b}, ssv[3] = {ss.r, ss.g, ss.b}, lev[3] = {m.le.r, m.le.g, m.le.b};
    const float bv[3] = {beta.r, beta.g, beta.b};
    const HomogeneousStepT<float> h = homogeneous_step<float>(stv, ssv, lev, bv, u_channel, u_t, ray.tmax);
    MediumEvent e;
    e.scattered = h.scattered;
    if (h.scattered) e.t = h.t;
    e.weight = Spectrum(h.weight[0], h.weight[1], h.weight[2]);
    e.emitted = Spectrum(h.emitted[0], h.emitted[1], h.emitted[2]);
    return e;
}

/// Beer–Lambert, exactly: exp(−σt·|d|·tmax) per channel (beta and u unused).
template <class Uniform>
Spectrum transmittance(const HomogeneousMedium& m, const Ray& ray, const Spectrum& /*beta*/, Uniform& /*u*/) {
    return detail::beer(m.sigma_t() * length(ray.d), ray.tmax);
}
}  // namespace pellucid

#include "pellucid/medium/grid_tracking.h"

namespace pellucid {
// ---- dispatch ----------------------------------------------------------------------------------
template <class Uniform>
MediumEvent sample_distance(const Medium& m, const Ray& ray, const Spectrum& beta, Uniform& u) {
    return std::visit([&](const auto& x) { return sample_distance(x, ray, beta, u); }, m);
}
template <class Uniform>
Spectrum transmittance(const Medium& m, const Ray& ray, const Spectrum& beta, Uniform& u) {
    return std::visit([&](const auto& x) { return transmittance(x, ray, beta, u); }, m);
}
}  // namespace pellucid
