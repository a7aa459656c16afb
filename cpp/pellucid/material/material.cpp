// Materials: their BxDFs built from Params (with the constants precomputed at construction) and to_string.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/material/material.h"

#include <sstream>

#include "pellucid/bxdf/ior.h"
#include "pellucid/math/constants.h"

namespace pellucid {

std::string format_float(float v) {
    std::ostringstream os;
    os << v;
    return os.str();
}
std::string format_spectrum(const Spectrum& s) {
    if (s.r == s.g && s.g == s.b) return format_float(s.r);
    return "[" + format_float(s.r) + ", " + format_float(s.g) + ", " + format_float(s.b) + "]";
}
std::string to_string(MicrofacetType t) { return t == MicrofacetType::GGX ? "ggx" : "beckmann"; }

std::string MicrofacetParams::to_string() const {
    std::string s = "distribution=" + pellucid::to_string(distribution);
    s += alpha_u == alpha_v ? ", alpha=" + format_float(alpha_u)
                            : ", alpha_u=" + format_float(alpha_u) + ", alpha_v=" + format_float(alpha_v);
    return shadowing == SmithShadowing::Separable ? s + ", shadowing=separable" : s;
}
std::string ConductorIORParams::to_string() const {
    std::string s = preset < 0 ? "eta=" + format_spectrum(eta) + ", k=" + format_spectrum(k)
                               : "material=" + conductor_names().at(size_t(preset));
    return s + ", fresnel=" + (schlick ? "schlick" : "exact");
}
std::string DielectricParams::to_string() const {
    return "int_ior=" + format_float(int_ior) + ", ext_ior=" + format_float(ext_ior) +
           ", specular_reflectance=" + format_spectrum(specular_reflectance) +
           ", specular_transmittance=" + format_spectrum(specular_transmittance);
}
std::string PlasticParams::to_string() const {
    return "diffuse_reflectance=" + format_spectrum(diffuse_reflectance) +
           ", specular_reflectance=" + format_spectrum(specular_reflectance) + ", int_ior=" + format_float(int_ior) +
           ", ext_ior=" + format_float(ext_ior) + ", variant=" + pellucid::to_string(variant);
}

namespace {
ConductorFresnel make_fresnel(const ConductorIORParams& p) {
    return p.schlick ? ConductorFresnel::schlick_from(p.eta, p.k) : ConductorFresnel{p.eta, p.k};
}
BxDF make_oren_nayar(const OrenNayarParams& p) {
    float rough = p.variant == OrenNayarVariant::Classic ? radians(p.sigma_degrees) : p.roughness;
    return OrenNayar(p.reflectance, rough, p.variant);
}
template <class D>
D make_distribution(const MicrofacetParams& m) {
    return D(m.alpha_u, m.alpha_v, m.shadowing);
}
BxDF make_rough_conductor(const RoughConductorParams& p, const ConductorFresnelAverage* fresnel_avg) {
    ConductorFresnel fr = make_fresnel(p.ior);
    if (p.microfacet.distribution == MicrofacetType::Beckmann)
        return RoughConductorBeckmann(make_distribution<Beckmann>(p.microfacet), fr, p.specular_reflectance);
    return RoughConductor(make_distribution<GGX>(p.microfacet), fr, p.specular_reflectance, p.multiple_scattering,
                          fresnel_avg);
}
// `distribution` picks the template argument (as make_rough_conductor); Kulla–Conty is GGX only
// (the builder rejects beckmann + multiple_scattering).
BxDF make_rough_dielectric(const RoughDielectricParams& p, const DielectricFresnelAverage* fresnel_avg) {
    const DielectricParams& d = p.dielectric;
    const MicrofacetParams& m = p.microfacet;
    if (m.distribution == MicrofacetType::Beckmann)
        return RoughDielectric<Beckmann>(make_distribution<Beckmann>(m), d.eta(), d.specular_reflectance,
                                         d.specular_transmittance);
    return RoughDielectric<GGX>(make_distribution<GGX>(m), d.eta(), d.specular_reflectance, d.specular_transmittance,
                                p.multiple_scattering, fresnel_avg);
}
// RoughPlastic takes p.coat_table when it was built for p's α and η, and otherwise builds or finds
// the table (bxdf/plastic.h).
template <class D>
RoughPlastic<D> make_rough_plastic(const RoughPlasticParams& p, const DielectricFresnelAverage* fresnel_avg) {
    const PlasticParams& q = p.plastic;
    return RoughPlastic<D>(make_distribution<D>(p.microfacet), q.int_ior / q.ext_ior, q.diffuse_reflectance,
                           q.specular_reflectance, q.variant, p.coat_transmittance, p.coat_table, fresnel_avg);
}
}  // namespace

BxDF OrenNayarMaterial::bxdf_for(const OrenNayarParams& p) const { return make_oren_nayar(p); }
std::string OrenNayarMaterial::to_string() const {
    bool classic = m_p.variant == OrenNayarVariant::Classic;
    return "OrenNayarMaterial[reflectance=" + format_spectrum(m_p.reflectance) +
           (classic ? ", variant=classic, sigma=" + format_float(m_p.sigma_degrees) + " deg"
                    : ", variant=eon, roughness=" + format_float(m_p.roughness)) + "]";
}

BxDF ConductorMaterial::bxdf_for(const ConductorParams& p) const {
    return SmoothConductor<ConductorFresnel>(make_fresnel(p.ior), p.specular_reflectance);
}
std::string ConductorMaterial::to_string() const {
    return "ConductorMaterial[" + m_p.ior.to_string() +
           ", specular_reflectance=" + format_spectrum(m_p.specular_reflectance) + "]";
}

RoughConductorMaterial::RoughConductorMaterial(const RoughConductorParams& p) : m_p(p) {
    if (p.multiple_scattering && p.microfacet.distribution == MicrofacetType::GGX)
        m_fresnel_avg = ConductorFresnelAverage::of(make_fresnel(p.ior));
}
BxDF RoughConductorMaterial::bxdf_for(const RoughConductorParams& p) const {
    return make_rough_conductor(p, &m_fresnel_avg);
}
std::string RoughConductorMaterial::to_string() const {
    return "RoughConductorMaterial[" + m_p.microfacet.to_string() + ", " + m_p.ior.to_string() +
           ", specular_reflectance=" + format_spectrum(m_p.specular_reflectance) +
           ", multiple_scattering=" + (m_p.multiple_scattering ? "true" : "false") + "]";
}

RoughDielectricMaterial::RoughDielectricMaterial(const RoughDielectricParams& p) : m_p(p) {
    if (p.multiple_scattering && p.microfacet.distribution == MicrofacetType::GGX)
        m_fresnel_avg = RoughDielectric<GGX>::multiscatter_fresnel_average(p.dielectric.eta());
}
BxDF RoughDielectricMaterial::bxdf_for(const RoughDielectricParams& p) const {
    return make_rough_dielectric(p, &m_fresnel_avg);
}
std::string RoughDielectricMaterial::to_string() const {
    return "RoughDielectricMaterial[" + m_p.microfacet.to_string() + ", " + m_p.dielectric.to_string() +
           ", multiple_scattering=" + (m_p.multiple_scattering ? "true" : "false") + "]";
}

// The sum variant has no R̄ (bxdf/plastic.h), so no average to compute.
PlasticMaterial::PlasticMaterial(const PlasticParams& p) : m_p(p) {
    if (p.variant != PlasticVariant::Sum) m_fresnel_avg = DielectricFresnelAverage::of(p.int_ior / p.ext_ior);
}
BxDF PlasticMaterial::bxdf_for(const PlasticParams& p) const {
    return SmoothPlastic(p.int_ior / p.ext_ior, p.diffuse_reflectance, p.specular_reflectance, p.variant,
                         &m_fresnel_avg);
}
std::string PlasticMaterial::to_string() const { return "PlasticMaterial[" + m_p.to_string() + "]"; }

// The coat table is resolved here, once, by building the BxDF: a textured material's per-hit BxDF
// (material/textured.h) copies these Params and so reuses it. A rough coat's R̄ comes from its
// table, not from the Fresnel average.
RoughPlasticMaterial::RoughPlasticMaterial(const RoughPlasticParams& p) : m_p(p) {
    const PlasticParams& q = p.plastic;
    if (q.variant != PlasticVariant::Sum) m_fresnel_avg = DielectricFresnelAverage::of(q.int_ior / q.ext_ior);
    m_p.coat_table = p.microfacet.distribution == MicrofacetType::Beckmann
                         ? make_rough_plastic<Beckmann>(m_p, &m_fresnel_avg).base().coat_table()
                         : make_rough_plastic<GGX>(m_p, &m_fresnel_avg).base().coat_table();
}
BxDF RoughPlasticMaterial::bxdf_for(const RoughPlasticParams& p) const {
    if (p.microfacet.distribution == MicrofacetType::Beckmann) return make_rough_plastic<Beckmann>(p, &m_fresnel_avg);
    return make_rough_plastic<GGX>(p, &m_fresnel_avg);
}
std::string RoughPlasticMaterial::to_string() const {
    return "RoughPlasticMaterial[" + m_p.microfacet.to_string() + ", " + m_p.plastic.to_string() +
           ", coat_transmittance=" + pellucid::to_string(m_p.coat_transmittance) + "]";
}

std::string to_string(SubsurfaceModel m) {
    switch (m) {
        case SubsurfaceModel::Dipole: return "dipole";
        case SubsurfaceModel::BetterDipole: return "better_dipole";
        case SubsurfaceModel::RandomWalk: return "random_walk";
        case SubsurfaceModel::Auto: return "auto";
        case SubsurfaceModel::Coated: return "coated";
    }
    return "?";
}
std::string SubsurfaceParams::to_string() const {
    std::string s = "model=" + pellucid::to_string(model) + ", int_ior=" + format_float(boundary.int_ior) +
                    ", ext_ior=" + format_float(boundary.ext_ior);
    s += from_albedo ? ", albedo=" + format_spectrum(albedo) + ", mfp=" + format_spectrum(mfp)
                     : ", sigma_a=" + format_spectrum(sigma_a) + ", sigma_s=" + format_spectrum(sigma_s) +
                           ", scale=" + format_float(scale);
    s += ", g=" + format_float(g);
    return rough ? s + ", " + microfacet.to_string() : s;
}
// The boundary has no Kulla–Conty term, hence no Fresnel average.
BxDF SubsurfaceMaterial::bxdf_for(const SubsurfaceParams& p) const {
    if (!p.rough) return SmoothDielectric(p.eta(), Spectrum(1.f), Spectrum(1.f));
    RoughDielectricParams r;
    r.microfacet = p.microfacet;
    r.dielectric = p.boundary;
    return make_rough_dielectric(r, nullptr);
}

std::string PrincipledMaterial::to_string() const {
    const PrincipledParams& p = m_p;
    return "PrincipledMaterial[base_color=" + format_spectrum(p.base_color) + ", metallic=" + format_float(p.metallic) +
           ", roughness=" + format_float(p.roughness) + ", specular=" + format_float(p.specular) +
           ", specular_tint=" + format_float(p.specular_tint) + ", sheen=" + format_float(p.sheen) +
           ", sheen_tint=" + format_float(p.sheen_tint) + ", clearcoat=" + format_float(p.clearcoat) +
           ", clearcoat_gloss=" + format_float(p.clearcoat_gloss) + ", anisotropic=" + format_float(p.anisotropic) +
           (p.variant == PrincipledVariant::Burley2015
                ? ", variant=2015, specular_transmission=" + format_float(p.specular_transmission) +
                      ", flatness=" + format_float(p.flatness) + ", eta=" +
                      (p.eta > 0.f ? format_float(p.eta) : std::string("from specular")) +
                      (p.thin ? ", thin, diffuse_transmission=" + format_float(p.diffuse_transmission) : "")
                : std::string()) +
           "]";
}
}  // namespace pellucid
