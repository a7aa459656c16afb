// Parameter pieces shared by several materials (microfacet roughness, conductor IOR), and the
// formatting helpers of the materials' to_string.
// SPDX-License-Identifier: Apache-2.0
//
// A parameter that may vary over a surface is a Tex<T> (material/tex.h).
#pragma once
#include <string>

#include "pellucid/bxdf/microfacet.h"
#include "pellucid/material/tex.h"
#include "pellucid/math/spectrum.h"

namespace pellucid {

enum class MicrofacetType { GGX, Beckmann };
std::string to_string(MicrofacetType t);

/// Microfacet roughness as read from a scene description: α along the tangent (u) and bitangent (v).
/// α ∈ [0, 1] (the builders clamp α > 1 to 1); α < 1e-3 makes the BxDF a delta lobe (microfacet.h).
/// `shadowing` picks the Smith G2 form (key "shadowing": "height_correlated" or "separable").
struct MicrofacetParams {
    MicrofacetType distribution = MicrofacetType::GGX;
    Tex<float> alpha_u{0.1f}, alpha_v{0.1f};
    SmithShadowing shadowing = SmithShadowing::HeightCorrelated;
    std::string to_string() const;
};

/// Complex IOR of a conductor; `preset` indexes conductor_names() (bxdf/ior.h), -1 when eta/k
/// were given. (An index, not a string, keeps the Params free of heap members.)
struct ConductorIORParams {
    int preset = -1;
    Tex<Spectrum> eta{Spectrum(0.f)}, k{Spectrum(1.f)};  ///< default: ideal mirror (F ≡ 1), ior.h's "none"
    bool schlick = false;  ///< fresnel = "schlick": Schlick with the exact normal-incidence R0
    std::string to_string() const;
};

/// Shortest decimal form of a float ("0.1", "1e-05"), for messages and to_string.
std::string format_float(float v);
std::string format_spectrum(const Spectrum& s);
/// A parameter for to_string: its constant, or "texture N" when bound.
std::string format_tex(const Tex<float>& t);
std::string format_tex(const Tex<Spectrum>& t);
}  // namespace pellucid
