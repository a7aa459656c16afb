// Dielectric materials: `dielectric`, `rough_dielectric`, `thin_dielectric`.
// SPDX-License-Identifier: Apache-2.0
//
// `dielectric` (SmoothDielectric) and `thin_dielectric` (ThinDielectric), bxdf/dielectric.h:
// | parameter              | type         | default | meaning                                          |
// |------------------------|--------------|---------|--------------------------------------------------|
// | int_ior                | float/string | "bk7"   | interior IOR > 0, or a name of bxdf/ior.h ("water", "diamond", ...) |
// | ext_ior                | float/string | "air"   | exterior IOR > 0 (the side the normal points to) |
// | specular_reflectance   | colour       | 1       | multiplier on reflection, in [0, 1]              |
// | specular_transmittance | colour       | 1       | multiplier on transmission, in [0, 1]            |
// JSON: {"type": "dielectric", "int_ior": "water", "ext_ior": "air"}
//
// `rough_dielectric` (RoughDielectric<GGX|Beckmann>, Walter et al. 2007): the above plus
// `distribution` ("ggx" or "beckmann"), `alpha`, `alpha_u`/`alpha_v` or `roughness`, and
// `shadowing`, exactly as for `rough_conductor`, and `multiple_scattering` (bool, default false:
// Kulla–Conty compensation of the reflection + transmission energy, ggx only; bxdf/kulla_conty.h).
// JSON: {"type": "rough_dielectric", "int_ior": 1.5, "alpha": 0.3, "multiple_scattering": true}
#pragma once
#include <string>

#include "pellucid/bxdf/bxdf.h"
#include "pellucid/geometry/interaction.h"
#include "pellucid/material/params.h"

namespace pellucid {

struct DielectricParams {
    float int_ior = 1.5046f, ext_ior = 1.000277f;
    Spectrum specular_reflectance{1.f}, specular_transmittance{1.f};
    float eta() const { return int_ior / ext_ior; }
    std::string to_string() const;
};

class DielectricMaterial {
public:
    explicit DielectricMaterial(const DielectricParams& p) : m_p(p) {}
    BxDF get_bxdf(const SurfaceInteraction&) const { return bxdf_for(m_p); }
    BxDF bxdf_for(const DielectricParams& p) const {
        return SmoothDielectric(p.eta(), p.specular_reflectance, p.specular_transmittance);
    }
    const DielectricParams& params() const { return m_p; }
    std::string to_string() const { return "DielectricMaterial[" + m_p.to_string() + "]"; }

private:
    DielectricParams m_p;
};

class ThinDielectricMaterial {
public:
    explicit ThinDielectricMaterial(const DielectricParams& p) : m_p(p) {}
    BxDF get_bxdf(const SurfaceInteraction&) const { return bxdf_for(m_p); }
    BxDF bxdf_for(const DielectricParams& p) const {
        return ThinDielectric(p.eta(), p.specular_reflectance, p.specular_transmittance);
    }
    const DielectricParams& params() const { return m_p; }
    std::string to_string() const { return "ThinDielectricMaterial[" + m_p.to_string() + "]"; }

private:
    DielectricParams m_p;
};

struct RoughDielectricParams {
    MicrofacetParams microfacet;
    DielectricParams dielectric;
    bool multiple_scattering = false;
};

class RoughDielectricMaterial {
public:
    /// With multiple_scattering, computes the Kulla–Conty set-up's Fresnel average once.
    explicit RoughDielectricMaterial(const RoughDielectricParams& p);
    BxDF get_bxdf(const SurfaceInteraction&) const { return bxdf_for(m_p); }
    /// The BxDF of `p`: params() with textured fields written in (material/textured.h), reusing
    /// the Fresnel average computed at construction while p's IOR is params()'s.
    BxDF bxdf_for(const RoughDielectricParams& p) const;
    const RoughDielectricParams& params() const { return m_p; }
    std::string to_string() const;

private:
    RoughDielectricParams m_p;
    DielectricFresnelAverage m_fresnel_avg;  // RoughDielectric::multiscatter_fresnel_average (fresnel.h)
};
}  // namespace pellucid
