// Radial diffusion profiles of a semi-infinite scattering medium under a normal searchlight: the
// classical dipole (Jensen et al. 2001) and the better dipole (d'Eon 2012), with exact totals,
// exact-CDF radius sampling, the hemispherical Fresnel moments they use, and the inversion from a
// diffuse colour and mean free path. docs/subsurface.md states their accuracy against the random walk.
// SPDX-License-Identifier: Apache-2.0
//
// CONVENTIONS (checked by tests/cpp/bssrdf/test_profile.cpp):
//  * Units: σa, σs in 1/length (scene units); r in length; R(r) = eval(r) in 1/length² (exitance per
//    unit area per unit entered flux); total() is dimensionless.
//  * eta is the index of the medium relative to the outside (1.33 for water in air).
//  * R(r) = α'·S(r σ't)·σ't², where α' = σ's/σ't is the reduced albedo and S is the profile in units
//    of the reduced mean free path; sample() and pdf() follow S (not α'), so they are defined even at
//    α' = 0, where eval() and total() are 0.
//  * sample(u) inverts the exact CDF of 2πr R(r) truncated at r_max(), the radius holding 99.9 % of
//    R's mass: its density per unit area is pdf(r) = R(r)/(0.999·total()) on [0, r_max] (for α' > 0)
//    and 0 beyond, so pdf() > 0 wherever eval() > 0 inside r_max. The last 0.1 % of the profile's
//    mass lies beyond r_max and is never sampled.
//  * A medium with σ't = 0 (nothing to scatter or absorb) has the empty profile: every member returns
//    0, diffusion_length() and mean_free_path() return +∞.
//  * diffusion_length() is +∞ when σa = 0. Every other member is finite and ≥ 0 for finite, non-
//    negative σa and σs, g ∈ [−1, 1) and eta > 0.
#pragma once
#include <cstddef>
#include <string>
#include <type_traits>

namespace pellucid::bssrdf {

/// The diffusion model of a profile.
enum class Diffusion {
    Dipole,        ///< Jensen, Marschner, Levoy, Hanrahan 2001, "A Practical Model for Subsurface Light Transport"
    BetterDipole,  ///< d'Eon 2012, "A Better Dipole" (Grosjean's D, moment boundary condition, fluence + flux exitance)
};

/// The model's name in scenes and Python: "dipole", "better_dipole".
const char* to_string(Diffusion model);
/// The model of a name given by to_string; false (out untouched) for any other name.
bool parse_diffusion(const std::string& name, Diffusion* out);

/// Hemispherical Fresnel moment C_i = ∫0^1 F(μ) μ^i dμ (i ≥ 0) of a smooth dielectric boundary whose
/// inside has index eta relative to the outside. internal: light arriving from the inside (total
/// internal reflection included when eta > 1), else from the outside. μ is the cosine of the angle of
/// arrival on the side the light comes from. Computed by Gauss–Legendre quadrature of the exact
/// fresnel_dielectric (split at the critical angle, with a change of variable that removes the
/// square-root kink there; accurate to ~1e-12), not by polynomial fits. eta ≤ 0 or non-finite gives 0.
double fresnel_moment(int i, double eta, bool internal);

/// c = 1 − 2·C1(eta, external): the normalisation of the Fresnel exit lobe (1 − F(cos θ))/(c π),
/// which makes ∫ (1 − F(cos θ))/(c π) cos θ dω = 1 over the outside hemisphere (F is the reflectance
/// seen from the outside at angle θ). 1 for eta = 1.
float exit_lobe_norm(float eta);

/// The boundary condition both models take from the internal Fresnel moments of index eta:
/// t1 = 1 − 2C1 and t2 = 1 − 3C2, computed as 2∫(1 − F)μ dμ and 3∫(1 − F)μ² dμ (no cancellation).
/// The quadrature is most of Profile::make's cost: a material computes them once for its channels.
struct BoundaryMoments {
    double t1 = 1.0, t2 = 1.0;
};
BoundaryMoments boundary_moments(float eta);

/// One colour channel's radial profile R(r) of a semi-infinite medium (σa, σs, g, η) under the
/// diffusion model: exitance per unit area at distance r from a unit flux that entered at r = 0.
/// Trivially copyable and small (stored per material and channel); all members are const and cheap
/// except sample(), which runs a safeguarded Newton iteration (7 to 15 steps, about 0.5 µs).
struct Profile {
    /// The profile of (σa, σs, g, η). Negative or non-finite inputs are clamped to the valid range
    /// (σ ≥ 0, g ∈ [−1, 1], eta > 0; NaN → 0, eta NaN → 1); g = 1 leaves σ's = 0.
    static Profile make(Diffusion model, float sigma_a, float sigma_s, float g, float eta);
    /// The same with the boundary's moments already computed (boundary_moments(eta)).
    static Profile make(Diffusion model, float sigma_a, float sigma_s, float g, const BoundaryMoments& moments);

    /// R(r) ≥ 0 in 1/length²; r < 0 is treated as |r|.
    float eval(float r) const;
    /// ∫0^∞ 2πr R(r) dr (the total diffuse reflectance), in closed form; in [0, 1].
    float total() const;
    /// A radius in [0, r_max()] for u ∈ [0, 1), with density pdf() per unit area.
    float sample(float u) const;
    /// Density of sample() per unit AREA of the plane at radius r (the radial density is 2πr·pdf(r)).
    float pdf(float r) const;
    /// The radius holding 99.9 % of the profile's mass; sample() never exceeds it.
    float r_max() const;
    /// 1/σtr of the model (Dipole: σtr = sqrt(3σa σ't); BetterDipole: sqrt(σa/D), D Grosjean's).
    float diffusion_length() const;
    /// 1/σ't = 1/(σa + σs(1 − g)).
    float mean_free_path() const;
    /// σ's/σ't, the reduced single-scattering albedo α'.
    float reduced_albedo() const { return float(m_alpha); }
    Diffusion model() const { return m_model; }

    // The profile in units of the reduced mean free path (ρ = r·σ't), without the α' factor:
    // S(ρ) and its tail mass T(ρ) = ∫ρ^∞ 2πρ' S(ρ') dρ' (so R(r) = α' σ't² S(r σ't)).
    double shape(double rho) const;
    double shape_tail(double rho) const;

private:
    friend double total_of_reduced_albedo(Diffusion, double, double);
    friend bool from_diffuse(Diffusion, float, float, float, float, float*, float*);
    void set_shape(Diffusion model, double alpha_p, double t1, double t2);
    double solve_tail(double target) const;

    Diffusion m_model = Diffusion::Dipole;
    double m_alpha = 0.0;      ///< α'
    double m_sigma_tp = 0.0;   ///< σ't (1/length); 0 for the empty profile
    double m_s = 0.0;          ///< σtr/σ't
    double m_zv = 1.0;         ///< virtual source height above the surface, in units of 1/σ't (real source depth is 1)
    double m_cphi = 0.0;       ///< weight of the fluence term (BetterDipole), including 1/(4πD̃)
    double m_ce = 1.0 / (4.0 * 3.14159265358979323846);  ///< weight of the flux terms, including 1/(4π)
    double m_tail0 = 0.0;      ///< shape_tail(0): the total of S
    double m_rho_max = 0.0;    ///< r_max·σ't
};

static_assert(std::is_trivially_copyable_v<Profile>, "Profile is stored per material and channel: no heap");

/// Inversion: the σa, σs (given g, η, the model) whose profile has total() == albedo ∈ [0, 1) and whose
/// mean free path 1/σ't == mfp. False (outputs untouched) when albedo is out of range, mfp is not finite
/// and > 0, g is not in [−1, 1) or eta is not finite and > 0.
bool from_diffuse(Diffusion model, float albedo, float mfp, float g, float eta, float* sigma_a, float* sigma_s);

/// out[i] = p.eval(r[i]), p.pdf(r[i]), p.sample(u[i]) for i < n (the loops of the Python binding).
void eval_batch(const Profile& p, const float* r, size_t n, float* out);
void pdf_batch(const Profile& p, const float* r, size_t n, float* out);
void sample_batch(const Profile& p, const float* u, size_t n, float* out);

/// The total of the profile with reduced albedo alpha_p ∈ [0, 1] (independent of σ't), for charts and
/// for from_diffuse.
double total_of_reduced_albedo(Diffusion model, double alpha_p, double eta);
}  // namespace pellucid::bssrdf
