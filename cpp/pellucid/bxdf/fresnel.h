// Fresnel reflectance: exact dielectric and conductor formulas, Schlick's approximation, and the
// tiny policy structs that BxDF templates take as their Fresnel parameter.
// SPDX-License-Identifier: Apache-2.0
//
// Conventions: cos_theta_i is the cosine between the incident direction and the interface normal of
// the side it arrives from; `eta` is the RELATIVE index η_t/η_i seen from the +normal side (eta > 1
// means "entering a denser medium" when cos_theta_i > 0). All reflectances are unpolarised
// (average of s and p), in [0, 1].
#pragma once
#include <algorithm>
#include <cmath>
#include <string>
#include <type_traits>

#include "pellucid/math/constants.h"
#include "pellucid/math/lane_types.h"
#include "pellucid/math/spectrum.h"
#include "pellucid/simd/lane.h"

namespace pellucid {

/// Exact unpolarised Fresnel reflectance of a dielectric interface (Born & Wolf, "Principles of
/// Optics", §1.5.2, eqs. 21a/21b; also Hecht, "Optics", eq. 4.42–4.43).
/// cos_i < 0 means the direction arrives from the −normal side: the interface is flipped
/// (eta → 1/eta). Returns 1 on total internal reflection and exactly 0 for eta == 1.
/// If cos_t / eta_t are given they receive |cos θt| and the η actually used (undefined on TIR).
template <class F>
inline F fresnel_dielectric(F cos_i, F eta, F* cos_t_out = nullptr, F* eta_used = nullptr) {
    // Over a lane type F (simd/lane.h); the float instantiation is the scalar function below.
    // Every branch of the scalar form is a per-lane select here, with the same operations.
    cos_i = lane::select(cos_i < F(-1.f), F(-1.f), lane::select(cos_i > F(1.f), F(1.f), cos_i));
    const auto back = cos_i < F(0.f);
    eta = lane::select(back, F(1.f) / eta, eta);
    cos_i = lane::select(back, lane::neg(cos_i), cos_i);
    if (eta_used) *eta_used = eta;
    // Snell: sin θt = sin θi / η.
    const F x = F(1.f) - cos_i * cos_i;
    const F sin2_i = lane::select(F(0.f) < x, x, F(0.f));
    const F sin2_t = sin2_i / (eta * eta);
    const F y = F(1.f) - sin2_t;
    const F cos_t = lane::sqrt(lane::select(F(0.f) < y, y, F(0.f)));
    const F r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    const F r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    const F r = F(0.5f) * (r_parl * r_parl + r_perp * r_perp);
    const auto matched = eta == F(1.f);
    if (cos_t_out) *cos_t_out = lane::select(matched, cos_i, cos_t);
    const F R = lane::select(r < F(0.f), F(0.f), lane::select(r > F(1.f), F(1.f), r));
    return lane::select(matched, F(0.f), lane::select(sin2_t >= F(1.f), F(1.f), R));
}
inline float fresnel_dielectric(float cos_i, float eta, float* cos_t_out = nullptr, float* eta_used = nullptr) {
    return fresnel_dielectric<float>(cos_i, eta, cos_t_out, eta_used);
}

/// fresnel_dielectric in double precision over a double lane type D (double, or a double packet:
/// simd/lane.h, "The double side"), for the rough dielectrics' half-vector step (dielectric.h) and
/// the precomputed tables and profiles. The scalar form's branches are per-lane selects computing the same IEEE operations,
/// so each lane of a packet is the double function's result, bit for bit. (D = float is excluded:
/// a call with float arguments takes the double function.)
template <class D, std::enable_if_t<std::is_same_v<D, double> || !std::is_arithmetic_v<D>, int> = 0>
inline D fresnel_dielectric_d(D cos_i, D eta, D inv_eta) {
    const D zero(0.0), one(1.0);
    cos_i = lane::select(D(-1.0) < cos_i, cos_i, D(-1.0));  // std::max(-1, cos_i)
    cos_i = lane::select(cos_i < one, cos_i, one);          // std::min(1, cos_i)
    const auto back = cos_i < zero;
    const D e = lane::select(back, inv_eta, eta), inv_e = lane::select(back, eta, inv_eta);
    cos_i = lane::select(back, lane::neg(cos_i), cos_i);
    const D x = one - cos_i * cos_i;
    const D sin2_t = lane::select(zero < x, x, zero) * (inv_e * inv_e);
    const D cos_t = lane::sqrt(one - sin2_t);  // NaN on TIR, not selected
    // r_parl = a/b, r_perp = c/d over one division: (a²d² + c²b²)/(b²d²). b, d > 0 wherever the
    // result is selected (cos θi = 0 with cos θt = 0 is total internal reflection).
    const D a = e * cos_i - cos_t, b = e * cos_i + cos_t;
    const D c = cos_i - e * cos_t, d = cos_i + e * cos_t;
    const D b2 = b * b, d2 = d * d;
    const D r = D(0.5) * ((a * a * d2 + c * c * b2) / (b2 * d2));
    return lane::select(eta == one, zero, lane::select(sin2_t >= one, one, lane::select(r < one, r, one)));
}
template <class D, std::enable_if_t<std::is_same_v<D, double> || !std::is_arithmetic_v<D>, int> = 0>
inline D fresnel_dielectric_d(D cos_i, D eta) {
    return fresnel_dielectric_d<D>(cos_i, eta, D(1.0) / eta);
}
inline double fresnel_dielectric_d(double cos_i, double eta) { return fresnel_dielectric_d<double>(cos_i, eta); }

/// A half-vector step written over a double lane type (dielectric_half_d, principled_half_d) run on
/// a float packet's double parts: fn(wo, wi, eta) on each part, into r[0..kDoubleParts<F>).
template <class F, class R, class Fn>
inline void on_double_parts(const V3<F>& wo, const V3<F>& wi, const F& eta, Fn fn, R* r) {
    using D = DoubleT<F>;
    constexpr int P = kDoubleParts<F>;
    D ox[P], oy[P], oz[P], ix[P], iy[P], iz[P], e[P];
    lane::to_doubles(wo.x, ox), lane::to_doubles(wo.y, oy), lane::to_doubles(wo.z, oz);
    lane::to_doubles(wi.x, ix), lane::to_doubles(wi.y, iy), lane::to_doubles(wi.z, iz);
    lane::to_doubles(eta, e);
    for (int p = 0; p < P; ++p) r[p] = fn(Vec3P<D>(ox[p], oy[p], oz[p]), Vec3P<D>(ix[p], iy[p], iz[p]), e[p]);
}
/// One field of on_double_parts' results rounded to float, on the lanes `where` (`other` elsewhere).
template <class F, class R, class Field>
inline F from_double_parts(const MaskT<F>& where, const R* r, Field field, float other) {
    DoubleT<F> parts[kDoubleParts<F>];
    for (int p = 0; p < kDoubleParts<F>; ++p) parts[p] = field(r[p]);
    return lane::select(where, lane::from_doubles(parts), F(other));
}

/// Exact unpolarised reflectance of a conductor with complex relative IOR η + i·k for one
/// wavelength (Born & Wolf §14.2; the same formula as the dielectric case with complex η, computed
/// in double precision so that k up to ~1e4 stays accurate). cos_i is clamped to [0, 1].
double fresnel_conductor_1(double cos_i, double eta, double k);

/// The same reflectance in real arithmetic over a lane type F (simd/lane.h), for render time.
/// With n cos θt = a + ib = sqrt(n² − sin²θi), n = η + ik (so a² − b² = t0 = η² − k² − sin²θi and
/// ab = ηk), the two polarisations are (Born & Wolf §14.2, eqs. 20–21, as rearranged in Heavens,
/// "Optical Properties of Thin Solid Films", 1955, §4):
///   Rs = ((c − a)² + b²) / ((c + a)² + b²),
///   Rp = Rs · ((a c − s²)² + b² c²) / ((a c + s²)² + b² c²),   c = cos θi, s² = sin²θi,
/// each a ratio of sums of squares, so nothing cancels there. a and b come from a² + b² =
/// sqrt(t0² + 4η²k²) without cancellation: the root of the larger of a², b² is taken and the other
/// follows from ab = ηk. t0 is formed as (η − 1)(η + 1) − k² + c², exact for η = 1, k = 0.
/// Against the complex double formula (fresnel_conductor_1) over 2·10⁵ random float inputs
/// (η ∈ [1e-3, 100], k ∈ [1e-6, 100]): median relative error 5e-8, 99.9th percentile 8e-7; the
/// worst, 1.7e-4, is at an unphysical η < 0.1 with k < 1e-4 near normal incidence, where t0 itself
/// cancels. cos_i is clamped to [0, 1] (callers pass |cos θi|).
template <class F>
inline F fresnel_conductor(F cos_i, F eta, F k) {
    const F zero(0.f), one(1.f), half(0.5f);
    const F c = lane::select(cos_i < zero, zero, lane::select(cos_i > one, one, cos_i));
    const F c2 = c * c;
    const F s2x = (one - c) * (one + c);
    const F s2 = lane::select(s2x < zero, zero, s2x);
    const F t0 = (eta - one) * (eta + one) - k * k + c2;
    const F ek = eta * k;
    const F A = lane::sqrt(t0 * t0 + F(4.f) * ek * ek);  // a² + b²
    const auto pos = t0 >= zero;
    const F big = lane::sqrt(half * (A + lane::abs(t0)));  // a when t0 ≥ 0, else b
    const F other = lane::select(big > zero, ek / big, zero);
    const F a = lane::select(pos, big, other);
    const F b = lane::select(pos, other, big);
    const F b2 = b * b;
    const F ds = (c + a) * (c + a) + b2;
    const F Rs = lane::select(ds > zero, ((c - a) * (c - a) + b2) / ds, one);
    const F ac = a * c, b2c2 = b2 * c2;
    const F dp = (ac + s2) * (ac + s2) + b2c2;
    const F Rp = lane::select(dp > zero, Rs * (((ac - s2) * (ac - s2) + b2c2) / dp), Rs);
    const F R = half * (Rs + Rp);
    const F Rc = lane::select(R > one, one, R);
    // η = k = 0 is a degenerate input treated as a perfect mirror (as fresnel_conductor_1 does).
    return lane::select((eta == zero) & (k == zero), one, lane::select(Rc < zero, zero, Rc));
}

/// Per RGB channel conductor reflectance.
inline Spectrum fresnel_conductor(float cos_i, const Spectrum& eta, const Spectrum& k) {
    return Spectrum(fresnel_conductor<float>(cos_i, eta.r, k.r), fresnel_conductor<float>(cos_i, eta.g, k.g),
                    fresnel_conductor<float>(cos_i, eta.b, k.b));
}

/// Schlick 1994, "An Inexpensive BRDF Model for Physically-based Rendering", eq. 15:
/// F ≈ R0 + (1 − R0)(1 − cos θ)^5, with R0 = ((η1 − η2)/(η1 + η2))² the normal-incidence value.
/// Measured error against fresnel_dielectric: see docs/materials.md and test_fresnel.cpp.
inline float fresnel_schlick(float cos_i, float r0) {
    float m = clamp(1.f - std::fabs(cos_i), 0.f, 1.f);
    float m2 = m * m;
    return r0 + (1.f - r0) * (m2 * m2 * m);
}
inline Spectrum fresnel_schlick(float cos_i, const Spectrum& r0) {
    float m = clamp(1.f - std::fabs(cos_i), 0.f, 1.f);
    float m2 = m * m, m5 = m2 * m2 * m;
    return r0 + (Spectrum(1.f) - r0) * m5;
}
/// Normal-incidence reflectance ((η1 − η2)/(η1 + η2))² for a relative index η = η2/η1.
inline float schlick_r0(float eta) { return sqr((eta - 1.f) / (eta + 1.f)); }

/// Hemispherical (cosine-weighted) average of the dielectric reflectance,
/// F_avg = 2 ∫₀¹ F(μ, η) μ dμ (the "diffuse Fresnel reflectance"; d'Eon & Irving 2011 call it
/// the first Fresnel moment ×2). Computed by 32-point Gauss–Legendre quadrature, split at the
/// critical angle when η < 1, so it is accurate to ~1e-6 (tested).
float fresnel_dielectric_average(float eta);
/// The same average for a conductor, per channel, by quadrature (used by Kulla–Conty).
Spectrum fresnel_conductor_average(const Spectrum& eta, const Spectrum& k);

/// Policy: exact dielectric Fresnel with relative IOR eta.
struct DielectricFresnel {
    float eta = 1.5f;
    Spectrum eval(float cos_theta_i) const { return Spectrum(fresnel_dielectric(cos_theta_i, eta)); }
    Spectrum average() const { return Spectrum(fresnel_dielectric_average(eta)); }
    std::string to_string() const { return "DielectricFresnel[eta=" + std::to_string(eta) + "]"; }
};
/// Policy: exact conductor Fresnel with complex IOR eta + i k per channel, or (schlick = true)
/// Schlick's approximation seeded with the exact normal-incidence reflectance r0 = F(1; η, k) —
/// the usual "F0 from measured data" practice; build that form with schlick_from().
struct ConductorFresnel {
    Spectrum eta{0.2f, 0.92f, 1.1f};  // gold-like default; see ior.h for named metals
    Spectrum k{3.9f, 2.45f, 2.14f};
    bool schlick = false;
    Spectrum r0{0.f};  ///< used only when schlick

    static ConductorFresnel schlick_from(const Spectrum& eta, const Spectrum& k) {
        return ConductorFresnel{eta, k, true, fresnel_conductor(1.f, eta, k)};
    }
    Spectrum eval(float cos_theta_i) const {
        return schlick ? fresnel_schlick(cos_theta_i, r0) : fresnel_conductor(std::fabs(cos_theta_i), eta, k);
    }
    /// Schlick: closed form 2∫(R0 + (1−R0)(1−μ)^5) μ dμ = R0 + (1 − R0)/21.
    Spectrum average() const {
        return schlick ? r0 + (Spectrum(1.f) - r0) * (1.f / 21.f) : fresnel_conductor_average(eta, k);
    }
    std::string to_string() const {
        return "ConductorFresnel[eta=" + eta.to_string() + ", k=" + k.to_string() +
               (schlick ? ", schlick r0=" + r0.to_string() : std::string()) + "]";
    }
};
/// Fresnel averages precomputed from constant parameters. A material computes them once at load
/// (material/*.h) and hands them to the BxDF constructors that need an average (plastic's R̄,
/// Kulla–Conty of rough_dielectric and rough_conductor). A textured material builds its BxDF at every
/// hit (material/textured.h) from the same constants: get() returns the stored value when asked
/// for the parameters it was computed from (bit for bit, so the result is the one the quadrature
/// gives), and runs the quadrature otherwise, i.e. at every hit where the IOR itself is textured.
struct DielectricFresnelAverage {
    float eta = 1.f;
    float value = 0.f;  ///< fresnel_dielectric_average(eta) (0 for the default η = 1)
    static DielectricFresnelAverage of(float eta);
    float get(float eta) const;
};
struct ConductorFresnelAverage {
    ConductorFresnel fresnel;
    Spectrum value{0.f};  ///< fresnel.average()
    bool valid = false;   ///< false: get() always computes
    static ConductorFresnelAverage of(const ConductorFresnel& f);
    Spectrum get(const ConductorFresnel& f) const;
};
/// A Fresnel policy's average(), from `pre` where one applies (ConductorFresnel) and not null.
template <class Fresnel>
Spectrum fresnel_average(const Fresnel& f, const ConductorFresnelAverage*) {
    return f.average();
}
inline Spectrum fresnel_average(const ConductorFresnel& f, const ConductorFresnelAverage* pre) {
    return pre ? pre->get(f) : f.average();
}
/// fresnel_dielectric_average(eta), from `pre` when not null.
inline float fresnel_average(float eta, const DielectricFresnelAverage* pre) {
    return pre ? pre->get(eta) : fresnel_dielectric_average(eta);
}

/// Policy: Schlick's approximation with normal-incidence reflectance r0 per channel.
struct SchlickFresnel {
    Spectrum r0{0.04f};
    Spectrum eval(float cos_theta_i) const { return fresnel_schlick(cos_theta_i, r0); }
    /// Closed form: 2∫(R0 + (1−R0)(1−μ)^5) μ dμ = R0 + (1 − R0)/21.
    Spectrum average() const { return r0 + (Spectrum(1.f) - r0) * (1.f / 21.f); }
    std::string to_string() const { return "SchlickFresnel[r0=" + r0.to_string() + "]"; }
};
}  // namespace pellucid
