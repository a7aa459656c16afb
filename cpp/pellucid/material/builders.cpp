// Material builders: parameter parsing, validation (errors name the key path and value) and the
// documented clamps. Parameter tables: the material headers and docs/scene-format.md.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/material/builders.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <type_traits>

#include "pellucid/bxdf/ior.h"
#include "pellucid/scene/properties.h"
#include "pellucid/scene/registry.h"
#include "pellucid/util/error.h"
#include "pellucid/util/log.h"
#include "pellucid/material/textured.h"
#include "pellucid/scene/texture_builder.h"

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

/// Reads a material's parameters into its Params fields; a parameter given as a texture (an object
/// with a "type", or the name of one of the scene's textures) binds its Tex field to that texture
/// (material/tex.h), which keeps its default as the constant value, and lists the texture in the
/// material's MaterialTextures.
class Binder {
public:
    Binder(Properties& p, const BuildContext& ctx) : m_p(p), m_ctx(ctx) {}
    Properties& props() { return m_p; }

    /// A colour with channels in [lo, hi] (error outside).
    void colour(const std::string& key, Tex<Spectrum>& field, float lo = 0.f, float hi = 1.f) {
        if (bind(key, field, TexMap::Identity, lo, hi, true, false)) return;
        field.value = m_p.get_spectrum(key, field.value);
        m_p.check_spectrum_range(key, field.value, lo, hi);
    }
    /// A float ≥ 0 (error below 0), clamped to `hi` with a warning; `map` maps the value (r → r²).
    bool nonneg(const std::string& key, Tex<float>& field, float hi, TexMap map = TexMap::Identity) {
        if (bind(key, field, map, 0.f, hi, true)) return true;
        float v = read_nonneg(m_p, key, field.value, hi);
        field.value = map == TexMap::Square ? v * v : v;
        return false;
    }
    /// A float in [lo, hi] (error outside).
    void range(const std::string& key, Tex<float>& field, float lo, float hi) {
        if (bind(key, field, TexMap::Identity, lo, hi, true, false)) return;
        field.value = m_p.check_range(key, m_p.get_float(key, field.value), lo, hi);
    }
    /// Bind `key` to `field` if its value is a texture; true if it was. The texture's values must lie
    /// in [lo, hi] (TextureBuilder::check_range); above hi they are clamped when `clamp_high`.
    template <class T>
    bool bind(const std::string& key, Tex<T>& field, TexMap map, float lo, float hi, bool names_ok,
              bool clamp_high = true) {
        if (!m_p.has(key)) return false;
        const Node* n = m_p.get_node(key);
        bool is_tex = n->is_object() || (names_ok && m_ctx.textures && m_ctx.textures->is_texture(*n, true));
        if (!is_tex) return false;
        if (!m_ctx.textures || !m_ctx.material_textures)
            m_p.fail(key, "a texture is only allowed in a scene (this interface takes constant parameters)");
        MaterialTextures& mt = *m_ctx.material_textures;
        if (mt.count >= MaterialTextures::kMaxTextured)
            m_p.fail(key, "too many textured parameters (at most " + std::to_string(MaterialTextures::kMaxTextured) + ")");
        uint32_t id = m_ctx.textures->texture(*n, m_p.key_path(key));
        m_ctx.textures->check_range(id, m_p.key_path(key), lo, hi, std::is_same_v<T, float>, clamp_high);
        field.texture = int32_t(id);
        field.map = map;
        field.lo = lo;
        field.hi = hi;
        mt.bound[mt.count++] = id;
        return true;
    }

private:
    Properties& m_p;
    const BuildContext& m_ctx;
};

/// An IOR: a number > 0, a name of bxdf/ior.h, or a texture (values clamped to [1e-3, 10]).
void read_ior(Binder& b, const std::string& key, const char* def_name, Tex<float>& field) {
    Properties& p = b.props();
    const Node* n = p.has(key) ? p.get_node(key) : nullptr;
    if (!n) {
        field = dielectric_ior(def_name);
        return;
    }
    if (n->is_string()) {
        std::vector<std::string> names = dielectric_names();
        if (std::find(names.begin(), names.end(), n->as_string()) != names.end()) {
            field = dielectric_ior(n->as_string());
            return;
        }
        if (b.bind(key, field, TexMap::Identity, 1e-3f, 10.f, true)) return;
        p.fail(key, "unknown IOR name '" + n->as_string() + "' (known: " + join_names(names) + ")");
    }
    if (b.bind(key, field, TexMap::Identity, 1e-3f, 10.f, false)) return;
    if (!n->is_number()) p.fail(key, std::string("expected a number or an IOR name, got a ") + n->kind_name());
    float v = float(n->as_number());
    if (!(v > 0.f) || !std::isfinite(v)) p.fail(key, "value " + format_float(v) + " must be > 0");
    field = v;
}

/// distribution + shadowing + one of alpha | alpha_u/alpha_v | roughness (α = r²), each constant or
/// textured.
void read_microfacet(Binder& b, MicrofacetParams& m) {
    Properties& p = b.props();
    std::string d = p.get_choice("distribution", "ggx", "distribution", {"ggx", "beckmann"});
    m.distribution = d == "ggx" ? MicrofacetType::GGX : MicrofacetType::Beckmann;
    std::string g = p.get_choice("shadowing", "height_correlated", "shadowing", {"height_correlated", "separable"});
    m.shadowing = g == "separable" ? SmithShadowing::Separable : SmithShadowing::HeightCorrelated;
    bool has_alpha = p.has("alpha"), has_uv = p.has("alpha_u") || p.has("alpha_v"), has_r = p.has("roughness");
    if (int(has_alpha) + int(has_uv) + int(has_r) > 1)
        p.fail(has_r ? "roughness" : "alpha_u", "give only one of alpha, alpha_u/alpha_v, roughness");
    if (has_r || has_alpha) {
        // roughness: α = r² (Burley 2012 §5.4, microfacet.h alpha_from_roughness).
        // A bound texture keeps the default α = 0.1 as its constant.
        const char* key = has_r ? "roughness" : "alpha";
        if (!b.bind(key, m.alpha_u, has_r ? TexMap::Square : TexMap::Identity, 0.f, 1.f, true)) {
            float v = read_nonneg(p, key, has_r ? 0.f : 0.1f, 1.f);
            m.alpha_u = has_r ? v * v : v;
        }
        m.alpha_v = m.alpha_u;  // one texture (or constant) for both
        return;
    }
    if (has_uv) {
        if (!p.has("alpha_u")) p.fail("", "missing required key 'alpha_u' (alpha_v given)");
        b.nonneg("alpha_u", m.alpha_u, 1.f);
        if (p.has("alpha_v")) b.nonneg("alpha_v", m.alpha_v, 1.f);
        else m.alpha_v = m.alpha_u;
        return;
    }
    m.alpha_u = m.alpha_v = 0.1f;
}

void read_conductor_ior(Binder& b, ConductorIORParams& c) {
    Properties& p = b.props();
    std::string fresnel = p.get_choice("fresnel", "exact", "fresnel mode", {"exact", "schlick"});
    c.schlick = fresnel == "schlick";
    bool has_ek = p.has("eta") || p.has("k");
    if (has_ek) {
        if (p.has("material")) p.fail("material", "give either material or eta/k, not both");
        if (!p.has("eta")) p.fail("", "missing required key 'eta' (k given)");
        c.eta = Spectrum(1.f);
        c.k = Spectrum(0.f);
        // Textured eta is clamped to [1e-3, 100], k to [0, 100].
        if (!b.bind("eta", c.eta, TexMap::Identity, 1e-3f, 100.f, true)) {
            c.eta = p.get_spectrum("eta", Spectrum(1.f));
            for (int i = 0; i < 3; ++i)
                if (!(c.eta.value[i] > 0.f)) p.fail("eta", "value " + format_float(c.eta.value[i]) + " must be > 0");
        }
        if (!b.bind("k", c.k, TexMap::Identity, 0.f, 100.f, true)) {
            c.k = p.get_spectrum("k", Spectrum(0.f));
            for (int i = 0; i < 3; ++i)
                if (c.k.value[i] < 0.f) p.fail("k", "value " + format_float(c.k.value[i]) + " must be >= 0");
        }
        return;
    }
    std::string name = p.get_string("material", "none");
    std::vector<std::string> names = conductor_names();
    auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end()) p.fail("material", "unknown metal '" + name + "' (known: " + join_names(names) + ")");
    c.preset = int(it - names.begin());
    ConductorIOR ior = conductor_ior(name);
    c.eta = ior.eta;
    c.k = ior.k;
}

void read_dielectric(Binder& b, DielectricParams& d) {
    read_ior(b, "int_ior", "bk7", d.int_ior);
    read_ior(b, "ext_ior", "air", d.ext_ior);
    d.specular_reflectance = Spectrum(1.f);
    d.specular_transmittance = Spectrum(1.f);
    b.colour("specular_reflectance", d.specular_reflectance);
    b.colour("specular_transmittance", d.specular_transmittance);
}

void read_plastic(Binder& b, PlasticParams& q) {
    Properties& p = b.props();
    q.diffuse_reflectance = Spectrum(0.5f);
    q.specular_reflectance = Spectrum(1.f);
    b.colour("diffuse_reflectance", q.diffuse_reflectance);
    b.colour("specular_reflectance", q.specular_reflectance);
    read_ior(b, "int_ior", "polypropylene", q.int_ior);
    read_ior(b, "ext_ior", "air", q.ext_ior);
    std::string v = p.get_choice("variant", "coupled", "variant", {"coupled", "linear", "sum"});
    q.variant = v == "coupled" ? PlasticVariant::Coupled : v == "linear" ? PlasticVariant::Linear : PlasticVariant::Sum;
}

/// coat_transmittance of rough_plastic. "rough" tabulates the coat once per material (bxdf/plastic.h,
/// RoughCoatTable): a textured α or IOR would need a table per hit, so it is an error (checked on
/// q's α and IOR fields).
void read_coat_transmittance(Properties& p, RoughPlasticParams& q) {
    std::string c = p.get_choice("coat_transmittance", "smooth", "coat transmittance", {"smooth", "rough"});
    q.coat_transmittance = c == "rough" ? CoatTransmittance::Rough : CoatTransmittance::Smooth;
    if (q.coat_transmittance != CoatTransmittance::Rough) return;
    if (q.plastic.variant == PlasticVariant::Sum)
        p.fail("coat_transmittance", "'rough' is not used by variant 'sum' (use 'coupled' or 'linear')");
    const char* key = q.plastic.int_ior.textured()   ? "int_ior"
                      : q.plastic.ext_ior.textured() ? "ext_ior"
                                                     : nullptr;
    if (!key && (q.microfacet.alpha_u.textured() || q.microfacet.alpha_v.textured()))
        for (const char* k : {"roughness", "alpha", "alpha_u", "alpha_v"})
            if (!key && p.has(k)) key = k;
    if (key)
        p.fail(key, "a texture is not allowed with coat_transmittance 'rough' (the coat's transmittance "
                    "table is built once per material; give a constant, or use coat_transmittance 'smooth')");
}
}  // namespace

Material build_lambertian(Properties& p, const BuildContext& ctx) {
    LambertianParams m;
    Binder b(p, ctx);
    m.reflectance = Spectrum(0.5f);
    b.colour("reflectance", m.reflectance);
    return m;
}

Material build_oren_nayar(Properties& p, const BuildContext& ctx) {
    OrenNayarParams q;
    Binder b(p, ctx);
    q.reflectance = Spectrum(0.5f);
    b.colour("reflectance", q.reflectance);
    std::string v = p.get_choice("variant", "eon", "variant", {"eon", "classic"});
    q.variant = v == "eon" ? OrenNayarVariant::EON : OrenNayarVariant::Classic;
    const char* other = q.variant == OrenNayarVariant::EON ? "sigma" : "roughness";
    if (p.has(other))
        p.fail(other, std::string("not used by variant '") + v + "' (classic takes sigma in degrees, eon roughness)");
    if (q.variant == OrenNayarVariant::Classic) {
        q.sigma_degrees = 20.f;
        b.nonneg("sigma", q.sigma_degrees, 90.f);
    } else {
        q.roughness = 0.5f;
        b.nonneg("roughness", q.roughness, 1.f);
    }
    return q;
}

Material build_conductor(Properties& p, const BuildContext& ctx) {
    ConductorParams q;
    Binder b(p, ctx);
    read_conductor_ior(b, q.ior);
    q.specular_reflectance = Spectrum(1.f);
    b.colour("specular_reflectance", q.specular_reflectance);
    return q;
}

// Kulla-Conty energy compensation: our albedo tables are tabulated for GGX only.
// They are also tabulated with height-correlated shadowing: the separable G loses more energy than
// they restore.
bool read_multiple_scattering(Properties& p, const MicrofacetParams& m) {
    bool on = p.get_bool("multiple_scattering", false);
    if (on && m.distribution != MicrofacetType::GGX)
        p.fail("multiple_scattering", "requires distribution 'ggx' (the Kulla-Conty tables are GGX only)");
    if (on && m.shadowing != SmithShadowing::HeightCorrelated)
        p.fail("multiple_scattering",
               "requires shadowing 'height_correlated' (the Kulla-Conty tables are tabulated with it)");
    return on;
}

Material build_rough_conductor(Properties& p, const BuildContext& ctx) {
    RoughConductorParams q;
    Binder b(p, ctx);
    read_microfacet(b, q.microfacet);
    read_conductor_ior(b, q.ior);
    q.specular_reflectance = Spectrum(1.f);
    b.colour("specular_reflectance", q.specular_reflectance);
    q.multiple_scattering = read_multiple_scattering(p, q.microfacet);
    return q;
}

Material build_dielectric(Properties& p, const BuildContext& ctx) {
    DielectricParams q;
    Binder b(p, ctx);
    read_dielectric(b, q);
    return q;
}
Material build_thin_dielectric(Properties& p, const BuildContext& ctx) {
    ThinDielectricParams q;
    Binder b(p, ctx);
    read_dielectric(b, q);
    return q;
}
Material build_rough_dielectric(Properties& p, const BuildContext& ctx) {
    RoughDielectricParams q;
    Binder b(p, ctx);
    read_microfacet(b, q.microfacet);
    read_dielectric(b, q.dielectric);
    q.multiple_scattering = read_multiple_scattering(p, q.microfacet);
    return q;
}

Material build_subsurface(Properties& p, const BuildContext& ctx) {
    SubsurfaceParams q;
    Binder b(p, ctx);
    const std::string model =
        p.get_choice("model", "auto", "model", {"auto", "dipole", "better_dipole", "random_walk", "coated"});
    q.model = model == "dipole"          ? SubsurfaceModel::Dipole
              : model == "better_dipole" ? SubsurfaceModel::BetterDipole
              : model == "random_walk"   ? SubsurfaceModel::RandomWalk
              : model == "coated"        ? SubsurfaceModel::Coated
                                         : SubsurfaceModel::Auto;
    read_ior(b, "int_ior", "water", q.boundary.int_ior);
    read_ior(b, "ext_ior", "air", q.boundary.ext_ior);
    q.rough = p.has("alpha") || p.has("alpha_u") || p.has("alpha_v") || p.has("roughness");
    if (q.rough) read_microfacet(b, q.microfacet);
    const bool coeffs = p.has("sigma_a") || p.has("sigma_s") || p.has("scale");
    const bool diffuse = p.has("albedo") || p.has("mfp");
    if (coeffs && diffuse)
        p.fail(p.has("albedo") ? "albedo" : "mfp",
               "give either sigma_a/sigma_s (with scale) or albedo/mfp, not both");
    q.from_albedo = !coeffs;
    constexpr float kBig = 3.0e38f;  // finite in float: a coefficient must stay finite once stored
    if (q.from_albedo) {
        b.colour("albedo", q.albedo, 0.f, 1.f);  // 1: a lossless interior (σa = 0)
        b.colour("mfp", q.mfp, 1e-30f, kBig);
    } else {
        b.colour("sigma_a", q.sigma_a, 0.f, kBig);
        b.colour("sigma_s", q.sigma_s, 0.f, kBig);
        q.scale = p.get_float("scale", 1.f);
        if (!(q.scale > 0.f) || !std::isfinite(q.scale))
            p.fail("scale", "value " + format_float(q.scale) + " must be > 0 and finite");
    }
    b.range("g", q.g, -0.999f, 0.999f);
    return q;
}

Material build_plastic(Properties& p, const BuildContext& ctx) {
    PlasticParams q;
    Binder b(p, ctx);
    read_plastic(b, q);
    return q;
}
Material build_rough_plastic(Properties& p, const BuildContext& ctx) {
    RoughPlasticParams q;
    Binder b(p, ctx);
    read_microfacet(b, q.microfacet);
    read_plastic(b, q.plastic);
    read_coat_transmittance(p, q);
    return q;
}

Material build_principled(Properties& p, const BuildContext& ctx) {
    PrincipledParams q;
    Binder b(p, ctx);
    std::string v = p.get_choice("variant", "2012", "variant", {"2012", "2015"});
    q.variant = v == "2015" ? PrincipledVariant::Burley2015 : PrincipledVariant::Burley2012;
    bool v2015 = q.variant == PrincipledVariant::Burley2015;
    q.thin = v2015 && p.get_bool("thin", false);
    // Keys of the other variant (or mode) are errors, not silently ignored.
    auto unused = [&](std::initializer_list<const char*> keys, const std::string& why) {
        for (const char* k : keys)
            if (p.has(k)) p.fail(k, "not used by " + why);
    };
    if (!v2015)
        unused({"specular_transmission", "eta", "flatness", "thin", "diffuse_transmission"},
               "variant '2012' (a key of variant '2015')");
    else if (q.thin)
        unused({"metallic", "clearcoat", "clearcoat_gloss"}, "the thin 2015 model");
    else
        unused({"diffuse_transmission"}, "the solid 2015 model (it needs thin: true)");
    if (v2015 && p.has("eta") && p.has("specular"))
        p.fail("eta", "give either eta or specular, not both (specular sets eta)");
    b.colour("base_color", q.base_color);
    if (!q.thin) b.range("metallic", q.metallic, 0.f, 1.f);
    b.range("roughness", q.roughness, 0.f, 1.f);
    b.range("specular", q.specular, 0.f, 1.f);
    b.range("specular_tint", q.specular_tint, 0.f, 1.f);
    b.range("sheen", q.sheen, 0.f, 1.f);
    b.range("sheen_tint", q.sheen_tint, 0.f, 1.f);
    if (!q.thin) {
        b.range("clearcoat", q.clearcoat, 0.f, 1.f);
        b.range("clearcoat_gloss", q.clearcoat_gloss, 0.f, 1.f);
    }
    b.range("anisotropic", q.anisotropic, 0.f, 1.f);
    if (v2015) {
        b.range("specular_transmission", q.specular_transmission, 0.f, 1.f);
        b.range("flatness", q.flatness, 0.f, 1.f);
        if (p.has("eta")) {
            q.eta = 1.5f;  // the constant where a texture is bound
            b.range("eta", q.eta, 1e-3f, 10.f);
        }
        if (q.thin) b.range("diffuse_transmission", q.diffuse_transmission, 0.f, 2.f);
    }
    return q;
}

namespace {
// Keys every material takes: bump_map / bump_scale / bump_model, normal_map /
// normal_map_convention, invalid_normals, and terminator_softening / terminator_model
// (material/textured.h).
void read_normal_perturbation(Properties& p, const BuildContext& ctx) {
    static const char* keys[] = {"bump_map", "bump_scale", "bump_step_scale", "normal_map", "normal_map_convention",
                                 "terminator_softening", "bump_model", "invalid_normals", "terminator_model"};
    bool any = false;
    for (const char* k : keys) any = any || p.has(k);
    if (!any) return;
    if (!ctx.textures || !ctx.material_textures)
        p.fail(p.has("bump_map") ? "bump_map" : "normal_map",
               "bump and normal maps are only allowed in a scene (this interface takes constant parameters)");
    MaterialTextures& mt = *ctx.material_textures;
    if (p.has("bump_map")) mt.bump = int32_t(ctx.textures->texture(*p.get_node("bump_map"), p.key_path("bump_map"), true));
    mt.bump_scale = p.get_float("bump_scale", 1.f);
    mt.bump_step_scale = p.get_float("bump_step_scale", 1.f);
    if (!(mt.bump_step_scale > 0.f)) p.fail("bump_step_scale", "value " + format_float(mt.bump_step_scale) + " must be > 0");
    if (p.has("normal_map"))
        mt.normal_map = int32_t(ctx.textures->texture(*p.get_node("normal_map"), p.key_path("normal_map"), true));
    mt.normal_map_directx =
        p.get_choice("normal_map_convention", "opengl", "normal map convention", {"opengl", "directx"}) == "directx";
    mt.terminator_softening = p.get_bool("terminator_softening", true);
    mt.bump_model = p.get_choice("bump_model", "footprint", "bump model", {"footprint", "mitsuba"}) == "mitsuba"
                        ? BumpModel::Mitsuba
                        : BumpModel::Footprint;
    const std::string inv = p.get_choice("invalid_normals", "bend", "invalid normal treatment", {"bend", "mirror", "keep"});
    mt.invalid_normals = inv == "mirror" ? InvalidNormals::Mirror : inv == "keep" ? InvalidNormals::Keep : InvalidNormals::Bend;
    mt.terminator_model = p.get_choice("terminator_model", "chiang", "terminator model", {"chiang", "estevez"}) == "estevez"
                              ? TerminatorModel::Estevez
                              : TerminatorModel::Chiang;
}
}  // namespace

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
        p.fail("type", unknown_type_message("material", type, names));
    }
    Material m = it->second(p, ctx);
    prepare_material(m);
    read_normal_perturbation(p, ctx);
    if (p.has("two_sided")) {
        if (!ctx.material_textures)
            p.fail("two_sided", "is a scene-level key (this interface evaluates the BSDF on both sides)");
        ctx.material_textures->two_sided = p.get_bool("two_sided", true);
    }
    p.check_unqueried();
    return m;
}
}  // namespace pellucid
