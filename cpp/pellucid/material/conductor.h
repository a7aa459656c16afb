// Conductor materials: `conductor` (smooth mirror) and `rough_conductor` (microfacet).
// SPDX-License-Identifier: Apache-2.0
//
// `conductor` (bxdf/conductor.h, SmoothConductor):
// | parameter            | type     | default | meaning                                                  |
// |----------------------|----------|---------|----------------------------------------------------------|
// | material             | string   | "none"  | metal preset of bxdf/ior.h (Au, Ag, Cu, Al, Cr, Fe, Ti, Ni; "none" = ideal mirror, F ≡ 1) |
// | eta, k               | colour   | —, 0    | complex IOR instead of `material` (eta > 0 required, k ≥ 0); not with `material` |
// | specular_reflectance | colour   | 1       | multiplier on F, in [0, 1]                               |
// | fresnel              | string   | "exact" | "exact" or "schlick" (Schlick 1994 with the exact R0 = F(0°)) |
// JSON: {"type": "conductor", "material": "Au"}
//
// `rough_conductor` (MicrofacetReflection<GGX|Beckmann, ConductorFresnel>): the above plus
// | parameter           | type   | default | meaning                                                   |
// |---------------------|--------|---------|-----------------------------------------------------------|
// | distribution        | string | "ggx"   | "ggx" or "beckmann"                                       |
// | alpha               | float  | 0.1     | isotropic α ≥ 0 (> 1 clamped to 1; < 1e-3 → delta mirror) |
// | alpha_u, alpha_v    | float  | —       | anisotropic α (alpha_v defaults to alpha_u); not with alpha |
// | roughness           | float  | —       | perceptual r ∈ [0, 1] instead of α: α = r² (Burley 2012 §5.4) |
// | shadowing           | string | "height_correlated" | or "separable": the Smith G form (bxdf/microfacet.h) |
// | multiple_scattering | bool   | false   | Kulla–Conty energy compensation (ggx only; height_correlated only) |
// JSON: {"type": "rough_conductor", "material": "Al", "alpha_u": 0.05, "alpha_v": 0.3,
//        "multiple_scattering": true}
#pragma once
#include <string>

#include "pellucid/bxdf/bxdf.h"
#include "pellucid/geometry/interaction.h"
#include "pellucid/material/params.h"

namespace pellucid {

struct ConductorParams {
    ConductorIORParams ior;
    Spectrum specular_reflectance{1.f};
};

class ConductorMaterial {
public:
    explicit ConductorMaterial(const ConductorParams& p) : m_p(p) {}
    BxDF get_bxdf(const SurfaceInteraction&) const { return bxdf_for(m_p); }
    /// The BxDF of `p`: params() with textured fields written in (material/textured.h).
    BxDF bxdf_for(const ConductorParams& p) const;
    const ConductorParams& params() const { return m_p; }
    std::string to_string() const;

private:
    ConductorParams m_p;
};

struct RoughConductorParams {
    MicrofacetParams microfacet;
    ConductorIORParams ior;
    Spectrum specular_reflectance{1.f};
    bool multiple_scattering = false;
};

class RoughConductorMaterial {
public:
    /// With multiple_scattering, computes Kulla–Conty's Fresnel average once.
    explicit RoughConductorMaterial(const RoughConductorParams& p);
    BxDF get_bxdf(const SurfaceInteraction&) const { return bxdf_for(m_p); }
    /// The BxDF of `p`: params() with textured fields written in (material/textured.h), reusing
    /// the Fresnel average computed at construction while p's eta, k and fresnel are params()'s.
    BxDF bxdf_for(const RoughConductorParams& p) const;
    const RoughConductorParams& params() const { return m_p; }
    std::string to_string() const;

private:
    RoughConductorParams m_p;
    ConductorFresnelAverage m_fresnel_avg;  // fresnel.h
};
}  // namespace pellucid
