// Emitted power: Monte-Carlo integrals of each light's emission against power(), and the delta
// lights' sample semantics.
//
// Finite lights: all light leaving the emitter crosses an enclosing sphere S (radius R) exactly
// once, so Φ = ∫_S ∫ L(x ← ω) (n_in·ω) dω dA(x). Points x are uniform on S (pdf 1/4πR²) and ω
// comes from the light's own sample_li (its radiance and pdf), so radiance, sampling density and
// power() must agree. Lights at infinity: ∫ L̄ dω over the sphere of directions, by uniform sphere
// sampling (independent of the light's sampler) and by sample_li.
//
// Bound: each estimate must lie within z·SE of power(), z for a two-sided α = 1e-3 Šidák-corrected
// over the kPowerTests estimates of this file, plus 1e-5 relative for float rounding (needed only by
// the zero-variance constant light).
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>

#include "light_cases.h"
#include "pellucid/integrator/path_services.h"
#include "pellucid/math/constants.h"
#include "pellucid/sampling/rng.h"
#include "pellucid/sampling/warp.h"
#include "support/chi2.h"
#include "support/scene_util.h"

using namespace pellucid;

using pellucid::test::LogCapture;
using pellucid::test::scene_from;
using pellucid::test::z_two_sided;

namespace {
constexpr int kPowerTests = 8;
constexpr int kN = 200000;

const double kZ = z_two_sided(test::sidak_alpha(1e-3, kPowerTests));

struct Estimate {
    double mean = 0, se = 0;
};
template <class F>
Estimate mc(F&& f, uint64_t seed) {
    PCG32 rng(seed, 17);
    double s = 0, s2 = 0;
    for (int i = 0; i < kN; ++i) {
        double v = f(rng);
        s += v;
        s2 += v * v;
    }
    double m = s / kN, var = std::max(0.0, s2 / kN - m * m);
    return {m, std::sqrt(var / (kN - 1))};
}
void expect_power(const Estimate& e, double power, const char* what) {
    EXPECT_LT(std::fabs(e.mean - power), kZ * e.se + 1e-5 * power)
        << what << ": Monte-Carlo " << e.mean << " ± " << e.se << " vs power() " << power;
}

// Flux leaving an enclosing sphere (centre c, radius R) of a finite light, by its sample_li.
template <class L>
Estimate flux_through_sphere(const L& light, const Point3f& c, float R, uint64_t seed) {
    return mc([&](PCG32& rng) {
        Vec3f n_out = square_to_uniform_sphere(rng.next_2d());
        LightSampleContext ctx{c + R * n_out, -n_out};
        auto s = light.sample_li(ctx, rng.next_2d());
        if (!s) return 0.0;
        double cos_in = dot(-n_out, s->wi);
        EXPECT_GT(cos_in, 0.0);  // the light is inside the sphere
        return 4 * M_PI * double(R) * R * double(s->L.average()) * cos_in / double(s->pdf);
    }, seed);
}
}  // namespace

TEST(LightPower, AreaMeshOneSidedCube) {
    // A closed convex cube emitting outward: Φ = π·A·L, A = 24 (the [-1,1]³ cube scaled by 1).
    TriangleMesh m = TriangleMesh::cube();
    AreaLight light(m, Spectrum(0.5f, 1.f, 1.5f), false);
    EXPECT_NEAR(light.area(), 24.f, 1e-4f);
    EXPECT_NEAR(light.power(), M_PI * 24 * 1.0, 1e-3);
    expect_power(flux_through_sphere(light, Point3f(0.f), 4.f, 1), light.power(), "one-sided cube");
}

TEST(LightPower, AreaMeshTwoSidedPlanar) {
    auto tris = test::planar_light_triangles();
    AreaLight light(test::mesh_of(tris), Spectrum(2.f), true);
    double area = 2.0 * 1.0 + 0.5 * 1.0 * 1.2;
    EXPECT_NEAR(light.area(), area, 1e-5);
    EXPECT_NEAR(light.power(), 2 * M_PI * area * 2.0, 1e-3);
    expect_power(flux_through_sphere(light, Point3f(0.5f, 2.f, 0.f), 3.f, 2), light.power(), "two-sided planar");
}

TEST(LightPower, AreaSphereOutward) {
    // Sampled by its cone from every point of the enclosing sphere: Φ = π·4πr²·L.
    AreaLight light(Point3f(0.5f, -0.3f, 0.2f), 0.8f, false, Spectrum(1.f, 2.f, 3.f), false);
    EXPECT_NEAR(light.power(), M_PI * 4 * M_PI * 0.64 * 2.0, 1e-3);
    expect_power(flux_through_sphere(light, Point3f(0.f), 3.f, 3), light.power(), "sphere");
}

TEST(LightPower, PointOffCentre) {
    PointLight light(Point3f(0.7f, -0.4f, 0.3f), Spectrum(3.f));
    EXPECT_NEAR(light.power(), 4 * M_PI * 3.0, 1e-4);
    expect_power(flux_through_sphere(light, Point3f(0.f), 2.f, 4), light.power(), "point");
}

TEST(LightPower, SpotRampIntegratesExactly) {
    // Φ = 2π I ∫ falloff(θ) sin θ dθ; the flux estimate integrates the actual falloff, so it checks
    // the closed form in power() as well as the falloff itself.
    for (auto [cutoff, beam] : {std::pair<float, float>{40.f, 25.f}, {30.f, 0.f}, {60.f, 60.f}}) {
        SpotLight light(Point3f(0.2f, 0.1f, -0.3f), Vec3f(0.3f, -1.f, 0.2f), Spectrum(5.f), cutoff, beam);
        // Independent quadrature of the same integral (midpoint, 1e5 steps in θ).
        double q = 0, c = radians(cutoff), b = radians(beam);
        const int n = 100000;
        for (int i = 0; i < n; ++i) {
            double th = (i + 0.5) * c / n;
            double fall = th <= b ? 1.0 : (c - th) / (c - b);
            q += fall * std::sin(th) * c / n;
        }
        EXPECT_NEAR(light.power(), 2 * M_PI * 5.0 * q, 1e-4 * light.power()) << cutoff << "/" << beam;
        if (cutoff == 40.f)
            expect_power(flux_through_sphere(light, Point3f(0.f), 2.f, 5), light.power(), "spot");
    }
}

TEST(LightPower, ConstantIntegratesOverTheSphere) {
    ConstantLight light(Spectrum(0.25f, 0.5f, 0.75f));
    LightSampleContext ctx{Point3f(0.f), Normal3f(0.f)};
    Estimate e = mc([&](PCG32& rng) {
        auto s = light.sample_li(ctx, rng.next_2d());
        return s ? double(s->L.average()) / double(s->pdf) : 0.0;
    }, 6);
    const float r = 3.f;
    expect_power({e.mean * M_PI * r * r, e.se * M_PI * r * r}, light.power(r), "constant");
    EXPECT_NEAR(light.power(r), M_PI * r * r * 4 * M_PI * 0.5, 1e-3);
}

TEST(LightPower, EnvmapIntegratesOverTheSphere) {
    EnvmapLight light(test::asymmetric_envmap_image(), 2.f, test::test_rotation());
    LightSampleContext ctx{Point3f(0.f), Normal3f(0.f)};
    const float r = 2.5f;
    const double k = M_PI * r * r;
    EXPECT_NEAR(light.power(r), k * light.integral(), 1e-4 * light.power(r));
    // Uniform directions: independent of the map's sampler.
    Estimate u = mc([&](PCG32& rng) {
        Vec3f w = square_to_uniform_sphere(rng.next_2d());
        return double(light.Le(w).average()) * 4 * M_PI;
    }, 7);
    expect_power({u.mean * k, u.se * k}, light.power(r), "envmap, uniform directions");
    // The light's own importance sampling.
    Estimate s = mc([&](PCG32& rng) {
        auto ls = light.sample_li(ctx, rng.next_2d());
        return ls ? double(ls->L.average()) / double(ls->pdf) : 0.0;
    }, 8);
    expect_power({s.mean * k, s.se * k}, light.power(r), "envmap, sample_li");
}

TEST(DeltaLightSemantics, PointSampleSemantics) {
    PointLight light(Point3f(1.f, 2.f, 3.f), Spectrum(4.f, 8.f, 12.f));
    LightSampleContext ctx{Point3f(1.f, 2.f, 0.f), Normal3f(0, 0, 1)};
    auto s = light.sample_li(ctx, Vec2f(0.3f, 0.7f));
    ASSERT_TRUE(s);
    EXPECT_TRUE(s->delta);
    EXPECT_FALSE(s->infinite);
    EXPECT_EQ(s->pdf, 1.f);  // a discrete choice: the estimator divides by 1
    EXPECT_NEAR(s->wi.z, 1.f, 1e-6f);
    EXPECT_EQ(s->p_light, Point3f(1.f, 2.f, 3.f));
    EXPECT_NEAR(s->L.r, 4.f / 9.f, 1e-6f);  // I/d²
    EXPECT_NEAR(s->L.b, 12.f / 9.f, 1e-6f);
    // The sample does not depend on u.
    auto s2 = light.sample_li(ctx, Vec2f(0.9f, 0.1f));
    EXPECT_EQ(s2->wi, s->wi);
    EXPECT_EQ(s2->L, s->L);
    // At the light's own position there is no direction.
    EXPECT_FALSE(light.sample_li({Point3f(1.f, 2.f, 3.f), Normal3f(0.f)}, Vec2f(0.5f)));
}

TEST(DeltaLightSemantics, SpotSampleSemantics) {
    // Looks down -y from y = 2; cutoff 30°, beam 10°.
    SpotLight light(Point3f(0.f, 2.f, 0.f), Vec3f(0, -1, 0), Spectrum(6.f), 30.f, 10.f);
    auto at = [&](float deg) {
        float d = 2.f * std::tan(radians(deg));
        return light.sample_li({Point3f(d, 0.f, 0.f), Normal3f(0, 1, 0)}, Vec2f(0.5f));
    };
    auto on_axis = at(0.f);
    ASSERT_TRUE(on_axis);
    EXPECT_TRUE(on_axis->delta);
    EXPECT_EQ(on_axis->pdf, 1.f);
    EXPECT_NEAR(on_axis->L.r, 6.f / 4.f, 1e-6f);
    auto inside_beam = at(9.f);
    float d2 = 4.f / sqr(std::cos(radians(9.f)));
    EXPECT_NEAR(inside_beam->L.r, 6.f / d2, 1e-5f);
    auto ramp = at(20.f);  // halfway down the linear ramp
    d2 = 4.f / sqr(std::cos(radians(20.f)));
    EXPECT_NEAR(ramp->L.r, 0.5f * 6.f / d2, 1e-4f);
    EXPECT_FALSE(at(31.f));  // outside the cone: no light
}

TEST(DeltaLightSemantics, DirectionalSampleSemanticsAndPower) {
    const float radius = 3.f;
    DirectionalLight light(Vec3f(0.f, -2.f, 0.f), Spectrum(1.5f), radius);
    for (Point3f p : {Point3f(0.f), Point3f(5.f, -3.f, 1.f)}) {
        auto s = light.sample_li({p, Normal3f(0, 1, 0)}, Vec2f(0.2f, 0.8f));
        ASSERT_TRUE(s);
        EXPECT_TRUE(s->delta);
        EXPECT_TRUE(s->infinite);
        EXPECT_EQ(s->pdf, 1.f);
        EXPECT_NEAR(s->wi.y, 1.f, 1e-6f);  // toward the light: against its travel direction
        EXPECT_EQ(s->L, Spectrum(1.5f));   // irradiance, independent of position
    }
    // The power crossing a disk of the scene's bounding radius, perpendicular to the light.
    EXPECT_NEAR(light.power(), M_PI * radius * radius * 1.5, 1e-4);
}

TEST(LightSelection, BalancedGivesEachLightAtInfinityTheShareOfAllFiniteLights) {
    // Two point lights of power 4π·1 and 4π·3, a constant environment and a directional light.
    // balanced: the two lights at infinity and the finite set get 1/3 each; the finite third is
    // split 1 : 3 by power. The environment's power over the scene's disk must not matter. (The
    // nee strategy: under mis, NEE leaves the constant environment out; the test below.)
    auto scene = scene_from(R"({"camera": {"type": "perspective"}, "film": {"width": 4, "height": 4},
        "integrator": {"type": "path", "strategy": "nee"},
        "shapes": [{"type": "sphere", "radius": 50, "material": {"type": "lambertian"}}],
        "lights": [{"type": "point", "position": [0, 0, 0], "intensity": 1},
                   {"type": "constant", "radiance": 7},
                   {"type": "point", "position": [1, 0, 0], "intensity": 3},
                   {"type": "directional", "direction": [0, -1, 0], "irradiance": 0.01}]})");
    ASSERT_EQ(scene->lights.size(), 4u);
    EXPECT_NEAR(scene->light_pmf(0), 1.0 / 12.0, 1e-6);
    EXPECT_NEAR(scene->light_pmf(1), 1.0 / 3.0, 1e-6);
    EXPECT_NEAR(scene->light_pmf(2), 3.0 / 12.0, 1e-6);
    EXPECT_NEAR(scene->light_pmf(3), 1.0 / 3.0, 1e-6);
}

TEST(LightSelection, MisLeavesConstantEnvironmentsToBsdfSampling) {
    // Under mis and direct, NEE never picks a constant environment (light.h, nee_under_mis); the
    // other lights share the probabilities by the selection rule: balanced gives the directional
    // light as much as the finite pair, which splits its half 1 : 3.
    const std::string lights = R"("lights": [{"type": "point", "position": [0, 0, 0], "intensity": 1},
                   {"type": "constant", "radiance": 7},
                   {"type": "point", "position": [1, 0, 0], "intensity": 3},
                   {"type": "directional", "direction": [0, -1, 0], "irradiance": 0.01}]})";
    auto make = [](const std::string& strategy, const std::string& lights) {
        return scene_from(R"({"camera": {"type": "perspective"}, "film": {"width": 4, "height": 4},
            "integrator": {"type": "path", "strategy": ")" + strategy + R"("},
            "shapes": [{"type": "sphere", "radius": 50, "material": {"type": "lambertian"}}], )" + lights);
    };
    for (const char* strategy : {"mis", "direct"}) {
        auto scene = make(strategy, lights);
        EXPECT_NEAR(scene->light_pmf(0), 1.0 / 8.0, 1e-6) << strategy;
        EXPECT_EQ(scene->light_pmf(1), 0.f) << strategy;
        EXPECT_NEAR(scene->light_pmf(2), 3.0 / 8.0, 1e-6) << strategy;
        EXPECT_NEAR(scene->light_pmf(3), 0.5, 1e-6) << strategy;
        EXPECT_TRUE(scene->nee_lights) << strategy;
    }
    // Lit by constant environments only: no light for NEE under mis (the paths take no light
    // samples, PathSetup::use_nee); nee and bsdf keep the rule as it was.
    const std::string env_only = R"("lights": [{"type": "constant", "radiance": 1}, {"type": "constant", "radiance": 2}]})";
    auto mis = make("mis", env_only);
    EXPECT_FALSE(mis->nee_lights);
    EXPECT_FALSE(make_path_setup(*mis, 8, 5, true, true, SamplerType::Independent).use_nee);
    EXPECT_FALSE(make("direct", env_only)->nee_lights);
    auto nee = make("nee", env_only);
    EXPECT_TRUE(nee->nee_lights);
    EXPECT_NEAR(nee->light_pmf(0), 0.5, 1e-6);
    EXPECT_TRUE(make("bsdf", env_only)->nee_lights);
}

TEST(LightSelection, PowerAndUniformModes) {
    const std::string lights = R"("lights": [{"type": "point", "position": [0, 0, 0], "intensity": 1},
                   {"type": "point", "position": [1, 0, 0], "intensity": 3}]})";
    auto make = [&](const std::string& mode) {
        return scene_from(R"({"camera": {"type": "perspective"}, "film": {"width": 4, "height": 4},
            "integrator": {"type": "path", "light_selection": ")" + mode + R"("},
            "shapes": [{"type": "sphere", "radius": 50, "material": {"type": "lambertian"}}], )" + lights);
    };
    auto power = make("power"), uniform = make("uniform");
    EXPECT_NEAR(power->light_pmf(0), 0.25, 1e-6);
    EXPECT_NEAR(power->light_pmf(1), 0.75, 1e-6);
    EXPECT_NEAR(uniform->light_pmf(0), 0.5, 1e-6);
    EXPECT_NEAR(uniform->light_pmf(1), 0.5, 1e-6);
}
