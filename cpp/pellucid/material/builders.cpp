// Material builders: parameter parsing, validation (errors name the key path and value) and the
// documented clamps. Parameter tables: the material headers and docs/scene-format.md.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/material/builders.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>

#include "pellucid/bxdf/ior.h"
#include "pellucid/scene/properties.h"
#include "pellucid/scene/registry.h"
#include "pellucid/util/error.h"
#include "pellucid/util/log.h"

namespace pellucid {
namespace {

void warn_clamped(const Properties& p, const std::string& key, float v, float to) {
    log_warning(format_error(p.source(), p.key_path(key),
                             "value " + format_float(v) + " clamped to " + format_float(to)));
}

/// A float ≥ 0 (error below 0), clamped to `hi` with a warning.
float read_nonneg(Properties& p, const std::string& key, float def, float hi) {
    float v = p.get_float(key, def);
    if (v < 0.f) p.fail(key, "value " + format_float(v) + " must be >= 0");
    if (v > hi) {
        warn_clamped(p, key, v, hi);
        v = hi;
    }
    return v;
}

Spectrum read_colour(Properties& p, const std::string& key, const Spectrum& def) {
    Spectrum s = p.get_spectrum(key, def);
    p.check_spectrum_range(key, s, 0.f, 1.f);
    return s;
}

std::string read_choice(Properties& p, const std::string& key, const std::string& def, const char* what,
                        std::initializer_list<const char*> known) {
    std::string v = p.get_string(key, def);
    std::string list;
    for (const char* k : known) {
        if (v == k) return v;
        list += (list.empty() ? "" : ", ") + std::string(k);
    }
    p.fail(key, std::string("unknown ") + what + " '" + v + "' (known: " + list + ")");
}

/// An IOR: a number > 0 or a name of bxdf/ior.h.
float read_ior(Properties& p, const std::string& key, const char* def_name) {
    const Node* n = p.get_node(key);
    if (!n) return dielectric_ior(def_name);
    if (n->is_string()) {
        std::vector<std::string> names = dielectric_names();
        if (std::find(names.begin(), names.end(), n->as_string()) == names.end())
            p.fail(key, "unknown IOR name '" + n->as_string() + "' (known: " + join_names(names) + ")");
        return dielectric_ior(n->as_string());
    }
    if (!n->is_number()) p.fail(key, std::string("expected a number or an IOR name, got a ") + n->kind_name());
    float v = float(n->as_number());
    if (!(v > 0.f) || !std::isfinite(v)) p.fail(key, "value " + format_float(v) + " must be > 0");
    return v;
}

/// distribution + one of alpha | alpha_u/alpha_v | roughness (α = r²).
MicrofacetParams read_microfacet(Properties& p) {
    MicrofacetParams m;
    std::string d = read_choice(p, "distribution", "ggx", "distribution", {"ggx", "beckmann"});
    m.distribution = d == "ggx" ? MicrofacetType::GGX : MicrofacetType::Beckmann;
    bool has_alpha = p.has("alpha"), has_uv = p.has("alpha_u") || p.has("alpha_v"), has_r = p.has("roughness");
    if (int(has_alpha) + int(has_uv) + int(has_r) > 1)
        p.fail(has_r ? "roughness" : "alpha_u", "give only one of alpha, alpha_u/alpha_v, roughness");
    if (has_r) {
        float r = read_nonneg(p, "roughness", 0.f, 1.f);
        m.alpha_u = m.alpha_v = r * r;  // Burley 2012 §5.4 (microfacet.h alpha_from_roughness)
    } else if (has_uv) {
        if (!p.has("alpha_u")) p.fail("", "missing required key 'alpha_u' (alpha_v given)");
        m.alpha_u = read_nonneg(p, "alpha_u", 0.1f, 1.f);
        m.alpha_v = read_nonneg(p, "alpha_v", m.alpha_u, 1.f);
    } else {
        m.alpha_u = m.alpha_v = read_nonneg(p, "alpha", 0.1f, 1.f);
    }
    return m;
}

ConductorIORParams read_conductor_ior(Properties& p) {
    ConductorIORParams c;
    std::string fresnel = read_choice(p, "fresnel", "exact", "fresnel mode", {"exact", "schlick"});
    c.schlick = fresnel == "schlick";
    bool has_ek = p.has("eta") || p.has("k");
    if (has_ek) {
        if (p.has("material")) p.fail("material", "give either material or eta/k, not both");
        if (!p.has("eta")) p.fail("", "missing required key 'eta' (k given)");
        c.eta = p.get_spectrum("eta", Spectrum(1.f));
        c.k = p.get_spectrum("k", Spectrum(0.f));
        for (int i = 0; i < 3; ++i) {
            if (!(c.eta[i] > 0.f)) p.fail("eta", "value " + format_float(c.eta[i]) + " must be > 0");
            if (c.k[i] < 0.f) p.fail("k", "value " + format_float(c.k[i]) + " must be >= 0");
        }
        return c;
    }
    std::string name = p.get_string("material", "none");
    std::vector<std::string> names = conductor_names();
    auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end()) p.fail("material", "unknown metal '" + name + "' (known: " + join_names(names) + ")");
    c.preset = int(it - names.begin());
    ConductorIOR ior = conductor_ior(name);
    c.eta = ior.eta;
    c.k = ior.k;
    return c;
}

DielectricParams read_dielectric(Properties& p) {
    DielectricParams d;
    d.int_ior = read_ior(p, "int_ior", "bk7");
    d.ext_ior = read_ior(p, "ext_ior", "air");
    d.specular_reflectance = read_colour(p, "specular_reflectance", Spectrum(1.f));
    d.specular_transmittance = read_colour(p, "specular_transmittance", Spectrum(1.f));
    return d;
}

PlasticParams read_plastic(Properties& p) {
    PlasticParams q;
    q.diffuse_reflectance = read_colour(p, "diffuse_reflectance", Spectrum(0.5f));
    q.specular_reflectance = read_colour(p, "specular_reflectance", Spectrum(1.f));
    q.int_ior = read_ior(p, "int_ior", "polypropylene");
    q.ext_ior = read_ior(p, "ext_ior", "air");
    std::string v = read_choice(p, "variant", "coupled", "variant", {"coupled", "sum"});
    q.variant = v == "coupled" ? PlasticVariant::Coupled : PlasticVariant::Sum;
    return q;
}
}  // namespace

Material build_lambertian(Properties& p, const BuildContext&) {
    DiffuseMaterial m;
    m.reflectance = read_colour(p, "reflectance", Spectrum(0.5f));
    return m;
}

Material build_oren_nayar(Properties& p, const BuildContext&) {
    OrenNayarParams q;
    q.reflectance = read_colour(p, "reflectance", Spectrum(0.5f));
    std::string v = read_choice(p, "variant", "eon", "variant", {"eon", "classic"});
    q.variant = v == "eon" ? OrenNayarVariant::EON : OrenNayarVariant::Classic;
    const char* other = q.variant == OrenNayarVariant::EON ? "sigma" : "roughness";
    if (p.has(other))
        p.fail(other, std::string("not used by variant '") + v + "' (classic takes sigma in degrees, eon roughness)");
    if (q.variant == OrenNayarVariant::Classic) q.sigma_degrees = read_nonneg(p, "sigma", 20.f, 90.f);
    else q.roughness = read_nonneg(p, "roughness", 0.5f, 1.f);
    return OrenNayarMaterial(q);
}

Material build_conductor(Properties& p, const BuildContext&) {
    ConductorParams q;
    q.ior = read_conductor_ior(p);
    q.specular_reflectance = read_colour(p, "specular_reflectance", Spectrum(1.f));
    return ConductorMaterial(q);
}

Material build_rough_conductor(Properties& p, const BuildContext&) {
    RoughConductorParams q;
    q.microfacet = read_microfacet(p);
    q.ior = read_conductor_ior(p);
    q.specular_reflectance = read_colour(p, "specular_reflectance", Spectrum(1.f));
    q.multiple_scattering = p.get_bool("multiple_scattering", false);
    if (q.multiple_scattering && q.microfacet.distribution != MicrofacetType::GGX)
        p.fail("multiple_scattering", "requires distribution 'ggx' (the Kulla-Conty table is GGX only)");
    return RoughConductorMaterial(q);
}

Material build_dielectric(Properties& p, const BuildContext&) { return DielectricMaterial(read_dielectric(p)); }
Material build_thin_dielectric(Properties& p, const BuildContext&) {
    return ThinDielectricMaterial(read_dielectric(p));
}
Material build_rough_dielectric(Properties& p, const BuildContext&) {
    RoughDielectricParams q;
    q.microfacet = read_microfacet(p);
    q.dielectric = read_dielectric(p);
    q.multiple_scattering = p.get_bool("multiple_scattering", false);
    if (q.multiple_scattering && q.microfacet.distribution != MicrofacetType::GGX)
        p.fail("multiple_scattering", "requires distribution 'ggx' (the Kulla-Conty tables are GGX only)");
    return RoughDielectricMaterial(q);
}

Material build_plastic(Properties& p, const BuildContext&) { return PlasticMaterial(read_plastic(p)); }
Material build_rough_plastic(Properties& p, const BuildContext&) {
    RoughPlasticParams q;
    q.microfacet = read_microfacet(p);
    q.plastic = read_plastic(p);
    return RoughPlasticMaterial(q);
}

Material build_principled(Properties& p, const BuildContext&) {
    PrincipledParams q;
    q.base_color = read_colour(p, "base_color", q.base_color);
    auto unit = [&](const char* key, float& v) { v = p.check_range(key, p.get_float(key, v), 0.f, 1.f); };
    unit("metallic", q.metallic);
    unit("roughness", q.roughness);
    unit("specular", q.specular);
    unit("specular_tint", q.specular_tint);
    unit("sheen", q.sheen);
    unit("sheen_tint", q.sheen_tint);
    unit("clearcoat", q.clearcoat);
    unit("clearcoat_gloss", q.clearcoat_gloss);
    unit("anisotropic", q.anisotropic);
    return PrincipledMaterial(q);
}

Material build_material(const Node& node, const std::string& source, const std::string& path) {
    return build_material(node, BuildContext{source, "."}, path);
}

Material build_material(const Node& node, const BuildContext& ctx, const std::string& path) {
    Properties p(node, ctx.source, path);
    std::string type = p.type();
    auto it = material_registry().find(type);
    if (it == material_registry().end()) {
        std::vector<std::string> names;
        for (const auto& [k, v] : material_registry()) names.push_back(k);
        p.fail("type", "unknown material type '" + type + "' (known: " + join_names(names) + ")");
    }
    Material m = it->second(p, ctx);
    p.check_unqueried();
    return m;
}
}  // namespace pellucid
