// The separable BSSRDF a diffusion profile renders with, and the probe rays that find its exit
// points (docs/subsurface.md).
// SPDX-License-Identifier: Apache-2.0
//
// S(po, ωo; pi, ωi) = (1 − F(cos θo)) · Sp(|po − pi|) · Sw(ωi)   (pbrt-v3 §11.4, "separable BSSRDF"):
//  * (1 − F(cos θo)) is the boundary's transmission where the path enters (the material's
//    dielectric BxDF samples it: the estimator keeps that sample's weight);
//  * Sp(r) = R(r), the radial profile of bssrdf/profile.h, one per colour channel;
//  * Sw(ωi) = (1 − F(cos θi))/(c π), c = 1 − 2·C1(η) (bssrdf::exit_lobe_norm): a normalised Fresnel
//    exit lobe, so a unit flux that entered leaves with R's total reflectance.
// The entry's refraction scales radiance by 1/η² and leaving scales it back by η²: the estimator
// applies neither (entry_weight below undoes the entry's).
//
// Exit points come from probe rays (King et al. 2013, "BSSRDF importance sampling", SIGGRAPH talk;
// as pbrt-v3 `SeparableBSSRDF::Sample_Sp`): a projection axis (the shading normal with probability
// 1/2, each tangent with 1/4), a colour channel (1/3 each), a radius r from that channel's profile
// and an angle φ give a point on the disk around po perpendicular to the axis; the chord through
// it along the axis, inside the sphere of radius r_max around po, is traced, and one of the hits on
// the same object is kept (uniformly). The density of the exit point per unit surface area is the
// one-sample MIS mixture over the 3 axes × 3 channels (the balance heuristic, Veach 1997 §9.2.4):
//   pdf(pi) = Σ_axis P(axis) Σ_ch (1/3) · pdf_ch(r_axis) · |n_i · axis| / N_hits,
// with r_axis the distance from po to pi across the axis.
#pragma once
#include <cstdint>

#include "pellucid/bssrdf/profile.h"
#include "pellucid/bxdf/bxdf_types.h"
#include "pellucid/geometry/interaction.h"
#include "pellucid/material/subsurface.h"
#include "pellucid/math/spectrum.h"

namespace pellucid {
class Scene;

/// Per channel σa, σs (1/scene unit) and g of a `subsurface` material: its sigma_a/sigma_s × scale,
/// or its albedo + mfp inverted by the model's profile (bssrdf::from_diffuse; albedo 1: σa = 0).
/// `model` is the diffusion model the inversion uses (the random walk uses the better dipole's).
/// The parameters are read through `tex` (TexEval{}: their constants).
void subsurface_coefficients(const SubsurfaceParams& p, const TexEval& tex, bssrdf::Diffusion model, Spectrum* sigma_a,
                             Spectrum* sigma_s);

struct SeparableBSSRDF {
    bssrdf::Profile profile[3];
    float eta = 1.33f;
    float exit_norm = 1.f;    ///< c of Sw
    float r_max[3] = {0.f, 0.f, 0.f};
    uint32_t shape = 0;       ///< exits count only on this shape
    bssrdf::Diffusion model = bssrdf::Diffusion::BetterDipole;

    /// Sp per channel at distance r.
    Spectrum sp(float r) const;
    /// Total diffuse reflectance per channel (the profile's closed form).
    Spectrum total() const;
    /// Sw·|cos θi| in the exit's local frame (z = the outside normal), and its density (cosine).
    Spectrum exit_eval(const Vec3f& wi_local, float* pdf) const;
    /// A cosine-weighted exit direction (local frame): weight (1 − F(cos θi))/c.
    bool exit_sample(const Vec2f& u, BxDFSample* out) const;
};

/// The BSSRDF of material parameters p, read through `tex`, under a diffusion model, for the given
/// shape.
SeparableBSSRDF make_separable_bssrdf(const SubsurfaceParams& p, const TexEval& tex, bssrdf::Diffusion model,
                                      uint32_t shape);

/// The BSSRDF at a hit of a material with textured parameters: b's model and shape with the
/// material's parameters evaluated at si (its footprint set). b itself where nothing is textured.
SeparableBSSRDF bssrdf_at(const Scene& scene, const SeparableBSSRDF& b, const SurfaceInteraction& si);

/// The entry's sample weight made into the BSSRDF's: × η² (undoing the radiance scaling of the
/// refraction, which the exit undoes in turn) — the boundary's (1 − F) stays in it.
inline float entry_weight_scale(const SeparableBSSRDF& b) { return b.eta * b.eta; }

/// Probe sampling from the entry point `entry` (its shading frame, on the outside): an exit point
/// on the same shape, written to *exit (its wo = the outside normal, its frames turned to the
/// outside), and Sp/pdf per channel into *weight. u_axis picks the axis and channel, u the radius
/// and angle, u_hit the hit among those on the chord. False: no exit found (the path ends).
bool sample_probe(const Scene& scene, const SeparableBSSRDF& b, const SurfaceInteraction& entry, float u_axis,
                  const Vec2f& u, float u_hit, SurfaceInteraction* exit, Spectrum* weight);
/// The density sample_probe gives the exit point pi (per unit area, for N_hits = 1), for tests.
float probe_pdf(const SeparableBSSRDF& b, const SurfaceInteraction& entry, const Point3f& pi, const Normal3f& ni);
}  // namespace pellucid
