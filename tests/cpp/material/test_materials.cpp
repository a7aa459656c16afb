// Every material type builds from JSON; errors carry the key path, parameter and value; the
// documented special cases (σ = 0 → Lambertian, α < 1e-3 → delta lobe, clamps) hold.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "pellucid/bxdf/batch.h"
#include "pellucid/material/bsdf_probe.h"
#include "pellucid/material/builders.h"
#include "pellucid/material/textured.h"
#include "pellucid/scene/build.h"
#include "pellucid/scene/json_io.h"
#include "pellucid/scene/registry.h"
#include "pellucid/util/error.h"
#include "support/error_of.h"

using namespace pellucid;

namespace {
Material material_from(const std::string& json) {
    return build_material(parse_json(json, "m.json"), "scene.json", "materials.m");
}
BxDF bxdf_from(const std::string& json) { return make_bxdf(material_from(json)); }

std::string material_error(const std::string& json) { return test::error_of_call([&] { material_from(json); }); }

Vec3f dir(float cos_theta, float phi) {
    float s = std::sqrt(1.f - cos_theta * cos_theta);
    return Vec3f(s * std::cos(phi), s * std::sin(phi), cos_theta);
}
}  // namespace

// One JSON object per registered type; the test fails if a type is registered but not listed.
TEST(Materials, EveryTypeBuildsFromJson) {
    const std::map<std::string, std::string> examples = {
        {"lambertian", R"({"type": "lambertian", "reflectance": [0.8, 0.2, 0.2]})"},
        {"oren_nayar", R"({"type": "oren_nayar", "reflectance": 0.7, "variant": "classic", "sigma": 30})"},
        {"conductor", R"({"type": "conductor", "material": "Au", "fresnel": "schlick"})"},
        {"rough_conductor", R"({"type": "rough_conductor", "material": "Al", "alpha_u": 0.05, "alpha_v": 0.3,
                              "multiple_scattering": true, "specular_reflectance": 0.9})"},
        {"dielectric", R"({"type": "dielectric", "int_ior": "water", "ext_ior": 1.0})"},
        {"rough_dielectric", R"({"type": "rough_dielectric", "int_ior": 1.5, "roughness": 0.5})"},
        {"thin_dielectric", R"({"type": "thin_dielectric", "int_ior": "bk7", "specular_transmittance": 0.9})"},
        {"plastic", R"({"type": "plastic", "diffuse_reflectance": [0.1, 0.3, 0.6], "variant": "sum"})"},
        {"rough_plastic", R"({"type": "rough_plastic", "int_ior": "polypropylene", "alpha": 0.2})"},
        {"principled", R"({"type": "principled", "base_color": [0.8, 0.2, 0.1], "roughness": 0.4,
                         "clearcoat": 1, "clearcoat_gloss": 0.9, "anisotropic": 0.5})"},
        {"subsurface", R"({"type": "subsurface", "model": "dipole", "albedo": [0.9, 0.6, 0.4], "mfp": 0.01,
                         "int_ior": 1.4, "g": 0.3})"},
    };
    std::set<size_t> alternatives;
    for (const auto& [type, fn] : material_registry()) {
        auto it = examples.find(type);
        ASSERT_NE(it, examples.end()) << "no example for registered material type '" << type << "'";
        Material m = material_from(it->second);
        alternatives.insert(m.index());
        BxDF b = make_bxdf(m);
        EXPECT_NE(flags(b), BxDFFlags::None) << type;
        EXPECT_EQ(to_string(m).rfind(type + "[", 0), 0u) << to_string(m);
        // The BxDF reflects something for a front-facing direction.
        float a[3];
        Vec3f wo = dir(0.7f, 0.3f);
        albedo_batch(b, BxDFContext{}, &wo.x, 1, 2000, 3, a, 1);
        EXPECT_GT(a[0] + a[1] + a[2], 0.f) << type;
        EXPECT_LE(a[1], 1.05f) << type;
    }
    EXPECT_EQ(examples.size(), material_registry().size());
    // Each type builds its own alternative of the Material variant, and every alternative has a type.
    EXPECT_EQ(alternatives.size(), material_registry().size());
    EXPECT_EQ(alternatives.size(), std::variant_size_v<Material>);
}

TEST(Materials, ErrorsNameKeyPathParameterAndValue) {
    EXPECT_EQ(material_error(R"({"type": "rough_conductor", "alpha": -0.1})"),
              "scene.json: materials.m.alpha: value -0.1 must be >= 0");
    EXPECT_EQ(material_error(R"({"type": "dielectric", "int_ior": 0})"),
              "scene.json: materials.m.int_ior: value 0 must be > 0");
    EXPECT_EQ(material_error(R"({"type": "rough_plastic", "ext_ior": -1.5})"),
              "scene.json: materials.m.ext_ior: value -1.5 must be > 0");
    EXPECT_EQ(material_error(R"({"type": "conductor", "eta": [1, 0, 1], "k": 2})"),
              "scene.json: materials.m.eta: value 0 must be > 0");
    EXPECT_EQ(material_error(R"({"type": "conductor", "material": "unobtainium"})").rfind(
                  "scene.json: materials.m.material: unknown metal 'unobtainium' (known: a-C, Ag", 0),
              0u);
    EXPECT_EQ(material_error(R"({"type": "rough_conductor", "distribution": "phong"})"),
              "scene.json: materials.m.distribution: unknown distribution 'phong' (known: ggx, beckmann)");
    EXPECT_EQ(material_error(R"({"type": "oren_nayar", "variant": "fancy"})"),
              "scene.json: materials.m.variant: unknown variant 'fancy' (known: eon, classic)");
    EXPECT_EQ(material_error(R"({"type": "plastic", "variant": "layered"})"),
              "scene.json: materials.m.variant: unknown variant 'layered' (known: coupled, linear, sum)");
    EXPECT_EQ(material_error(R"({"type": "rough_conductor", "fresnel": "approx"})"),
              "scene.json: materials.m.fresnel: unknown fresnel mode 'approx' (known: exact, schlick)");
    EXPECT_EQ(material_error(R"({"type": "dielectric", "int_ior": "glas"})").rfind(
                  "scene.json: materials.m.int_ior: unknown IOR name 'glas' (known: vacuum", 0),
              0u);
    EXPECT_EQ(material_error(R"({"type": "rough_dielectric", "distribution": "beckmann", "multiple_scattering": true})"),
              "scene.json: materials.m.multiple_scattering: requires distribution 'ggx' (the Kulla-Conty tables are "
              "GGX only)");
    EXPECT_EQ(material_error(R"({"type": "rough_plastic", "distribution": "blinn"})"),
              "scene.json: materials.m.distribution: unknown distribution 'blinn' (known: ggx, beckmann)");
    EXPECT_EQ(material_error(R"({"type": "rough_conductor", "distribution": "beckmann", "multiple_scattering": true})"),
              "scene.json: materials.m.multiple_scattering: requires distribution 'ggx' (the Kulla-Conty tables are "
              "GGX only)");
    EXPECT_EQ(material_error(R"({"type": "rough_conductor", "alpha": 0.1, "roughness": 0.3})"),
              "scene.json: materials.m.roughness: give only one of alpha, alpha_u/alpha_v, roughness");
    EXPECT_EQ(material_error(R"({"type": "conductor", "material": "Au", "eta": 1.2})"),
              "scene.json: materials.m.material: give either material or eta/k, not both");
    EXPECT_EQ(material_error(R"({"type": "oren_nayar", "variant": "classic", "roughness": 0.3})"),
              "scene.json: materials.m.roughness: not used by variant 'classic' (classic takes sigma in degrees, eon "
              "roughness)");
    EXPECT_EQ(material_error(R"({"type": "principled", "metallic": 1.5})"),
              "scene.json: materials.m.metallic: value 1.5 is out of range [0, 1]");
    EXPECT_EQ(material_error(R"({"type": "rough_conductor", "alpah": 0.1})"),
              "scene.json: materials.m.alpah: unknown parameter");
    EXPECT_EQ(material_error(R"({"type": "plastic", "diffuse_reflectance": 1.2})"),
              "scene.json: materials.m.diffuse_reflectance: value [1.200000, 1.200000, 1.200000] is out of range "
              "[0, 1]");
}

TEST(Materials, ErrorsInsideAScene) {
    SceneDesc d;
    d.source = "scene.json";
    d.root = parse_json(R"({"materials": {"gold": {"type": "rough_conductor", "material": "Au", "alpha": -0.1}}})",
                        "scene.json");
    try {
        build_scene(d);
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_STREQ(e.what(), "scene.json: materials.gold.alpha: value -0.1 must be >= 0");
    }
}

// `distribution` picks the template argument of the BxDF; `multiple_scattering` switches Kulla–Conty on.
TEST(Materials, DistributionPicksTheBxDF) {
    EXPECT_TRUE(std::holds_alternative<RoughDielectric<Beckmann>>(
        bxdf_from(R"({"type": "rough_dielectric", "distribution": "beckmann", "alpha": 0.3})")));
    EXPECT_TRUE(std::holds_alternative<RoughDielectric<GGX>>(bxdf_from(R"({"type": "rough_dielectric", "alpha": 0.3})")));
    EXPECT_TRUE(std::holds_alternative<RoughPlastic<Beckmann>>(
        bxdf_from(R"({"type": "rough_plastic", "distribution": "beckmann", "alpha": 0.3})")));
    EXPECT_TRUE(std::holds_alternative<RoughPlastic<GGX>>(bxdf_from(R"({"type": "rough_plastic", "alpha": 0.3})")));
    BxDF ms = bxdf_from(R"({"type": "rough_dielectric", "alpha": 0.5, "multiple_scattering": true})");
    ASSERT_TRUE(std::holds_alternative<RoughDielectric<GGX>>(ms));
    EXPECT_TRUE(std::get<RoughDielectric<GGX>>(ms).multiscatter());
    EXPECT_FALSE(std::get<RoughDielectric<GGX>>(bxdf_from(R"({"type": "rough_dielectric", "alpha": 0.5})")).multiscatter());
}

TEST(Materials, OrenNayarAtZeroRoughnessIsLambertian) {
    BxDF lam = bxdf_from(R"({"type": "lambertian", "reflectance": 0.6})");
    for (const char* json : {R"({"type": "oren_nayar", "reflectance": 0.6, "variant": "classic", "sigma": 0})",
                             R"({"type": "oren_nayar", "reflectance": 0.6, "variant": "eon", "roughness": 0})"}) {
        BxDF on = bxdf_from(json);
        for (float co : {0.9f, 0.4f, 0.05f})
            for (float ci : {0.95f, 0.5f, 0.1f}) {
                Vec3f wo = dir(co, 0.2f), wi = dir(ci, 2.5f);
                EXPECT_EQ(eval(on, BxDFContext{}, wo, wi), eval(lam, BxDFContext{}, wo, wi)) << json;
                EXPECT_EQ(pdf(on, BxDFContext{}, wo, wi), pdf(lam, BxDFContext{}, wo, wi)) << json;
            }
    }
}

TEST(Materials, TinyAlphaCollapsesToTheDeltaLobe) {
    for (const char* json : {R"({"type": "rough_conductor", "material": "Cu", "alpha": 5e-4})",
                             R"({"type": "rough_conductor", "distribution": "beckmann", "alpha": 1e-4})",
                             R"({"type": "rough_conductor", "roughness": 0.03})",  // α = 9e-4
                             R"({"type": "rough_dielectric", "alpha": 0})"}) {
        BxDF b = bxdf_from(json);
        Vec3f wo = dir(0.6f, 1.f);
        auto s = sample(b, BxDFContext{}, wo, 0.01f, Vec2f(0.3f, 0.7f));
        ASSERT_TRUE(s) << json;
        EXPECT_TRUE(s->is_specular()) << json;
        EXPECT_TRUE(is_specular(flags(b))) << json;
        EXPECT_EQ(eval(b, BxDFContext{}, wo, s->wi), Spectrum(0.f)) << json;
    }
    // The plastic coat becomes a delta lobe; the diffuse base stays.
    BxDF plastic = bxdf_from(R"({"type": "rough_plastic", "alpha": 9e-4})");
    EXPECT_EQ(flags(plastic), BxDFFlags::SpecularReflection | BxDFFlags::DiffuseReflection);
    // Just above the threshold the lobe is glossy.
    EXPECT_EQ(flags(bxdf_from(R"({"type": "rough_conductor", "alpha": 2e-3})")), BxDFFlags::GlossyReflection);
}

// The plastic variants, the rough coat's transmittance and the shadowing option reach the BxDF;
// their invalid combinations are errors that name the key.
TEST(Materials, PlasticOptionsAndShadowing) {
    BxDF lin = bxdf_from(R"({"type": "plastic", "variant": "linear"})");
    EXPECT_NE(std::get<SmoothPlastic>(lin).to_string().find("variant=linear"), std::string::npos);
    BxDF rp = bxdf_from(R"({"type": "rough_plastic", "distribution": "beckmann", "alpha": 0.2, "variant": "linear",
                            "coat_transmittance": "rough", "shadowing": "separable"})");
    const auto& b = std::get<RoughPlastic<Beckmann>>(rp);
    ASSERT_NE(b.base().coat_table(), nullptr);
    EXPECT_EQ(b.base().coat_table(),
              &RoughCoatTable::get(Beckmann(0.2f, 0.2f, SmithShadowing::Separable), 1.49f / 1.000277f));
    EXPECT_EQ(std::get<RoughPlastic<GGX>>(bxdf_from(R"({"type": "rough_plastic"})")).base().coat_table(), nullptr);
    BxDF rc = bxdf_from(R"({"type": "rough_conductor", "alpha": 0.3, "shadowing": "separable"})");
    EXPECT_NE(std::get<RoughConductor>(rc).to_string().find("shadowing=separable"), std::string::npos);
    BxDF rd = bxdf_from(R"({"type": "rough_dielectric", "distribution": "beckmann", "shadowing": "separable"})");
    EXPECT_NE(std::get<RoughDielectric<Beckmann>>(rd).to_string().find("shadowing=separable"), std::string::npos);
    EXPECT_NE(to_string(material_from(R"({"type": "rough_plastic", "coat_transmittance": "rough",
        "shadowing": "separable"})")).find("shadowing=separable, diffuse_reflectance"), std::string::npos);

    EXPECT_EQ(material_error(R"({"type": "rough_plastic", "coat_transmittance": "rough", "variant": "sum"})"),
              "scene.json: materials.m.coat_transmittance: 'rough' is not used by variant 'sum' (use 'coupled' or "
              "'linear')");
    EXPECT_EQ(material_error(R"({"type": "rough_plastic", "coat_transmittance": "table"})"),
              "scene.json: materials.m.coat_transmittance: unknown coat transmittance 'table' (known: smooth, rough)");
    EXPECT_EQ(material_error(R"({"type": "plastic", "coat_transmittance": "rough"})"),
              "scene.json: materials.m.coat_transmittance: unknown parameter");
    EXPECT_EQ(material_error(R"({"type": "rough_conductor", "shadowing": "smith"})"),
              "scene.json: materials.m.shadowing: unknown shadowing 'smith' (known: height_correlated, separable)");
    EXPECT_EQ(material_error(R"({"type": "rough_dielectric", "multiple_scattering": true, "shadowing": "separable"})"),
              "scene.json: materials.m.multiple_scattering: requires shadowing 'height_correlated' (the Kulla-Conty "
              "tables are tabulated with it)");
}

// coat_transmittance "rough" builds its table once per material: a textured colour is fine and the
// BxDF built at each hit reuses the material's table (no per-hit table); a textured α or IOR is an error.
TEST(Materials, RoughCoatTableIsBuiltOncePerMaterial) {
    const char* shapes = R"("shapes": [{"type": "sphere", "material": "m"}]})";
    auto make = [&](const std::string& mat) {
        SceneDesc d;
        d.source = "scene.json";
        d.root = parse_json(R"({"materials": {"m": )" + mat + "}, " + shapes, "scene.json");
        return build_scene(d);
    };
    auto scene = make(R"({"type": "rough_plastic", "coat_transmittance": "rough", "alpha": 0.25,
        "diffuse_reflectance": {"type": "checkerboard", "color0": 0.1, "color1": 0.9}})");
    const auto& mat = std::get<RoughPlasticParams>(scene->materials.at(0));
    const RoughCoatTable* table = mat.coat_table;
    ASSERT_NE(table, nullptr);
    EXPECT_EQ(table, &RoughCoatTable::get(GGX(0.25f), 1.49f / 1.000277f));
    ASSERT_TRUE(scene->material_textures.at(0).has_textured_params());
    TextureEvalContext ctx;
    for (float u : {0.1f, 0.6f}) {
        ctx.uv = Vec2f(u, 0.3f);
        BxDF b = make_bxdf(scene->materials[0], TexEval(scene->textures, ctx));
        EXPECT_EQ(std::get<RoughPlastic<GGX>>(b).base().coat_table(), table);
    }
    for (const char* key : {"alpha", "roughness", "int_ior", "ext_ior"}) {
        try {
            make(std::string(R"({"type": "rough_plastic", "coat_transmittance": "rough", ")") + key +
                 R"(": {"type": "checkerboard", "color0": 0.1, "color1": 0.3}})");
            ADD_FAILURE() << key << ": expected an error";
        } catch (const Error& e) {
            EXPECT_EQ(std::string(e.what()),
                      std::string("scene.json: materials.m.") + key +
                          ": a texture is not allowed with coat_transmittance 'rough' (the coat's transmittance table "
                          "is built once per material; give a constant, or use coat_transmittance 'smooth')");
        }
    }
    // The smooth transmittance takes a textured α.
    EXPECT_NO_THROW(make(R"({"type": "rough_plastic", "alpha": {"type": "checkerboard", "color0": 0.1, "color1": 0.3}})"));
}

// A Tex parameter bound to a texture reads it through a TexEval over the hit: clamped into the
// parameter's range, then mapped (roughness r -> alpha = r^2). TexEval{} reads the constants (a bound
// parameter keeps its default), and untextured fields give their constants either way.
TEST(Materials, TexParametersReadTheirTexturesThroughTexEval) {
    SceneDesc d;
    d.source = "scene.json";
    d.root = parse_json(R"({"materials": {
        "r": {"type": "rough_conductor", "material": "Au",
              "roughness": {"type": "checkerboard", "color0": 0.2, "color1": 0.6},
              "specular_reflectance": {"type": "checkerboard", "color0": [0.5, 0.25, 1.0], "color1": 0.9}},
        "a": {"type": "rough_conductor", "alpha": {"type": "checkerboard", "color0": 0.5, "color1": 3.0}}},
        "shapes": [{"type": "sphere", "material": "r"}, {"type": "sphere", "material": "a"}]})",
                        "scene.json");
    auto scene = build_scene(d);
    const auto& r = std::get<RoughConductorParams>(scene->materials.at(0));
    ASSERT_TRUE(r.microfacet.alpha_u.textured());
    EXPECT_EQ(r.microfacet.alpha_u.map, TexMap::Square);
    EXPECT_EQ(r.microfacet.alpha_v.texture, r.microfacet.alpha_u.texture);
    EXPECT_TRUE(r.specular_reflectance.textured());
    EXPECT_FALSE(r.ior.eta.textured() || r.ior.k.textured());
    EXPECT_EQ(scene->material_textures.at(0).count, 2);
    auto alpha_of = [](const BxDF& b) { return std::get<RoughConductor>(b).distribution().alpha_x(); };
    EXPECT_EQ(alpha_of(make_bxdf(scene->materials[0])), 0.1f);  // the constant of a bound α
    EXPECT_EQ(alpha_of(scene->material_bxdfs[0]), 0.1f);
    std::set<float> alphas, clamped;
    TextureEvalContext ctx;
    for (float u : {0.25f, 0.75f}) {
        ctx.uv = Vec2f(u, 0.25f);
        const TexEval tex(scene->textures, ctx);
        const BxDF b = make_bxdf(scene->materials[0], tex);
        alphas.insert(alpha_of(b));
        EXPECT_EQ(std::get<RoughConductor>(b).distribution().alpha_y(), alpha_of(b));
        const Spectrum ks = tex(r.specular_reflectance);
        EXPECT_TRUE(ks == Spectrum(0.9f) || ks == Spectrum(0.5f, 0.25f, 1.f)) << ks.to_string();
        EXPECT_EQ(tex(r.ior.eta), r.ior.eta.value);
        clamped.insert(alpha_of(make_bxdf(scene->materials[1], tex)));
    }
    // A float parameter reads the channel average of its texture (3 equal channels: within 1 ulp).
    ASSERT_EQ(alphas.size(), 2u);
    EXPECT_NEAR(*alphas.begin(), 0.2f * 0.2f, 1e-7f);
    EXPECT_NEAR(*alphas.rbegin(), 0.6f * 0.6f, 1e-7f);
    ASSERT_EQ(clamped.size(), 2u);
    EXPECT_NEAR(*clamped.begin(), 0.5f, 1e-7f);
    EXPECT_EQ(*clamped.rbegin(), 1.f);  // 3 is clamped to α's upper bound 1
}

TEST(Materials, ClampsAndMappings) {
    // α > 1 is clamped to 1; roughness r maps to α = r².
    auto rc = std::get<RoughConductorParams>(material_from(R"({"type": "rough_conductor", "alpha": 3})"));
    EXPECT_EQ(rc.microfacet.alpha_u.value, 1.f);
    rc = std::get<RoughConductorParams>(material_from(R"({"type": "rough_conductor", "roughness": 0.5})"));
    EXPECT_FLOAT_EQ(rc.microfacet.alpha_u.value, 0.25f);
    rc = std::get<RoughConductorParams>(material_from(R"({"type": "rough_conductor", "alpha_u": 0.2})"));
    EXPECT_EQ(rc.microfacet.alpha_v.value, 0.2f);
    auto on = std::get<OrenNayarParams>(material_from(R"({"type": "oren_nayar", "variant": "classic", "sigma": 120})"));
    EXPECT_EQ(on.sigma_degrees.value, 90.f);
    // Named IORs: η = int_ior/ext_ior.
    auto d = std::get<DielectricParams>(material_from(R"({"type": "dielectric", "int_ior": "water", "ext_ior": "air"})"));
    EXPECT_FLOAT_EQ(relative_eta(d, TexEval{}), 1.333f / 1.000277f);
    // Default conductor is Mitsuba 3's "none": a perfect mirror.
    BxDF mirror = bxdf_from(R"({"type": "conductor"})");
    auto s = sample(mirror, BxDFContext{}, dir(0.3f, 0.1f), 0.5f, Vec2f(0.5f));
    ASSERT_TRUE(s);
    EXPECT_NEAR(s->weight.g, 1.f, 1e-6f);
}

TEST(Materials, SchlickUsesTheExactNormalIncidenceReflectance) {
    BxDF exact = bxdf_from(R"({"type": "conductor", "material": "Au"})");
    BxDF schlick = bxdf_from(R"({"type": "conductor", "material": "Au", "fresnel": "schlick"})");
    auto a = sample(exact, BxDFContext{}, Vec3f(0, 0, 1), 0.5f, Vec2f(0.5f));
    auto b = sample(schlick, BxDFContext{}, Vec3f(0, 0, 1), 0.5f, Vec2f(0.5f));
    ASSERT_TRUE(a && b);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a->weight[c], b->weight[c], 1e-5f);
    a = sample(exact, BxDFContext{}, dir(0.2f, 0.f), 0.5f, Vec2f(0.5f));
    b = sample(schlick, BxDFContext{}, dir(0.2f, 0.f), 0.5f, Vec2f(0.5f));
    EXPECT_GT(std::fabs(a->weight.b - b->weight.b), 1e-3f);  // they differ at grazing angles
}

TEST(Materials, ProbeBatchesAgreeWithSingleCalls) {
    BSDFProbe p = BSDFProbe::from_desc(parse_json(R"({"type": "rough_plastic", "alpha": 0.3})", "p.json"));
    EXPECT_NE(p.to_string().find("bsdf(rough_plastic[distribution=ggx, alpha=0.3"), std::string::npos);
    const float wo[6] = {0.f, 0.6f, 0.8f, 0.3f, 0.f, 0.5f};  // second row not normalised
    const float u[6] = {0.9f, 0.2f, 0.7f, 0.1f, 0.5f, 0.5f};
    float wi[6], w[6], pd[2], f[6], pe[2];
    uint32_t lobe[2];
    sample_batch(p.bxdf, p.ctx, wo, u, 2, wi, w, pd, lobe);
    eval_batch(p.bxdf, p.ctx, wo, wi, 2, f);
    pdf_batch(p.bxdf, p.ctx, wo, wi, 2, pe);
    for (int i = 0; i < 2; ++i) {
        ASSERT_GT(pd[i], 0.f);
        EXPECT_NEAR(pe[i], pd[i], 1e-3f * pd[i]);
        EXPECT_NEAR(f[3 * i] / pe[i], w[3 * i], 1e-3f * w[3 * i]);
        EXPECT_NE(lobe[i], 0u);
    }
    BxDFTiming t = benchmark_bxdf(p.bxdf, p.ctx, 1000);
    EXPECT_GT(t.ns_eval, 0.0);
    EXPECT_GT(t.ns_sample, 0.0);
}

TEST(Materials, LambertianAlbedoMatchesReflectance) {
    BSDFProbe p = BSDFProbe::from_desc(parse_json(R"({"type": "lambertian", "reflectance": [0.2, 0.5, 0.9]})", "p"));
    const float wo[6] = {0.f, 0.f, 1.f, 0.9f, 0.f, 0.1f};
    float a[6], b[6];
    albedo_batch(p.bxdf, p.ctx, wo, 2, 100, 1, a, 0);
    albedo_batch(p.bxdf, p.ctx, wo, 2, 100, 1, b, 1);
    for (int i = 0; i < 6; ++i) EXPECT_EQ(a[i], b[i]);  // independent of the thread count
    EXPECT_NEAR(a[0], 0.2f, 1e-6f);
    EXPECT_NEAR(a[5], 0.9f, 1e-6f);
}
