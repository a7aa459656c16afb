// Materials: each model's BxDF from its Params (make_bxdf), the constants derived at load
// (prepare_material) and to_string.
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
std::string format_tex(const Tex<float>& t) {
    return t.textured() ? "texture " + std::to_string(t.texture) : format_float(t.value);
}
std::string format_tex(const Tex<Spectrum>& t) {
    return t.textured() ? "texture " + std::to_string(t.texture) : format_spectrum(t.value);
}

std::string to_string(MicrofacetType t) { return t == MicrofacetType::GGX ? "ggx" : "beckmann"; }

std::string MicrofacetParams::to_string() const {
    std::string s = "distribution=" + pellucid::to_string(distribution);
    const bool iso = alpha_u.texture == alpha_v.texture && alpha_u.value == alpha_v.value;
    s += iso ? ", alpha=" + format_tex(alpha_u) : ", alpha_u=" + format_tex(alpha_u) + ", alpha_v=" + format_tex(alpha_v);
    return shadowing == SmithShadowing::Separable ? s + ", shadowing=separable" : s;
}
std::string ConductorIORParams::to_string() const {
    std::string s = preset < 0 ? "eta=" + format_tex(eta) + ", k=" + format_tex(k)
                               : "material=" + conductor_names().at(size_t(preset));
    return s + ", fresnel=" + (schlick ? "schlick" : "exact");
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

namespace {
ConductorFresnel make_fresnel(const ConductorIORParams& p, const TexEval& tex) {
    const Spectrum eta = tex(p.eta), k = tex(p.k);
    return p.schlick ? ConductorFresnel::schlick_from(eta, k) : ConductorFresnel{eta, k};
}
template <class D>
D make_distribution(const MicrofacetParams& m, const TexEval& tex) {
    return D(tex(m.alpha_u), tex(m.alpha_v), m.shadowing);
}
// `distribution` picks the template argument; Kulla–Conty is GGX only (the builder rejects
// beckmann + multiple_scattering).
BxDF make_rough_dielectric(const MicrofacetParams& m, const DielectricParams& d, bool multiple_scattering,
                           const DielectricFresnelAverage* fresnel_avg, const TexEval& tex) {
    const float eta = relative_eta(d, tex);
    const Spectrum r = tex(d.specular_reflectance), t = tex(d.specular_transmittance);
    if (m.distribution == MicrofacetType::Beckmann)
        return RoughDielectric<Beckmann>(make_distribution<Beckmann>(m, tex), eta, r, t);
    return RoughDielectric<GGX>(make_distribution<GGX>(m, tex), eta, r, t, multiple_scattering, fresnel_avg);
}
// RoughPlastic takes p.coat_table when it was built for the hit's α and η, and otherwise builds or
// finds the table (bxdf/plastic.h).
template <class D>
RoughPlastic<D> make_rough_plastic(const RoughPlasticParams& p, const TexEval& tex) {
    const PlasticParams& q = p.plastic;
    return RoughPlastic<D>(make_distribution<D>(p.microfacet, tex), relative_eta(q, tex), tex(q.diffuse_reflectance),
                           tex(q.specular_reflectance), q.variant, p.coat_transmittance, p.coat_table, &q.fresnel_avg);
}
std::string bool_string(bool b) { return b ? "true" : "false"; }
std::string dielectric_string(const DielectricParams& d) {
    return "int_ior=" + format_tex(d.int_ior) + ", ext_ior=" + format_tex(d.ext_ior) +
           ", specular_reflectance=" + format_tex(d.specular_reflectance) +
           ", specular_transmittance=" + format_tex(d.specular_transmittance);
}
std::string plastic_string(const PlasticParams& p) {
    return "diffuse_reflectance=" + format_tex(p.diffuse_reflectance) +
           ", specular_reflectance=" + format_tex(p.specular_reflectance) + ", int_ior=" + format_tex(p.int_ior) +
           ", ext_ior=" + format_tex(p.ext_ior) + ", variant=" + pellucid::to_string(p.variant);
}
}  // namespace

// ---- make_bxdf: one per model ----

BxDF make_bxdf(const LambertianParams& p, const TexEval& tex) { return Lambertian(tex(p.reflectance)); }

BxDF make_bxdf(const OrenNayarParams& p, const TexEval& tex) {
    const bool classic = p.variant == OrenNayarVariant::Classic;
    const float rough = classic ? radians(tex(p.sigma_degrees)) : tex(p.roughness);
    return OrenNayar(tex(p.reflectance), rough, p.variant);
}

BxDF make_bxdf(const ConductorParams& p, const TexEval& tex) {
    return SmoothConductor<ConductorFresnel>(make_fresnel(p.ior, tex), tex(p.specular_reflectance));
}

BxDF make_bxdf(const RoughConductorParams& p, const TexEval& tex) {
    const ConductorFresnel fr = make_fresnel(p.ior, tex);
    const Spectrum ks = tex(p.specular_reflectance);
    if (p.microfacet.distribution == MicrofacetType::Beckmann)
        return RoughConductorBeckmann(make_distribution<Beckmann>(p.microfacet, tex), fr, ks);
    return RoughConductor(make_distribution<GGX>(p.microfacet, tex), fr, ks, p.multiple_scattering, &p.fresnel_avg);
}

BxDF make_bxdf(const DielectricParams& p, const TexEval& tex) {
    return SmoothDielectric(relative_eta(p, tex), tex(p.specular_reflectance), tex(p.specular_transmittance));
}
BxDF make_bxdf(const ThinDielectricParams& p, const TexEval& tex) {
    return ThinDielectric(relative_eta(p, tex), tex(p.specular_reflectance), tex(p.specular_transmittance));
}
BxDF make_bxdf(const RoughDielectricParams& p, const TexEval& tex) {
    return make_rough_dielectric(p.microfacet, p.dielectric, p.multiple_scattering, &p.fresnel_avg, tex);
}

BxDF make_bxdf(const PlasticParams& p, const TexEval& tex) {
    return SmoothPlastic(relative_eta(p, tex), tex(p.diffuse_reflectance), tex(p.specular_reflectance), p.variant,
                         &p.fresnel_avg);
}
BxDF make_bxdf(const RoughPlasticParams& p, const TexEval& tex) {
    if (p.microfacet.distribution == MicrofacetType::Beckmann) return make_rough_plastic<Beckmann>(p, tex);
    return make_rough_plastic<GGX>(p, tex);
}

BxDF make_bxdf(const PrincipledParams& p, const TexEval& tex) {
    PrincipledInputs in;
    in.base_color = tex(p.base_color);
    in.metallic = tex(p.metallic);
    in.roughness = tex(p.roughness);
    in.specular = tex(p.specular);
    in.specular_tint = tex(p.specular_tint);
    in.sheen = tex(p.sheen);
    in.sheen_tint = tex(p.sheen_tint);
    in.clearcoat = tex(p.clearcoat);
    in.clearcoat_gloss = tex(p.clearcoat_gloss);
    in.anisotropic = tex(p.anisotropic);
    in.specular_transmission = tex(p.specular_transmission);
    in.flatness = tex(p.flatness);
    in.diffuse_transmission = tex(p.diffuse_transmission);
    in.eta = tex(p.eta);
    in.variant = p.variant;
    in.thin = p.thin;
    return p.variant == PrincipledVariant::Burley2015 ? BxDF(PrincipledBSDF(in)) : BxDF(Principled(in));
}

// The boundary has no Kulla–Conty term, hence no Fresnel average.
BxDF make_bxdf(const SubsurfaceParams& p, const TexEval& tex) {
    if (!p.rough) return SmoothDielectric(relative_eta(p.boundary, tex), Spectrum(1.f), Spectrum(1.f));
    return make_rough_dielectric(p.microfacet, p.boundary, false, nullptr, tex);
}

// ---- constants derived at load ----

namespace {
template <class P>
void prepare(P&) {}
void prepare(RoughConductorParams& p) {
    if (p.multiple_scattering && p.microfacet.distribution == MicrofacetType::GGX)
        p.fresnel_avg = ConductorFresnelAverage::of(make_fresnel(p.ior, TexEval{}));
}
void prepare(RoughDielectricParams& p) {
    if (p.multiple_scattering && p.microfacet.distribution == MicrofacetType::GGX)
        p.fresnel_avg = RoughDielectric<GGX>::multiscatter_fresnel_average(relative_eta(p.dielectric, TexEval{}));
}
// The sum variant has no R̄ (bxdf/plastic.h), so no average to compute.
void prepare(PlasticParams& p) {
    if (p.variant != PlasticVariant::Sum) p.fresnel_avg = DielectricFresnelAverage::of(relative_eta(p, TexEval{}));
}
// The coat table is resolved once, by building the BxDF of the constants; every per-hit BxDF of a
// textured material reuses it. A rough coat's R̄ comes from its table, not from the Fresnel average.
void prepare(RoughPlasticParams& p) {
    prepare(p.plastic);
    p.coat_table = nullptr;
    p.coat_table = p.microfacet.distribution == MicrofacetType::Beckmann
                       ? make_rough_plastic<Beckmann>(p, TexEval{}).base().coat_table()
                       : make_rough_plastic<GGX>(p, TexEval{}).base().coat_table();
}
}  // namespace

void prepare_material(Material& m) {
    std::visit([](auto& p) { prepare(p); }, m);
}

// ---- to_string ----

namespace {
std::string describe(const LambertianParams& p) { return "lambertian[reflectance=" + format_tex(p.reflectance) + "]"; }
std::string describe(const OrenNayarParams& p) {
    const bool classic = p.variant == OrenNayarVariant::Classic;
    return "oren_nayar[reflectance=" + format_tex(p.reflectance) +
           (classic ? ", variant=classic, sigma=" + format_tex(p.sigma_degrees) + " deg"
                    : ", variant=eon, roughness=" + format_tex(p.roughness)) + "]";
}
std::string describe(const ConductorParams& p) {
    return "conductor[" + p.ior.to_string() + ", specular_reflectance=" + format_tex(p.specular_reflectance) + "]";
}
std::string describe(const RoughConductorParams& p) {
    return "rough_conductor[" + p.microfacet.to_string() + ", " + p.ior.to_string() +
           ", specular_reflectance=" + format_tex(p.specular_reflectance) +
           ", multiple_scattering=" + bool_string(p.multiple_scattering) + "]";
}
std::string describe(const DielectricParams& p) { return "dielectric[" + dielectric_string(p) + "]"; }
std::string describe(const ThinDielectricParams& p) { return "thin_dielectric[" + dielectric_string(p) + "]"; }
std::string describe(const RoughDielectricParams& p) {
    return "rough_dielectric[" + p.microfacet.to_string() + ", " + dielectric_string(p.dielectric) +
           ", multiple_scattering=" + bool_string(p.multiple_scattering) + "]";
}
std::string describe(const PlasticParams& p) { return "plastic[" + plastic_string(p) + "]"; }
std::string describe(const RoughPlasticParams& p) {
    return "rough_plastic[" + p.microfacet.to_string() + ", " + plastic_string(p.plastic) +
           ", coat_transmittance=" + pellucid::to_string(p.coat_transmittance) + "]";
}
std::string describe(const PrincipledParams& p) {
    std::string s = "principled[base_color=" + format_tex(p.base_color) + ", metallic=" + format_tex(p.metallic) +
                    ", roughness=" + format_tex(p.roughness) + ", specular=" + format_tex(p.specular) +
                    ", specular_tint=" + format_tex(p.specular_tint) + ", sheen=" + format_tex(p.sheen) +
                    ", sheen_tint=" + format_tex(p.sheen_tint) + ", clearcoat=" + format_tex(p.clearcoat) +
                    ", clearcoat_gloss=" + format_tex(p.clearcoat_gloss) + ", anisotropic=" + format_tex(p.anisotropic);
    if (p.variant == PrincipledVariant::Burley2015) {
        const bool from_specular = !p.eta.textured() && !(p.eta.value > 0.f);
        s += ", variant=2015, specular_transmission=" + format_tex(p.specular_transmission) +
             ", flatness=" + format_tex(p.flatness) + ", eta=" + (from_specular ? "from specular" : format_tex(p.eta));
        if (p.thin) s += ", thin, diffuse_transmission=" + format_tex(p.diffuse_transmission);
    }
    return s + "]";
}
std::string describe(const SubsurfaceParams& p) {
    std::string s = "subsurface[model=" + pellucid::to_string(p.model) + ", int_ior=" + format_tex(p.boundary.int_ior) +
                    ", ext_ior=" + format_tex(p.boundary.ext_ior);
    s += p.from_albedo ? ", albedo=" + format_tex(p.albedo) + ", mfp=" + format_tex(p.mfp)
                       : ", sigma_a=" + format_tex(p.sigma_a) + ", sigma_s=" + format_tex(p.sigma_s) +
                             ", scale=" + format_float(p.scale);
    s += ", g=" + format_tex(p.g);
    return (p.rough ? s + ", " + p.microfacet.to_string() : s) + "]";
}
}  // namespace

std::string to_string(const Material& m) {
    return std::visit([](const auto& p) { return describe(p); }, m);
}
}  // namespace pellucid
