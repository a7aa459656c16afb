// Plastic closed forms: the linear and coupled variants' directional albedo, the rough coat's
// transmittance table (smooth limit, energy bounds, cache) and agreement with Mitsuba 3.9.1.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include "pellucid/bxdf/dielectric.h"
#include "pellucid/bxdf/plastic.h"
#include "pellucid/bxdf/quadrature.h"
#include "pellucid/sampling/rng.h"

namespace pellucid {
namespace {

Vec3f dir(float c, float phi) {
    float s = std::sqrt(std::max(0.f, 1.f - c * c));
    return Vec3f(s * std::cos(phi), s * std::sin(phi), c);
}

/// F_dri = 1 − (1 − F_avg)/η², the smooth coat's internal diffuse reflectance (plastic.h).
double smooth_fdri(float eta) { return 1.0 - (1.0 - fresnel_dielectric_average(eta)) / (double(eta) * eta); }

/// ∫ f·|cos θi| dωi over the upper hemisphere of a plastic's diffuse lobe (φ-independent):
/// 2π ∫₀¹ diffuse(μo, μi) dμi by 32-point Gauss–Legendre.
Spectrum diffuse_albedo(const PlasticBase& b, float mu_o) {
    Spectrum s(0.f);
    for (int c = 0; c < 3; ++c)
        s[c] = float(2.0 * M_PI * integrate_gauss_legendre([&](double mu) { return double(b.diffuse(mu_o, float(mu))[c]); },
                                                           0.0, 1.0));
    return s;
}

// The linear variant over a smooth coat has the directional albedo ρ(θo) = Ks F(θo) + Kd (1 − F(θo))
// exactly (plastic.h), and the coupled one Ks F + (1 − F) Kd (1 − F_dri)/(1 − Kd F_dri). The specular
// part is read from sample()'s delta lobe (weight · probability), the diffuse part by quadrature.
TEST(Plastic, SmoothCoatAlbedoClosedForms) {
    const Spectrum kd(0.7f, 0.4f, 0.1f), ks(1.f, 0.8f, 0.5f);
    for (float eta : {1.49f, 1.333f})
        for (PlasticVariant v : {PlasticVariant::Linear, PlasticVariant::Coupled}) {
            SmoothPlastic p(eta, kd, ks, v);
            double fdri = smooth_fdri(eta);
            for (float mu : {1.f, 0.7f, 0.3f, 0.05f}) {
                Vec3f wo = dir(mu, 0.4f);
                auto s = p.sample(BxDFContext{}, wo, 0.f, Vec2f(0.5f));
                ASSERT_TRUE(s && s->is_specular());
                Spectrum spec = s->weight * s->pdf;
                Spectrum diff = diffuse_albedo(p.base(), mu);
                float F = fresnel_dielectric(mu, eta);
                for (int c = 0; c < 3; ++c) {
                    double escape = v == PlasticVariant::Linear ? 1.0 : (1.0 - fdri) / (1.0 - kd[c] * fdri);
                    EXPECT_NEAR(spec[c], ks[c] * F, 1e-6) << to_string(v) << " eta=" << eta << " mu=" << mu;
                    EXPECT_NEAR(diff[c], kd[c] * (1.0 - F) * escape, 1e-5)
                        << to_string(v) << " eta=" << eta << " mu=" << mu << " ch=" << c;
                }
            }
        }
    // Normal incidence, in numbers: the linear diffuse albedo is Kd (1 − ((η − 1)/(η + 1))²).
    SmoothPlastic lin(1.5f, Spectrum(0.5f), Spectrum(1.f), PlasticVariant::Linear);
    EXPECT_NEAR(diffuse_albedo(lin.base(), 1.f).r, 0.5 * (1.0 - 0.04), 1e-5);
}

// The linear variant is Mitsuba's nonlinear = false formula Kd/(1 − F_dri) (1/η²)(1 − F(θi))(1 − F(θo))
// cos θi/π. Mitsuba computes F_dri with the Egan–Hilgeman fit (its fresnel_diffuse_reflectance at
// 1/η); ours is the exact quadrature. At η = 1.49 they differ by 4.9e-4, i.e. 0.12 % of the diffuse.
TEST(Plastic, LinearIsMitsubasFormula) {
    const float eta = 1.49f;
    const Spectrum kd(0.6f, 0.3f, 0.9f);
    SmoothPlastic p(eta, kd, Spectrum(1.f), PlasticVariant::Linear);
    double fdri = smooth_fdri(eta);
    PCG32 rng(5, 3);
    for (int k = 0; k < 100; ++k) {
        Vec3f wo = dir(rng.next_float(), 6.f * rng.next_float()), wi = dir(rng.next_float(), 6.f * rng.next_float());
        Spectrum f = p.eval(BxDFContext{}, wo, wi);
        double t = (1.0 - fresnel_dielectric(wo.z, eta)) * (1.0 - fresnel_dielectric(wi.z, eta));
        for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(f[c], kd[c] / (1.0 - fdri) * t / (eta * eta) * wi.z / M_PI, 1e-6 * (1.0 + f[c]));
    }
    double x = 1.0 / eta;  // Egan & Hilgeman 1979 fit of the internal diffuse reflectance, x = 1/η < 1
    double fit = 0.0636 / x + x * (-1.4399 * x + 0.7099) + 0.6681;
    EXPECT_NEAR(fdri, 0.590246, 1e-6);
    EXPECT_NEAR(fit, 0.590732, 1e-6);
    EXPECT_LT(std::fabs((1.0 - fit) / (1.0 - fdri) - 1.0), 1.3e-3);
}

// As α → 0 the rough coat's table tends to the smooth values. At the smallest α (1e-4) the nodes
// μ_j ≥ 1/63 agree with 1 − F within 3e-5 (η > 1; 1e-4 for η < 1, where even this α blurs the √
// onset of 1 − F at the critical cosine, 0.66 here), and R̄ with F_dri within 1e-5; off the nodes,
// linear interpolation adds up to 7.2e-4 for η > 1 (μ ≥ 0.063).
template <class D>
void check_smooth_limit(SmithShadowing g) {
    for (float eta : {1.49f, 1.f / 1.333f}) {
        D d(1e-4f, 1e-4f, g);
        RoughCoatTable t = RoughCoatTable::compute(d, eta);
        std::string what = d.to_string() + " " + to_string(g) + " eta=" + std::to_string(eta);
        EXPECT_NEAR(t.internal_reflectance(), smooth_fdri(eta), 1e-5) << what;
        for (int j = 1; j < RoughCoatTable::kSize; ++j) {
            float mu = float(j) / float(RoughCoatTable::kSize - 1);
            EXPECT_NEAR(t.transmittance(mu), 1.f - fresnel_dielectric(mu, eta), eta > 1.f ? 3e-5f : 1e-4f)
                << what << " mu=" << mu;
        }
        if (eta > 1.f)
            for (int i = 63; i <= 1000; i += 7) {
                float mu = float(i) / 1000.f;
                EXPECT_NEAR(t.transmittance(mu), 1.f - fresnel_dielectric(mu, eta), 7.5e-4f) << what << " mu=" << mu;
            }
    }
}
TEST(RoughCoatTable, TendsToTheSmoothValuesAsAlphaVanishes) {
    for (SmithShadowing g : {SmithShadowing::HeightCorrelated, SmithShadowing::Separable}) {
        check_smooth_limit<GGX>(g);
        check_smooth_limit<Beckmann>(g);
    }
}

// A single-scattering coat only loses energy: from outside, coat reflectance + t(μ) ≤ 1; from inside,
// R̄ + T̄_int ≤ 1 with T̄_int = 2∫t(μ)μ dμ/η² (reciprocity of the transmission lobe). The coat's
// reflectance is estimated by sampling its lobe (bounds checked at 5 standard errors).
template <class D>
void check_energy_bounds(SmithShadowing g) {
    const float eta = 1.5f;
    for (float a : {0.1f, 0.5f, 1.f}) {
        D d(a, a, g);
        RoughCoatTable t = RoughCoatTable::compute(d, eta);
        std::string what = d.to_string();
        MicrofacetReflection<D, DielectricFresnel> coat(d, DielectricFresnel{eta});
        for (float mu : {1.f, 0.5f, 0.1f, 0.02f}) {
            PCG32 rng(13, 1);
            double s = 0.0, s2 = 0.0;
            const int n = 40000;
            for (int k = 0; k < n; ++k) {
                auto smp = coat.sample(BxDFContext{}, dir(mu, 0.f), 0.5f, rng.next_2d());
                double w = smp ? smp->weight.r : 0.0;
                s += w;
                s2 += w * w;
            }
            double e = s / n, se = std::sqrt(std::max(0.0, s2 / n - e * e) / n);
            EXPECT_LE(e + t.transmittance(mu), 1.0 + 5.0 * se + 1e-4) << what << " mu=" << mu;
        }
        double tbar = 2.0 * integrate_gauss_legendre([&](double mu) { return t.transmittance(float(mu)) * mu; }, 0.0, 1.0);
        EXPECT_LE(t.internal_reflectance() + tbar / (eta * eta), 1.0 + 1e-3) << what;
        EXPECT_GT(t.internal_reflectance(), 0.f) << what;
    }
}
TEST(RoughCoatTable, SingleScatteringOnlyLosesEnergy) {
    for (SmithShadowing g : {SmithShadowing::HeightCorrelated, SmithShadowing::Separable}) {
        check_energy_bounds<GGX>(g);
        check_energy_bounds<Beckmann>(g);
    }
}

// Mitsuba 3.9.1's roughplastic (η = 1.49, separable G), read through its BSDF eval (scalar_rgb):
// t(μ) at μ = 1, 0.8, 0.5, 0.2, 0.05 and its R̄. t agrees within 7e-4 (the two quadratures; Mitsuba's
// Beckmann G1 is a rational fit, microfacet.h). Mitsuba's R̄ is 2 × the mean of R_int(μ_j) μ_j over
// its 64 nodes, a rectangle rule that weights each node 1/64 where the trapezoid rule on the same
// nodes has 1/63: it comes out 63/64 of the integral (within 2e-3), about 1.5 % below ours, so
// Mitsuba's linear diffuse is 1.0–2.1 % darker at these four (docs/materials.md, Plastic).
struct MitsubaCoat {
    const char* distribution;
    float alpha, rbar, t[5];
};
const MitsubaCoat kMitsuba[] = {
    {"beckmann", 0.1f, 0.574662f, {0.961591f, 0.957313f, 0.911020f, 0.681436f, 0.443899f}},
    {"beckmann", 0.3f, 0.523425f, {0.961369f, 0.953685f, 0.903271f, 0.784563f, 0.706520f}},
    {"ggx", 0.1f, 0.545523f, {0.961159f, 0.955351f, 0.908429f, 0.717299f, 0.576355f}},
    {"ggx", 0.3f, 0.408760f, {0.954805f, 0.940894f, 0.888114f, 0.772410f, 0.679824f}},
};
TEST(RoughCoatTable, MatchesMitsubasTable) {
    const float mus[5] = {1.f, 0.8f, 0.5f, 0.2f, 0.05f};
    for (const MitsubaCoat& m : kMitsuba) {
        bool beck = std::string(m.distribution) == "beckmann";
        RoughCoatTable t = beck ? RoughCoatTable::compute(Beckmann(m.alpha, m.alpha, SmithShadowing::Separable), 1.49f)
                                : RoughCoatTable::compute(GGX(m.alpha, m.alpha, SmithShadowing::Separable), 1.49f);
        for (int i = 0; i < 5; ++i)
            EXPECT_NEAR(t.transmittance(mus[i]), m.t[i], 7e-4f) << m.distribution << " " << m.alpha << " mu=" << mus[i];
        EXPECT_NEAR(m.rbar / t.internal_reflectance(), 63.0 / 64.0, 2e-3) << m.distribution << " " << m.alpha;
    }
}

// Whole-lobe check against Mitsuba 3.9.1 (roughplastic, nonlinear = false, Kd = 0.6, η = 1.49): its
// eval of the glossy component and of the diffuse component at three direction pairs (Mitsuba's
// si.wi is our wo; both include cos θi). Glossy agrees within 0.8 % (Beckmann: Mitsuba's rational G1,
// up to 0.35 % per G1); diffuse, once Mitsuba's R̄ is put in place of ours, within 0.2 %.
TEST(RoughPlastic, LinearRoughCoatMatchesMitsubasEval) {
    struct Pair {
        float co, po, ci, pi, spec[2], diff[2];  // [beckmann 0.3, ggx 0.1]
    };
    const Pair pairs[] = {{0.9f, 0.2f, 0.7f, 2.9f, {2.502107e-02f, 1.007253e-02f}, {1.143695e-01f, 1.204248e-01f}},
                          {0.3f, 0.0f, 0.8f, 3.3f, {6.650967e-02f, 1.362654e-02f}, {1.144045e-01f, 1.167812e-01f}},
                          {0.6f, 1.0f, 0.15f, 4.0f, {7.180351e-02f, 1.883015e-02f}, {1.907646e-02f, 1.757699e-02f}}};
    const float eta = 1.49f, rbar_mitsuba[2] = {0.523425f, 0.545523f};
    Beckmann beck(0.3f, 0.3f, SmithShadowing::Separable);
    GGX ggx(0.1f, 0.1f, SmithShadowing::Separable);
    RoughPlastic<Beckmann> pb(beck, eta, Spectrum(0.6f), Spectrum(1.f), PlasticVariant::Linear, CoatTransmittance::Rough);
    RoughPlastic<GGX> pg(ggx, eta, Spectrum(0.6f), Spectrum(1.f), PlasticVariant::Linear, CoatTransmittance::Rough);
    MicrofacetReflection<Beckmann, DielectricFresnel> cb(beck, DielectricFresnel{eta});
    MicrofacetReflection<GGX, DielectricFresnel> cg(ggx, DielectricFresnel{eta});
    for (const Pair& p : pairs) {
        Vec3f wo = dir(p.co, p.po), wi = dir(p.ci, p.pi);
        float spec[2] = {cb.eval({}, wo, wi).r, cg.eval({}, wo, wi).r};
        float total[2] = {pb.eval({}, wo, wi).r, pg.eval({}, wo, wi).r};
        const PlasticBase* base[2] = {&pb.base(), &pg.base()};
        for (int k = 0; k < 2; ++k) {
            EXPECT_NEAR(spec[k] / p.spec[k], 1.0, 8e-3) << k << " wo=" << to_string(wo);
            double diff = base[k]->diffuse(wo.z, wi.z).r;
            double rescale = (1.0 - base[k]->internal_reflectance()) / (1.0 - rbar_mitsuba[k]);
            EXPECT_NEAR(diff * rescale / p.diff[k], 1.0, 2e-3) << k << " wo=" << to_string(wo);
            // The plastic's glossy lobe is the coat's: eval = coat + diffuse.
            EXPECT_NEAR(total[k], spec[k] + diff, 1e-6);
        }
    }
}

// The table against an independent estimate: the transmitted (from outside) and reflected (from
// inside) energy of the rough dielectric BxDF with the same distribution, by sampling it in
// Importance mode (no η² factor), over random azimuths of wo (the table averages the azimuth of an
// anisotropic coat). t at three nodes, and R̄ with cosine-weighted μ (R̄ = E[R_int(μ)], p(μ) = 2μ).
// Bounds: 5 standard errors + 5e-4 (the quadrature).
template <class D>
void check_against_rough_dielectric(const D& d, float eta) {
    RoughCoatTable table = RoughCoatTable::compute(d, eta);
    RoughDielectric<D> glass(d, eta);
    const BxDFContext ctx{TransportMode::Importance, BxDFFlags::All};
    auto estimate = [&](auto&& draw_wo, bool transmitted, double* se) {
        PCG32 rng(31, 7);
        const int n = 200000;
        double s = 0.0, s2 = 0.0;
        for (int k = 0; k < n; ++k) {
            Vec3f wo = draw_wo(rng);
            float ul = rng.next_float();
            auto smp = glass.sample(ctx, wo, ul, rng.next_2d());
            double w = smp && has_flag(smp->lobe, BxDFFlags::Transmission) == transmitted ? smp->weight.r : 0.0;
            s += w;
            s2 += w * w;
        }
        double m = s / n;
        *se = std::sqrt(std::max(0.0, s2 / n - m * m) / n);
        return m;
    };
    for (int j : {57, 32, 10}) {
        float mu = float(j) / float(RoughCoatTable::kSize - 1);
        double se, t = estimate([&](PCG32& r) { return dir(mu, 2.f * kPi * r.next_float()); }, true, &se);
        EXPECT_NEAR(table.transmittance(mu), t, 5.0 * se + 5e-4) << d.to_string() << " mu=" << mu;
    }
    double se, rbar = estimate([&](PCG32& r) { return -dir(std::sqrt(r.next_float()), 2.f * kPi * r.next_float()); },
                               false, &se);
    EXPECT_NEAR(table.internal_reflectance(), rbar, 5.0 * se + 5e-4) << d.to_string();
}
TEST(RoughCoatTable, AgreesWithTheRoughDielectric) {
    check_against_rough_dielectric(GGX(0.3f, 0.3f, SmithShadowing::Separable), 1.49f);
    check_against_rough_dielectric(GGX(0.1f, 0.4f), 1.5f);
    check_against_rough_dielectric(Beckmann(0.5f), 1.33f);
    check_against_rough_dielectric(Beckmann(0.4f, 0.15f, SmithShadowing::Separable), 1.6f);
}

// get() builds one table per key and hands out the same object afterwards; matches() tells a table
// built for other parameters apart (what RoughPlastic checks before reusing a table).
TEST(RoughCoatTable, CacheAndKey) {
    GGX a(0.2f, 0.2f, SmithShadowing::Separable), b(0.2f, 0.2f);
    const RoughCoatTable& ta = RoughCoatTable::get(a, 1.5f);
    EXPECT_EQ(&ta, &RoughCoatTable::get(a, 1.5f));
    EXPECT_NE(&ta, &RoughCoatTable::get(b, 1.5f));
    EXPECT_NE(&ta, &RoughCoatTable::get(a, 1.4f));
    EXPECT_TRUE(ta.matches(a, 1.5f));
    EXPECT_FALSE(ta.matches(b, 1.5f));
    EXPECT_FALSE(ta.matches(a, 1.4f));
    EXPECT_FALSE(ta.matches(GGX(0.21f, 0.2f, SmithShadowing::Separable), 1.5f));
    EXPECT_FALSE(ta.matches(Beckmann(0.2f, 0.2f, SmithShadowing::Separable), 1.5f));
    // A BxDF handed a matching table uses it; a mismatched one is replaced by the right table; the
    // smooth transmittance, an effectively smooth coat and the sum variant use none.
    RoughPlastic<GGX> p(a, 1.5f, Spectrum(0.5f), Spectrum(1.f), PlasticVariant::Linear, CoatTransmittance::Rough, &ta);
    EXPECT_EQ(p.base().coat_table(), &ta);
    RoughPlastic<GGX> q(b, 1.5f, Spectrum(0.5f), Spectrum(1.f), PlasticVariant::Linear, CoatTransmittance::Rough, &ta);
    EXPECT_EQ(q.base().coat_table(), &RoughCoatTable::get(b, 1.5f));
    EXPECT_EQ(RoughPlastic<GGX>(a, 1.5f).base().coat_table(), nullptr);
    EXPECT_EQ(RoughPlastic<GGX>(GGX(5e-4f), 1.5f, Spectrum(0.5f), Spectrum(1.f), PlasticVariant::Linear,
                                CoatTransmittance::Rough)
                  .base()
                  .coat_table(),
              nullptr);
    EXPECT_EQ(RoughPlastic<GGX>(a, 1.5f, Spectrum(0.5f), Spectrum(1.f), PlasticVariant::Sum, CoatTransmittance::Rough)
                  .base()
                  .coat_table(),
              nullptr);
}
}  // namespace
}  // namespace pellucid
