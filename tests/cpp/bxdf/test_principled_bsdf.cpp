// PrincipledBSDF (Burley 2015 as Mitsuba 3 defines it): closed forms (η ↔ specular, α mapping,
// lobe weights, the diffuse, fake-subsurface, diffuse-transmission and clearcoat terms), reference
// values of Mitsuba 3.9.1, the documented energy excess, and the `principled` builder's rules.
// The generic properties (χ², reciprocity, furnace, stability) are in test_bxdf_properties.cpp.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "pellucid/bxdf/bxdf.h"
#include "pellucid/material/builders.h"
#include "pellucid/scene/build.h"
#include "pellucid/scene/registry.h"
#include "pellucid/sampling/rng.h"
#include "pellucid/scene/json_io.h"
#include "pellucid/util/error.h"

using namespace pellucid;

namespace {
Vec3f dir(float theta, float phi) {
    return Vec3f(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
}
PrincipledInputs p2015() {
    PrincipledInputs p;
    p.variant = PrincipledVariant::Burley2015;
    p.sheen_tint = 0.f;
    p.clearcoat_gloss = 0.f;
    return p;
}
float schlick_weight(float c) { return std::pow(1.f - c, 5.f); }
const BxDFContext kRad{TransportMode::Radiance, BxDFFlags::All};
const BxDFContext kImp{TransportMode::Importance, BxDFFlags::All};

std::string material_error(const std::string& json) {
    try {
        build_material(parse_json(json, "m.json"), "scene.json", "materials.m");
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}
BxDF bxdf_of(const std::string& json) {
    return make_bxdf(build_material(parse_json(json, "m.json"), "scene.json", "materials.m"));
}
}  // namespace

// ((η − 1)/(η + 1))² = 0.08·specular; specular 0.5 ↔ η = 1.5 (the default of both plugins).
TEST(PrincipledBSDF, EtaFromSpecularInvertsR0) {
    EXPECT_NEAR(PrincipledBSDF::eta_from_specular(0.5f), 1.5f, 1e-6f);
    for (float s : {0.01f, 0.2f, 0.5f, 0.8f, 1.f}) {
        float eta = PrincipledBSDF::eta_from_specular(s);
        EXPECT_NEAR(sqr((eta - 1.f) / (eta + 1.f)), 0.08f * s, 1e-6f) << s;
    }
    EXPECT_EQ(PrincipledBSDF::eta_from_specular(0.f), 1.f);
    // With specular transmission η = 1 is moved off 1 (a refracting lobe needs η ≠ 1).
    PrincipledInputs p = p2015();
    p.specular = 0.f;
    EXPECT_EQ(PrincipledBSDF(p).eta(), 1.f);
    p.specular_transmission = 0.5f;
    EXPECT_NEAR(PrincipledBSDF(p).eta(), PrincipledBSDF::eta_from_specular(1e-3f), 1e-6f);
    p.eta = 1.f;
    EXPECT_EQ(PrincipledBSDF(p).eta(), 1.001f);
    p.eta = 1.33f;
    EXPECT_EQ(PrincipledBSDF(p).eta(), 1.33f);
}

// αx = max(1e-3, r²/s), αy = max(1e-3, r²·s), s = √(1 − 0.9·anisotropic); thin transmission uses
// roughness × (0.65η − 0.35).
TEST(PrincipledBSDF, AlphaFromRoughness) {
    Vec2f a = PrincipledBSDF::alpha_from_roughness(0.5f, 0.f);
    EXPECT_FLOAT_EQ(a.x, 0.25f);
    EXPECT_FLOAT_EQ(a.y, 0.25f);
    a = PrincipledBSDF::alpha_from_roughness(0.5f, 0.8f);
    EXPECT_FLOAT_EQ(a.x, 0.25f / std::sqrt(0.28f));
    EXPECT_FLOAT_EQ(a.y, 0.25f * std::sqrt(0.28f));
    a = PrincipledBSDF::alpha_from_roughness(0.f, 1.f);
    EXPECT_EQ(a.x, 1e-3f);
    EXPECT_EQ(a.y, 1e-3f);
    PrincipledInputs p = p2015();
    p.thin = true;
    p.roughness = 0.6f;
    p.eta = 1.4f;
    PrincipledBSDF b(p);
    EXPECT_FLOAT_EQ(b.specular_distribution().alpha_x(), 0.36f);
    EXPECT_FLOAT_EQ(b.thin_transmission_distribution().alpha_x(), sqr((0.65f * 1.4f - 0.35f) * 0.6f));
}

// Diffuse lobe weight (1 − metallic)(1 − spec_trans), transmission weight (1 − metallic)·spec_trans:
// the front-side specular reflection does not depend on spec_trans, so reflection is linear in
// (1 − spec_trans) and transmission in spec_trans.
TEST(PrincipledBSDF, LobeWeights) {
    Vec3f wo = dir(0.6f, 0.3f), wr = dir(0.9f, 2.8f), wt = dir(2.6f, 3.6f);
    auto f = [&](float m, float t, const Vec3f& wi) {
        PrincipledInputs p = p2015();
        p.base_color = Spectrum(0.7f, 0.5f, 0.3f);
        p.metallic = m;
        p.specular_transmission = t;
        p.eta = 1.5f;
        return PrincipledBSDF(p).eval(kRad, wo, wi);
    };
    for (float m : {0.f, 0.4f}) {
        Spectrum r0 = f(m, 0.f, wr), r1 = f(m, 1.f, wr), rh = f(m, 0.3f, wr);
        EXPECT_FALSE((r0 - r1).is_black());
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(rh[c], r1[c] + 0.7f * (r0[c] - r1[c]), 1e-6f) << m;
        Spectrum t1 = f(0.f, 1.f, wt), tm = f(m, 0.3f, wt);
        EXPECT_FALSE(t1.is_black());
        EXPECT_TRUE(f(m, 0.f, wt).is_black());
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(tm[c], (1.f - m) * 0.3f * t1[c], 1e-6f * t1[c] + 1e-9f);
    }
    // Transmission is tinted by √base; Radiance divides it by η'² (η' = 1.5 from outside).
    PrincipledInputs p = p2015();
    p.base_color = Spectrum(0.64f, 0.36f, 0.16f);
    p.specular_transmission = 1.f;
    p.eta = 1.5f;
    PrincipledBSDF b(p);
    Spectrum fr = b.eval(kRad, wo, wt), fi = b.eval(kImp, wo, wt);
    EXPECT_NEAR(fr.r / fr.g, 0.8f / 0.6f, 1e-5f);
    EXPECT_NEAR(fr.g / fr.b, 0.6f / 0.4f, 1e-5f);
    EXPECT_NEAR(fi.r / fr.r, 2.25f, 1e-5f);
}

// Diffuse at flatness 0 (Lambert part + retro-reflection) and 1 (Hanrahan–Krueger), thin diffuse
// transmission, clearcoat at normal incidence: each against its closed form.
TEST(PrincipledBSDF, DiffuseAndClearcoatClosedForms) {
    const float r = 0.7f;
    Vec3f wo = dir(0.5f, 0.2f), wi = dir(1.1f, 2.5f);
    float co = wo.z, ci = wi.z, cd = dot(wi, normalize(wo + wi));
    float fo = schlick_weight(co), fi = schlick_weight(ci), rr = 2.f * r * cd * cd;
    float f_d = (1.f - 0.5f * fo) * (1.f - 0.5f * fi);
    float f_r = rr * (fo + fi + fo * fi * (rr - 1.f));
    float fss = (1.f + (0.5f * rr - 1.f) * fo) * (1.f + (0.5f * rr - 1.f) * fi);
    float f_ss = 1.25f * (fss * (1.f / (co + ci) - 0.5f) + 0.5f);
    // Thin, no specular lobes: exactly the diffuse terms, weighted by (1 − d_t), d_t = diff_trans/2.
    PrincipledInputs p = p2015();
    p.thin = true;
    p.base_color = Spectrum(0.5f);
    p.roughness = r;
    p.diffuse_transmission = 0.5f;
    for (float flat : {0.f, 1.f}) {
        p.flatness = flat;
        float expect = 0.5f * kInvPi * (flat == 0.f ? f_d + f_r : f_ss) * ci * 0.75f;
        EXPECT_NEAR(PrincipledBSDF(p).eval(kRad, wo, wi).r, expect, 1e-6f) << flat;
    }
    Vec3f wt = dir(2.2f, 1.f);
    EXPECT_NEAR(PrincipledBSDF(p).eval(kRad, wo, wt).r, 0.25f * 0.5f * kInvPi * std::fabs(wt.z), 1e-7f);
    // Clearcoat at wo = wi = z: ¼·clearcoat·S(0.04)·D_GTR1(1) with G = 1, S(0.04, 1) = 0.04 (and no
    // 1/(4 cos θo cos θi), as Mitsuba defines the lobe).
    PrincipledInputs q = p2015();
    q.clearcoat_gloss = 0.5f;
    Vec3f z(0.f, 0.f, 1.f);
    Spectrum without = PrincipledBSDF(q).eval(kRad, z, z);
    q.clearcoat = 0.8f;
    float a = 0.1f + (0.001f - 0.1f) * 0.5f, a2 = a * a;
    float d1 = (a2 - 1.f) / (kPi * std::log(a2) * a2);
    EXPECT_NEAR((PrincipledBSDF(q).eval(kRad, z, z) - without).r, 0.25f * 0.8f * 0.04f * d1, 1e-4f);
}

// Reference values of Mitsuba 3.9.1's principled / principledthin (scalar_rgb, BSDF::eval and pdf
// at wo = dir(θ, φ), wi = dir(θ', φ'), Mitsuba's si.wi = our wo): the definition, pointwise. Behind
// an opaque solid the reference is Mitsuba's twosided(principled) (ours is two-sided).
TEST(PrincipledBSDF, MatchesMitsubaPointwise) {
    struct Ref {
        int config;
        float to, po, ti, pi;
        Spectrum f;
        float pdf;
    };
    PrincipledInputs cfg[4];
    cfg[0] = p2015();
    cfg[0].base_color = Spectrum(0.8f, 0.4f, 0.2f);
    cfg[0].roughness = 0.4f;
    cfg[0].sheen = 0.5f;
    cfg[0].sheen_tint = 0.3f;
    cfg[0].flatness = 0.4f;
    cfg[0].clearcoat = 0.7f;
    cfg[0].clearcoat_gloss = 0.6f;
    cfg[0].specular_tint = 0.3f;
    cfg[0].metallic = 0.2f;
    cfg[0].anisotropic = 0.4f;
    cfg[1] = p2015();
    cfg[1].base_color = Spectrum(0.9f, 0.8f, 0.6f);
    cfg[1].roughness = 0.3f;
    cfg[1].specular_transmission = 0.7f;
    cfg[1].eta = 1.33f;
    cfg[1].metallic = 0.1f;
    cfg[2] = p2015();
    cfg[2].base_color = Spectrum(0.9f, 0.8f, 0.6f);
    cfg[2].specular_transmission = 0.6f;
    cfg[2].specular = 0.8f;
    cfg[3] = p2015();
    cfg[3].thin = true;
    cfg[3].base_color = Spectrum(0.8f, 0.4f, 0.2f);
    cfg[3].roughness = 0.35f;
    cfg[3].specular_transmission = 0.6f;
    cfg[3].diffuse_transmission = 0.7f;
    cfg[3].eta = 1.4f;
    cfg[3].specular_tint = 0.4f;
    cfg[3].anisotropic = 0.5f;
    cfg[3].sheen = 0.4f;
    cfg[3].flatness = 0.3f;
    const Ref refs[] = {
        {0, 0.5f, 0.3f, 0.7f, 2.9f, {0.2198215f, 0.1173122f, 0.06605757f}, 0.313978f},
        {0, 1.2f, 0.1f, 0.4f, 3.5f, {0.2534723f, 0.1328946f, 0.07260576f}, 0.2962386f},
        {0, 0.5f, 0.3f, 2.5f, 2.0f, {0.f, 0.f, 0.f}, 0.f},
        // From behind without transmission: two-sided, as Mitsuba's twosided(principled).
        {0, 2.6f, 0.5f, 2.2f, 3.3f, {0.2173062f, 0.117023f, 0.06688133f}, 0.3541975f},
        {1, 0.5f, 0.3f, 0.7f, 2.9f, {0.09280431f, 0.08315945f, 0.06386974f}, 0.1447035f},
        {1, 1.2f, 0.1f, 0.4f, 3.5f, {0.07679455f, 0.0684356f, 0.05171771f}, 0.08112776f},
        {1, 2.3f, 1.0f, 0.6f, 4.0f, {0.01090642f, 0.01028267f, 0.008905053f}, 0.0103259f},
        {1, 2.6f, 0.5f, 2.2f, 3.3f, {0.007228671f, 0.007228671f, 0.007228671f}, 0.01151777f},
        {2, 0.5f, 0.3f, 0.7f, 2.9f, {0.124152f, 0.1144123f, 0.09493278f}, 0.2433385f},
        {2, 0.5f, 0.3f, 2.5f, 2.0f, {0.00147791f, 0.001393386f, 0.001206708f}, 0.003157656f},
        {2, 2.3f, 1.0f, 0.6f, 4.0f, {0.07981739f, 0.07525256f, 0.06517063f}, 0.05020405f},
        {2, 2.6f, 0.5f, 2.2f, 3.3f, {0.2376926f, 0.2376926f, 0.2376926f}, 0.4075115f},
        {3, 0.5f, 0.3f, 0.7f, 2.9f, {0.05212281f, 0.02730771f, 0.01490016f}, 0.1330483f},
        {3, 1.2f, 0.1f, 0.4f, 3.5f, {0.06699222f, 0.03568487f, 0.02003119f}, 0.1657094f},
        {3, 0.5f, 0.3f, 2.5f, 2.0f, {0.02944897f, 0.01472448f, 0.007362242f}, 0.03627267f},
        {3, 2.3f, 1.0f, 0.6f, 4.0f, {0.1006534f, 0.05032671f, 0.02516335f}, 0.08284522f},
        {3, 2.6f, 0.5f, 2.2f, 3.3f, {0.0480121f, 0.02681995f, 0.01622388f}, 0.1845682f},
    };
    for (const Ref& r : refs) {
        PrincipledBSDF b(cfg[r.config]);
        Vec3f wo = dir(r.to, r.po), wi = dir(r.ti, r.pi);
        Spectrum f = b.eval(kRad, wo, wi);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(f[c], r.f[c], 2e-4f * r.f[c] + 1e-9f) << r.config << " " << r.to;
        EXPECT_NEAR(b.pdf(kRad, wo, wi), r.pdf, 2e-4f * r.pdf + 1e-9f) << r.config << " " << r.to;
    }
}

// Not energy-conserving (principled_bsdf.h, "Energy"): a white base at high roughness reflects more
// than it receives at grazing incidence. Mean sample weight over 2·10⁵ samples (SE < 2e-3).
TEST(PrincipledBSDF, WhiteBaseExceedsOneAtGrazing) {
    PrincipledInputs p = p2015();
    p.base_color = Spectrum(1.f);
    p.roughness = 1.f;
    PrincipledBSDF b(p);
    PCG32 rng(3, 1);
    Vec3f wo = dir(std::acos(0.1f), 0.f);
    double sum = 0.0;
    const int n = 200000;
    for (int k = 0; k < n; ++k) {
        float ul = rng.next_float();
        auto s = b.sample(kImp, wo, ul, rng.next_2d());
        if (s) sum += s->weight.g;
    }
    EXPECT_GT(sum / n, 1.1);
}

TEST(PrincipledBSDF, BuilderVariantsAndErrors) {
    EXPECT_TRUE(std::holds_alternative<Principled>(bxdf_of(R"({"type": "principled"})")));
    BxDF b = bxdf_of(R"({"type": "principled", "variant": "2015", "specular_transmission": 1, "eta": 1.33})");
    ASSERT_TRUE(std::holds_alternative<PrincipledBSDF>(b));
    EXPECT_EQ(std::get<PrincipledBSDF>(b).eta(), 1.33f);
    EXPECT_FALSE(std::get<PrincipledBSDF>(b).thin());
    EXPECT_TRUE(is_transmissive(flags(b)));
    b = bxdf_of(R"({"type": "principled", "variant": "2015", "thin": true, "diffuse_transmission": 2})");
    ASSERT_TRUE(std::holds_alternative<PrincipledBSDF>(b));
    EXPECT_TRUE(std::get<PrincipledBSDF>(b).thin());
    EXPECT_EQ(to_string(flags(b)), to_string(BxDFFlags::DiffuseTransmission));
    EXPECT_EQ(material_error(R"({"type": "principled", "flatness": 0.5})"),
              "scene.json: materials.m.flatness: not used by variant '2012' (a key of variant '2015')");
    EXPECT_EQ(material_error(R"({"type": "principled", "variant": "2015", "eta": 1.4, "specular": 0.3})"),
              "scene.json: materials.m.eta: give either eta or specular, not both (specular sets eta)");
    EXPECT_EQ(material_error(R"({"type": "principled", "variant": "2015", "thin": true, "clearcoat": 1})"),
              "scene.json: materials.m.clearcoat: not used by the thin 2015 model");
    EXPECT_EQ(material_error(R"({"type": "principled", "variant": "2015", "diffuse_transmission": 1})"),
              "scene.json: materials.m.diffuse_transmission: not used by the solid 2015 model (it needs thin: true)");
    EXPECT_EQ(material_error(R"({"type": "principled", "variant": "2015", "thin": true, "diffuse_transmission": 2.5})"),
              "scene.json: materials.m.diffuse_transmission: value 2.5 is out of range [0, 2]");
    EXPECT_EQ(material_error(R"({"type": "principled", "variant": "2013"})"),
              "scene.json: materials.m.variant: unknown variant '2013' (known: 2012, 2015)");
}

// The solid with specular transmission (spec_trans = 1, metallic = 0: the `glassy` material of the
// benchmark's principled scene) splits the sampled visible normal m into reflection and transmission
// by F_η(wo·m), the Fresnel factor of the two lobes, so every sample weight f·|cos θi|/pdf reduces
// to the shadowing of wi: G1(wi) for reflection, √base·G1(wi)/η'² for transmission in Radiance mode
// (√base·G1(wi) in Importance mode), η' = η(wi side)/η(wo side). The weights are therefore bounded
// by max(1, 1/η'²)·√base whatever the roughness: a lobe-selection probability that does not follow
// F (a constant split, or F at another cosine) leaves one lobe undersampled and makes weights up to
// 1/probability, which this test catches while the χ² test (density = sampler) still passes.
// Tolerance 1e-3 relative: the sampled wi is a float vector whose length differs from 1 by ~1e-7, so
// wo·h and wi·h of the recomputed half vector differ by ~1e-7/|wo + wi|; at the grazing pairs of
// the grid (wo·h ≈ 0.011) that is 2.5e-4 of the weight (measured), elsewhere below 1e-5.
TEST(PrincipledBSDF, SpecTransSampleWeightIsShadowingOnly) {
    struct Case {
        float roughness, anisotropic, eta;
    };
    const Spectrum base(0.9f, 0.95f, 1.f);
    int checked = 0, transmitted = 0;
    for (const Case& c : {Case{0.1f, 0.f, 1.5f}, Case{0.5f, 0.f, 1.5f}, Case{0.3f, 0.5f, 1.33f}}) {
        PrincipledInputs p = p2015();
        p.base_color = base;
        p.roughness = c.roughness;
        p.anisotropic = c.anisotropic;
        p.specular_transmission = 1.f;
        p.eta = c.eta;
        const PrincipledBSDF b(p);
        const GGX& d = b.specular_distribution();
        for (const BxDFContext& ctx : {kRad, kImp}) {
            for (float co : {-0.95f, -0.6f, -0.3f, -0.1f, -0.02f, 0.02f, 0.1f, 0.3f, 0.6f, 0.95f, 1.f}) {
                for (float phi : {0.f, 0.7f, 2.4f}) {
                    const Vec3f wo = dir(std::acos(co), phi);
                    const float etap = co > 0.f ? c.eta : 1.f / c.eta;
                    const int n = 24;
                    for (int k = 0; k < n * n; ++k) {
                        const Vec2f u((float(k % n) + 0.5f) / n, (float(k / n) + 0.5f) / n);
                        const float u_lobe = (float((k * 7) % (n * n)) + 0.5f) / float(n * n);
                        const auto s = b.sample(ctx, wo, u_lobe, u);
                        if (!s || s->weight.is_black()) continue;
                        const bool trans = s->wi.z * wo.z < 0.f;
                        const float g1 = d.G1(s->wi);
                        for (int ch = 0; ch < 3; ++ch) {
                            float expect = g1;
                            if (trans) {
                                expect *= std::sqrt(base[ch]);
                                if (ctx.mode == TransportMode::Radiance) expect /= etap * etap;
                            }
                            ASSERT_NEAR(s->weight[ch], expect, 1e-3f * expect)
                                << "roughness " << c.roughness << " eta " << c.eta << " cos θo " << co << " φ "
                                << phi << " k " << k << (trans ? " transmission" : " reflection");
                        }
                        ++checked, transmitted += trans;
                    }
                }
            }
        }
    }
    // Both lobes were exercised.
    EXPECT_GT(checked, 20000);
    EXPECT_GT(transmitted, checked / 4);
}
