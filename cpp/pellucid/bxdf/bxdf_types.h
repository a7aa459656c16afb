// BxDF conventions, flags and the sample record shared by every reflection model.
// SPDX-License-Identifier: Apache-2.0
//
// CONVENTIONS (checked by tests/cpp/bxdf/test_bxdf_properties.cpp):
//  * All directions are unit vectors in the LOCAL shading frame: z is the shading normal.
//  * Both directions point AWAY from the surface: wo toward the viewer / previous path vertex,
//    wi toward the light / next vertex (pbrt's names).
//  * eval(ctx, wo, wi) returns f(wo, wi)·|cos θi|  (the cosine is included).
//  * pdf(ctx, wo, wi) is a density per unit solid angle of wi.
//  * sample(ctx, wo, u_lobe, u) returns weight = f·|cos θi| / pdf; for a delta lobe the weight is
//    the lobe's throughput divided by its discrete selection probability, pdf holds that
//    probability, and the lobe carries a Specular flag. eval() and pdf() are 0 for delta lobes:
//    delta lobes are reached only through sample().
//  * "No sample" is std::nullopt; a returned sample always has pdf > 0 and finite weight ≥ 0.
//  * TransportMode::Radiance scales refracted throughput by 1/η² (radiance is not conserved across
//    a refractive boundary); TransportMode::Importance does not (Veach 1997, §5.2).
#pragma once
#include <cstdint>
#include <string>

#include <optional>

#include "pellucid/math/lane_types.h"
#include "pellucid/math/spectrum.h"
#include "pellucid/math/vec.h"

namespace pellucid {

enum class BxDFFlags : uint32_t {
    None = 0,
    Reflection = 1 << 0,
    Transmission = 1 << 1,
    Diffuse = 1 << 2,
    Glossy = 1 << 3,
    Specular = 1 << 4,
    DiffuseReflection = Diffuse | Reflection,
    DiffuseTransmission = Diffuse | Transmission,
    GlossyReflection = Glossy | Reflection,
    GlossyTransmission = Glossy | Transmission,
    SpecularReflection = Specular | Reflection,
    SpecularTransmission = Specular | Transmission,
    All = Diffuse | Glossy | Specular | Reflection | Transmission
};
constexpr BxDFFlags operator|(BxDFFlags a, BxDFFlags b) {
    return BxDFFlags(uint32_t(a) | uint32_t(b));
}
constexpr BxDFFlags operator&(BxDFFlags a, BxDFFlags b) {
    return BxDFFlags(uint32_t(a) & uint32_t(b));
}
inline BxDFFlags& operator|=(BxDFFlags& a, BxDFFlags b) { return a = a | b; }
constexpr bool has_flag(BxDFFlags f, BxDFFlags bit) { return (uint32_t(f) & uint32_t(bit)) != 0; }
constexpr bool is_specular(BxDFFlags f) { return has_flag(f, BxDFFlags::Specular); }
constexpr bool is_non_specular(BxDFFlags f) {
    return has_flag(f, BxDFFlags::Diffuse | BxDFFlags::Glossy);
}
constexpr bool is_reflective(BxDFFlags f) { return has_flag(f, BxDFFlags::Reflection); }
constexpr bool is_transmissive(BxDFFlags f) { return has_flag(f, BxDFFlags::Transmission); }
std::string to_string(BxDFFlags f);

/// Which quantity is transported along the path: radiance (camera paths) or importance (light paths).
enum class TransportMode { Radiance, Importance };

/// Per-query context: transport mode and the lobes the caller allows sample() to choose.
struct BxDFContext {
    TransportMode mode = TransportMode::Radiance;
    BxDFFlags allowed = BxDFFlags::All;
};

struct BxDFSample {
    Vec3f wi{0.f};
    Spectrum weight{0.f};  ///< f·|cos θi| / pdf
    float pdf = 0.f;       ///< solid-angle density, or the discrete lobe probability for delta lobes
    float eta = 1.f;       ///< relative IOR crossed along wi (1 for reflection)
    BxDFFlags lobe = BxDFFlags::None;
    bool is_specular() const { return pellucid::is_specular(lobe); }
};

/// A sample of kLaneWidth<F> lanes, as the templated BxDFs return it: `valid` marks the lanes that
/// hold one (a lane without a sample is what std::nullopt is to BxDFSample); `lobe` holds each
/// lane's BxDFFlags bits.
template <class F>
struct BxDFSampleT {
    MaskT<F> valid;
    V3<F> wi;
    RGB<F> weight;
    F pdf;
    F eta;
    IntT<F> lobe;
};
/// A reflection model's sample drawn by picking a lobe and then evaluating the whole model toward wi
/// (the one-sample MIS estimator over the lobes; Veach 1997, §9.2.4): valid on the lanes `ok` whose
/// density is positive, weight f/pdf, lobe DiffuseReflection on the lanes `diffuse` (a diffuse lobe
/// was picked) and GlossyReflection elsewhere.
template <class F>
inline BxDFSampleT<F> reflection_sample_from_eval(const V3<F>& wi, const RGB<F>& f, const F& pdf, const MaskT<F>& ok,
                                                  const MaskT<F>& diffuse) {
    BxDFSampleT<F> s;
    s.valid = ok && pdf > F(0.f);
    s.wi = wi;
    s.pdf = pdf;
    s.weight = f / lane::select(s.valid, pdf, F(1.f));
    s.eta = F(1.f);
    s.lobe = lane::select(lane::int_mask(diffuse), IntT<F>(int32_t(BxDFFlags::DiffuseReflection)),
                          IntT<F>(int32_t(BxDFFlags::GlossyReflection)));
    return s;
}
/// The one-lane sample as the scalar BxDF API returns it.
inline std::optional<BxDFSample> to_optional(const BxDFSampleT<float>& s) {
    if (!s.valid) return std::nullopt;
    BxDFSample r;
    r.wi = s.wi;
    r.weight = s.weight;
    r.pdf = s.pdf;
    r.eta = s.eta;
    r.lobe = BxDFFlags(uint32_t(s.lobe));
    return r;
}
}  // namespace pellucid
