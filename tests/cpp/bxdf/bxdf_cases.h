// Parameter sets for the BxDF property suite: one BxDFCases<T> specialisation per alternative of
// `BxDF` (a missing specialisation is a compile error, so a new model cannot skip the suite).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "pellucid/bxdf/bxdf.h"
#include "pellucid/bxdf/ior.h"

namespace pellucid::test {

/// Incident directions with generic azimuths and cosines, so that delta directions never fall on
/// a χ² bin edge.
inline Vec3f dir(float cos_theta, float phi) {
    float s = std::sqrt(std::max(0.f, 1.f - cos_theta * cos_theta));
    return Vec3f(s * std::cos(phi), s * std::sin(phi), cos_theta);
}
inline std::vector<Vec3f> wo_front() { return {dir(0.83f, 0.31f), dir(0.27f, 2.23f)}; }
inline std::vector<Vec3f> wo_both() { return {dir(0.83f, 0.31f), dir(0.27f, 2.23f), dir(-0.61f, 4.1f)}; }

template <class T>
struct Case {
    std::string name;
    T bxdf;
    std::vector<Vec3f> wos = wo_front();
    TransportMode mode = TransportMode::Radiance;
    bool lossless = false;  ///< white furnace must give 1 (within furnace_tol + 5 SE)
    float furnace_tol = 1e-5f;
    bool chi2 = true;
    /// false: reciprocity is checked only where f(wo, wi) and f(wi, wo) are both non-zero (a lobe
    /// whose support is not symmetric in wo and wi, e.g. PrincipledBSDF's thin transmission).
    bool symmetric_support = true;
};

template <class T>
struct BxDFCases;  // static std::vector<Case<T>> cases(); static std::vector<T> sweep();

// Parameter grids of the stability sweep (REFERENCE.md §7.2).
inline const std::vector<float>& sweep_alphas() {
    static const std::vector<float> v{0.f, 1e-6f, 1e-4f, 1e-3f, 1e-2f, 0.1f, 0.5f, 1.f};
    return v;
}
inline const std::vector<float>& sweep_etas() {
    static const std::vector<float> v{1.f, 1.0001f, 0.9999f, 1.33f, 1.5f, 1.f / 1.5f, 2.42f};
    return v;
}
inline const std::vector<float>& sweep_reflectances() {
    static const std::vector<float> v{0.f, 1.f};
    return v;
}

inline ConductorFresnel metal(const char* name) {
    ConductorIOR c = conductor_ior(name);
    return ConductorFresnel{c.eta, c.k};
}

template <>
struct BxDFCases<Lambertian> {
    static std::vector<Case<Lambertian>> cases() {
        Case<Lambertian> white{"white", Lambertian(Spectrum(1.f))};
        white.lossless = true;
        return {{"albedo0.7", Lambertian(Spectrum(0.7f, 0.5f, 0.3f))}, white};
    }
    static std::vector<Lambertian> sweep() { return {Lambertian(Spectrum(0.f)), Lambertian(Spectrum(1.f))}; }
};

template <>
struct BxDFCases<OrenNayar> {
    static std::vector<Case<OrenNayar>> cases() {
        Case<OrenNayar> eon_white{"eon_white_r1", OrenNayar(Spectrum(1.f), 1.f, OrenNayarVariant::EON)};
        eon_white.lossless = true;
        eon_white.furnace_tol = 1e-4f;
        eon_white.chi2 = false;
        return {{"classic_sigma0.5", OrenNayar(Spectrum(0.8f), 0.5f, OrenNayarVariant::Classic)},
                {"eon_r0.7", OrenNayar(Spectrum(0.9f, 0.6f, 0.3f), 0.7f, OrenNayarVariant::EON)},
                eon_white};
    }
    static std::vector<OrenNayar> sweep() {
        std::vector<OrenNayar> v;
        for (float r : sweep_reflectances())
            for (float s : {0.f, 1e-4f, 0.5f, 1.f, 10.f}) {
                v.emplace_back(Spectrum(r), s, OrenNayarVariant::Classic);
                v.emplace_back(Spectrum(r), s, OrenNayarVariant::EON);
            }
        return v;
    }
};

template <>
struct BxDFCases<SmoothConductor<ConductorFresnel>> {
    using T = SmoothConductor<ConductorFresnel>;
    static std::vector<Case<T>> cases() {
        Case<T> white{"none", T(metal("none"))};
        white.lossless = true;
        white.chi2 = false;
        return {{"Au", T(metal("Au"))}, white};
    }
    static std::vector<T> sweep() {
        std::vector<T> v;
        for (float k : {0.f, 1e3f})
            for (float eta : sweep_etas()) v.emplace_back(ConductorFresnel{Spectrum(eta), Spectrum(k)});
        return v;
    }
};

template <class D>
struct BxDFCases<MicrofacetReflection<D, ConductorFresnel>> {
    using T = MicrofacetReflection<D, ConductorFresnel>;
    static std::vector<Case<T>> cases() {
        std::vector<Case<T>> c{{"Cu_iso0.3", T(D(0.3f), metal("Cu"))},
                               {"Al_aniso0.15x0.45", T(D(0.15f, 0.45f), metal("Al"))},
                               {"Au_separable0.4x0.2", T(D(0.4f, 0.2f, SmithShadowing::Separable), metal("Au"))}};
        if constexpr (std::is_same_v<D, GGX>) {
            c.push_back({"Au_ms_alpha0.6", T(D(0.6f), metal("Au"), Spectrum(1.f), true)});
            for (float a : {0.5f, 1.f}) {
                Case<T> w{"white_ms_alpha" + std::to_string(a), T(D(a), metal("none"), Spectrum(1.f), true)};
                w.lossless = true;
                w.furnace_tol = 3e-3f;  // table interpolation error of E(μ, α) (test_kulla_conty.cpp)
                w.chi2 = a == 1.f;
                c.push_back(w);
            }
        }
        return c;
    }
    static std::vector<T> sweep() {
        std::vector<T> v;
        for (float a : sweep_alphas())
            for (float k : {0.f, 1e3f})
                for (float eta : {1.f, 1.5f, 0.2f})
                    for (bool ms : {false, true}) v.emplace_back(D(a, 0.5f * a), ConductorFresnel{Spectrum(eta), Spectrum(k)}, Spectrum(1.f), ms);
        for (float a : sweep_alphas())
            v.emplace_back(D(a, 0.5f * a, SmithShadowing::Separable), ConductorFresnel{Spectrum(1.5f), Spectrum(0.f)});
        return v;
    }
};

template <>
struct BxDFCases<SmoothDielectric> {
    static std::vector<Case<SmoothDielectric>> cases() {
        Case<SmoothDielectric> glass{"glass_importance", SmoothDielectric(1.5f)};
        glass.wos = {dir(0.83f, 0.31f), dir(0.27f, 2.23f), dir(-0.61f, 4.1f), dir(-0.85f, 1.f)};
        glass.mode = TransportMode::Importance;
        glass.lossless = true;
        Case<SmoothDielectric> water{"water_radiance", SmoothDielectric(1.333f)};
        water.wos = wo_both();
        return {glass, water};
    }
    static std::vector<SmoothDielectric> sweep() {
        std::vector<SmoothDielectric> v;
        for (float eta : sweep_etas()) v.emplace_back(eta);
        return v;
    }
};

template <>
struct BxDFCases<ThinDielectric> {
    static std::vector<Case<ThinDielectric>> cases() {
        Case<ThinDielectric> c{"thin1.5", ThinDielectric(1.5f)};
        c.wos = wo_both();
        c.lossless = true;
        return {c};
    }
    static std::vector<ThinDielectric> sweep() {
        std::vector<ThinDielectric> v;
        for (float eta : sweep_etas()) v.emplace_back(eta);
        return v;
    }
};

template <class D>
struct BxDFCases<RoughDielectric<D>> {
    using T = RoughDielectric<D>;
    static std::vector<Case<T>> cases() {
        Case<T> a{"eta1.5_alpha0.3", T(D(0.3f), 1.5f)};
        a.wos = wo_both();
        Case<T> b{"eta1.33_aniso_importance", T(D(0.2f, 0.5f), 1.333f)};
        b.wos = wo_both();
        b.mode = TransportMode::Importance;
        Case<T> sep{"eta1.5_separable0.4x0.25", T(D(0.4f, 0.25f, SmithShadowing::Separable), 1.5f)};
        sep.wos = wo_both();
        std::vector<Case<T>> c{a, b, sep};
        if constexpr (std::is_same_v<D, Beckmann>) {
            Case<T> inv{"eta1/1.5_alpha0.6", T(D(0.6f), 1.f / 1.5f)};
            inv.wos = wo_both();
            c.push_back(inv);
        } else {
            // Kulla–Conty: R+T = 1 from both sides, within the tables' error (test_kulla_conty_dielectric.cpp).
            Case<T> w{"white_ms_eta1.5_alpha0.6", T(D(0.6f), 1.5f, Spectrum(1.f), Spectrum(1.f), true)};
            w.wos = wo_both();
            w.mode = TransportMode::Importance;
            w.lossless = true;
            w.furnace_tol = 3e-3f;
            Case<T> w2{"white_ms_eta1/1.33_alpha0.8", T(D(0.8f), 1.f / 1.333f, Spectrum(1.f), Spectrum(1.f), true)};
            w2.wos = wo_both();
            w2.lossless = true;
            w2.furnace_tol = 3e-3f;
            w2.chi2 = false;
            // Anisotropic α reads the isotropic table at √(αx αy): compensation is approximate
            // (furnace 0.96–1.00 at 2:1, dielectric.h), so this case is not lossless.
            Case<T> w3{"ms_aniso0.8x0.4_eta1.33", T(D(0.8f, 0.4f), 1.333f, Spectrum(1.f), Spectrum(1.f), true)};
            w3.wos = wo_both();
            w3.chi2 = false;
            c.push_back(w);
            c.push_back(w2);
            c.push_back(w3);
        }
        return c;
    }
    static std::vector<T> sweep() {
        std::vector<T> v;
        for (float a : sweep_alphas())
            for (float eta : sweep_etas())
                for (bool ms : {false, true}) v.emplace_back(D(a), eta, Spectrum(1.f), Spectrum(1.f), ms);
        for (float a : sweep_alphas())
            for (float eta : {1.5f, 1.f / 1.5f}) v.emplace_back(D(a, a, SmithShadowing::Separable), eta);
        return v;
    }
};

template <>
struct BxDFCases<SmoothPlastic> {
    static std::vector<Case<SmoothPlastic>> cases() {
        Case<SmoothPlastic> white{"coupled_white", SmoothPlastic(1.5f, Spectrum(1.f), Spectrum(1.f))};
        white.lossless = true;
        white.furnace_tol = 1e-4f;  // quadrature of F_avg (1e-6) and float sums
        white.chi2 = false;
        // Linear: albedo Ks F + Kd (1 − F) (plastic.h), so 1 for Kd = Ks = 1.
        Case<SmoothPlastic> lin_white{"linear_white",
                                      SmoothPlastic(1.49f, Spectrum(1.f), Spectrum(1.f), PlasticVariant::Linear)};
        lin_white.lossless = true;
        lin_white.furnace_tol = 1e-4f;
        lin_white.chi2 = false;
        return {{"coupled", SmoothPlastic(1.49f, Spectrum(0.2f, 0.5f, 0.8f), Spectrum(1.f))},
                {"sum", SmoothPlastic(1.5f, Spectrum(0.5f), Spectrum(0.5f), PlasticVariant::Sum)},
                {"linear", SmoothPlastic(1.49f, Spectrum(0.8f, 0.45f, 0.15f), Spectrum(0.9f), PlasticVariant::Linear)},
                white, lin_white};
    }
    static std::vector<SmoothPlastic> sweep() {
        std::vector<SmoothPlastic> v;
        for (float eta : sweep_etas())
            for (float r : sweep_reflectances())
                for (auto var : {PlasticVariant::Coupled, PlasticVariant::Sum, PlasticVariant::Linear})
                    v.emplace_back(eta, Spectrum(r), Spectrum(1.f - r), var);
        return v;
    }
};

template <class D>
struct BxDFCases<RoughPlastic<D>> {
    using T = RoughPlastic<D>;
    static std::vector<Case<T>> cases() {
        const auto sep = SmithShadowing::Separable;
        const auto rough = CoatTransmittance::Rough;
        // The rough coat's table with white Kd = Ks = 1: a single-scattering coat loses energy at
        // large α, so these are checked for E ≤ 1 only (test_plastic.cpp has the closed forms).
        Case<T> white{"coupled_rough_white_alpha0.6",
                      T(D(0.6f), 1.5f, Spectrum(1.f), Spectrum(1.f), PlasticVariant::Coupled, rough)};
        white.chi2 = false;
        Case<T> lin_white{"linear_rough_separable_white_alpha0.3",
                          T(D(0.3f, 0.3f, sep), 1.49f, Spectrum(1.f), Spectrum(1.f), PlasticVariant::Linear, rough)};
        lin_white.chi2 = false;
        return {{"coupled_alpha0.2", T(D(0.2f), 1.49f, Spectrum(0.2f, 0.5f, 0.8f), Spectrum(1.f))},
                {"sum_alpha0.4", T(D(0.4f), 1.5f, Spectrum(0.5f), Spectrum(0.5f), PlasticVariant::Sum)},
                {"linear_alpha0.15", T(D(0.15f), 1.49f, Spectrum(0.8f, 0.45f, 0.15f), Spectrum(1.f), PlasticVariant::Linear)},
                {"linear_rough_separable_alpha0.3",
                 T(D(0.3f, 0.3f, sep), 1.49f, Spectrum(0.15f, 0.45f, 0.8f), Spectrum(1.f), PlasticVariant::Linear, rough)},
                {"coupled_rough_alpha0.5",
                 T(D(0.5f), 1.6f, Spectrum(0.6f, 0.4f, 0.2f), Spectrum(0.7f), PlasticVariant::Coupled, rough)},
                white, lin_white};
    }
    static std::vector<T> sweep() {
        std::vector<T> v;
        for (float a : sweep_alphas())
            for (float eta : sweep_etas())
                for (float r : sweep_reflectances()) v.emplace_back(D(a), eta, Spectrum(r), Spectrum(1.f));
        // The rough coat's table (built once per (α, η): a subset of the grid keeps the sweep fast).
        for (float a : {1e-3f, 0.1f, 1.f})
            for (float eta : {1.f, 1.5f, 1.f / 1.5f, 2.42f})
                for (auto var : {PlasticVariant::Coupled, PlasticVariant::Linear})
                    v.emplace_back(D(a, a, SmithShadowing::Separable), eta, Spectrum(1.f), Spectrum(1.f), var,
                                   CoatTransmittance::Rough);
        return v;
    }
};

template <>
struct BxDFCases<Principled> {
    static PrincipledInputs params(float metallic, float rough, float cc, float sheen, float aniso) {
        PrincipledInputs p;
        p.base_color = Spectrum(0.6f, 0.3f, 0.15f);
        p.metallic = metallic;
        p.roughness = rough;
        p.clearcoat = cc;
        p.clearcoat_gloss = 0.7f;
        p.sheen = sheen;
        p.anisotropic = aniso;
        return p;
    }
    static std::vector<Case<Principled>> cases() {
        return {{"dielectric_clearcoat_sheen", Principled(params(0.f, 0.6f, 1.f, 0.5f, 0.f))},
                {"metal_aniso", Principled(params(1.f, 0.5f, 0.f, 0.f, 0.8f))},
                {"mixed", Principled(params(0.5f, 0.8f, 0.3f, 0.f, 0.3f))}};
    }
    static std::vector<Principled> sweep() {
        std::vector<Principled> v;
        for (float r : {0.f, 1e-3f, 0.5f, 1.f})
            for (float m : {0.f, 1.f})
                for (float c : {0.f, 1.f}) {
                    PrincipledInputs p = params(m, r, c, 1.f, 1.f);
                    p.clearcoat_gloss = 1.f;
                    v.emplace_back(p);
                    p.base_color = Spectrum(0.f);
                    p.sheen = 0.f;
                    v.emplace_back(p);
                }
        return v;
    }
};

// Disney 2015 BSDF (solid and thin). Base colours ≤ 0.6 where the model would otherwise exceed a
// white furnace of 1 (principled_bsdf.h, "Energy").
template <>
struct BxDFCases<PrincipledBSDF> {
    static PrincipledInputs params(float metallic, float rough, float spec_trans, float eta) {
        PrincipledInputs p;
        p.variant = PrincipledVariant::Burley2015;
        p.base_color = Spectrum(0.6f, 0.3f, 0.15f);
        p.metallic = metallic;
        p.roughness = rough;
        p.specular_transmission = spec_trans;
        p.eta = eta;
        return p;
    }
    static std::vector<Case<PrincipledBSDF>> cases() {
        PrincipledInputs a = params(0.f, 0.6f, 0.f, 0.f);
        a.clearcoat = 1.f;
        a.clearcoat_gloss = 0.7f;
        a.sheen = 0.5f;
        a.sheen_tint = 0.5f;
        a.flatness = 0.5f;
        PrincipledInputs glass = params(0.f, 0.5f, 1.f, 1.5f);  // α = 0.25: resolved by the χ² cells
        glass.base_color = Spectrum(0.9f, 0.8f, 0.6f);
        PrincipledInputs mixed = params(0.3f, 0.5f, 0.6f, 1.f / 1.33f);
        mixed.anisotropic = 0.5f;
        mixed.specular_tint = 0.5f;
        mixed.clearcoat = 0.5f;
        // α_c = 0.05: at gloss 1 (α_c = 0.001) the clear coat's pdf is so peaked that the ~1e-7
        // direction change of a frame round trip (the bumped suite) moves it by more than 1e-3.
        mixed.clearcoat_gloss = 0.5f;
        PrincipledInputs metal = params(1.f, 0.4f, 0.f, 0.f);
        metal.base_color = Spectrum(0.9f, 0.6f, 0.3f);
        metal.anisotropic = 0.8f;
        // Thin: the specular transmission (support not symmetric) without diffuse transmission, so
        // that reciprocity sees it alone; diffuse transmission in the second case.
        PrincipledInputs thin = params(0.f, 0.5f, 0.5f, 1.5f);
        thin.thin = true;
        thin.sheen = 0.3f;
        thin.specular_tint = 0.4f;
        thin.anisotropic = 0.3f;
        PrincipledInputs thin_diffuse = params(0.f, 0.7f, 0.f, 1.33f);
        thin_diffuse.thin = true;
        thin_diffuse.diffuse_transmission = 1.2f;
        thin_diffuse.flatness = 0.5f;

        Case<PrincipledBSDF> c_glass{"2015_glass_eta1.5", PrincipledBSDF(glass)};
        c_glass.wos = wo_both();
        Case<PrincipledBSDF> c_glass_imp{"2015_glass_importance", PrincipledBSDF(glass)};
        c_glass_imp.wos = wo_both();
        c_glass_imp.mode = TransportMode::Importance;
        Case<PrincipledBSDF> c_mixed{"2015_mixed_eta1/1.33", PrincipledBSDF(mixed)};
        c_mixed.wos = wo_both();
        Case<PrincipledBSDF> c_thin{"2015_thin", PrincipledBSDF(thin)};
        c_thin.wos = wo_both();
        c_thin.symmetric_support = false;
        Case<PrincipledBSDF> c_thin_d{"2015_thin_diffuse", PrincipledBSDF(thin_diffuse)};
        c_thin_d.wos = wo_both();
        return {{"2015_clearcoat_sheen_flatness", PrincipledBSDF(a)},
                {"2015_metal_aniso", PrincipledBSDF(metal)},
                c_glass, c_glass_imp, c_mixed, c_thin, c_thin_d};
    }
    static std::vector<PrincipledBSDF> sweep() {
        std::vector<PrincipledBSDF> v;
        for (bool thin : {false, true})
            for (float r : {0.f, 1e-3f, 0.5f, 1.f})
                for (float m : {0.f, 1.f})
                    for (float st : {0.f, 0.5f, 1.f})
                        for (float eta : sweep_etas()) {
                            PrincipledInputs p = params(m, r, st, eta);
                            p.thin = thin;
                            p.clearcoat = 1.f;
                            p.sheen = 1.f;
                            p.flatness = 0.5f;
                            p.anisotropic = r == 0.5f ? 1.f : 0.f;
                            p.diffuse_transmission = thin ? 1.f : 0.f;
                            v.emplace_back(p);
                            p.base_color = Spectrum(m == 0.f ? 1.f : 0.f);
                            p.specular_tint = 1.f;
                            v.emplace_back(p);
                        }
        return v;
    }
};

/// Every alternative of a std::variant of BxDFs, as a gtest type list for the typed suites, and
/// sums over the alternatives' parameter sets (the suites count their χ² runs with it, for the
/// Šidák correction).
template <class V>
struct VariantTypes;
template <class... Ts>
struct VariantTypes<std::variant<Ts...>> {
    using type = ::testing::Types<Ts...>;
    /// Σ over the alternatives T of count(BxDFCases<T>::cases()).
    template <class F>
    static int sum_over_cases(F&& count) {
        return (0 + ... + count(BxDFCases<Ts>::cases()));
    }
};
}  // namespace pellucid::test
