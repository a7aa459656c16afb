// The AOV integrator: normals and depth against closed forms at every pixel, albedo against the
// material's known directional albedo (z-tests), scene/API plumbing and bad input.
// Geometry tests use a 0.001-pixel box filter, so a pixel's samples all lie within 0.001 px of its
// centre; normals are compared with the analytic one at the centre ray (found by our own ray cast),
// depth with the mean of the closed form over the very sample positions the renderer used (same
// per-sample PCG32 streams as render_tile), so it is exact to float rounding.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>

#include "pellucid/api.h"
#include "pellucid/integrator/aov.h"
#include "pellucid/scene/json_io.h"
#include "pellucid/util/error.h"
#include "support/chi2.h"
#include "support/scene_util.h"

using namespace pellucid;

using pellucid::test::LogCapture;
using pellucid::test::scene_from;
using pellucid::test::z_two_sided;

namespace {
const char* kSharp = R"("film": {"width": 32, "height": 24, "filter": {"type": "box", "radius": 0.001}})";
const char* kCamera = R"("camera": {"type": "perspective", "fov": 40,
    "to_world": [{"look_at": {"origin": [0.3, 0.2, 4], "target": [0, 0, 0], "up": [0, 1, 0]}}]})";

// Distance from a point to the ray's line, and the nearest sphere hit (double).
bool hit_sphere(const Ray& r, const Vec3d& c, double rad, double* t, double* miss_dist) {
    Vec3d o(r.o), d(r.d), oc = o - c;
    double b = glm::dot(oc, d), q = glm::dot(oc, oc) - rad * rad, disc = b * b - q;
    *miss_dist = std::sqrt(std::max(0.0, glm::dot(oc, oc) - b * b));
    if (disc < 0) return false;
    *t = -b - std::sqrt(disc);
    return *t > 0;
}
}  // namespace

TEST(AovNormal, SphereMatchesTheAnalyticNormal) {
    const Vec3d c(0.1, -0.1, 0.0);
    const double rad = 1.1;
    auto scene = scene_from(std::string("{") + kSharp + "," + kCamera + R"(,
        "sampler": {"sample_count": 4}, "integrator": {"type": "aov", "aov": "normal"},
        "shapes": [{"type": "sphere", "center": [0.1, -0.1, 0], "radius": 1.1}]})");
    RenderResult r = render(*scene, RenderOptions{});
    int on = 0, off = 0, negative = 0;
    for (int y = 0; y < scene->height; ++y)
        for (int x = 0; x < scene->width; ++x) {
            Ray ray = scene->camera.generate_ray(x + 0.5f, y + 0.5f);
            double t, miss;
            const float* px = r.image.pixel(x, y);
            bool hit = hit_sphere(ray, c, rad, &t, &miss);
            if (hit && miss < 0.98 * rad) {
                Vec3d n = (Vec3d(ray.o) + t * Vec3d(ray.d) - c) / rad;
                for (int k = 0; k < 3; ++k) EXPECT_NEAR(px[k], n[k], 1e-3) << "pixel " << x << "," << y << " axis " << k;
                negative += px[0] < -0.1f || px[1] < -0.1f;
                ++on;
            } else if (!hit && miss > 1.02 * rad) {
                for (int k = 0; k < 3; ++k) EXPECT_EQ(px[k], 0.f) << "miss at " << x << "," << y;
                ++off;
            }
        }
    EXPECT_GT(on, 200);
    EXPECT_GT(off, 50);
    EXPECT_GT(negative, 20);  // signed components are kept (not clamped or remapped)
    EXPECT_EQ(r.stats.invalid_samples, 0u);
}

TEST(AovDepth, PlaneAtKnownDistanceIsExact) {
    // The rectangle [-1.5, 1.5]² in z = −0.5, the camera at z = 2.5 looking down −z: D = 3 and
    // t = D / cos(angle to the axis) per pixel; outside the rectangle the depth is 0.
    const double D = 3.0, half = 1.5;
    auto scene = scene_from(std::string("{") + kSharp + R"(, "sampler": {"sample_count": 2},
        "camera": {"type": "perspective", "fov": 70,
                   "to_world": [{"look_at": {"origin": [0, 0, 2.5], "target": [0, 0, 0], "up": [0, 1, 0]}}]},
        "integrator": {"type": "aov", "aov": "depth"},
        "shapes": [{"type": "rectangle", "to_world": [{"scale": 1.5}, {"translate": [0, 0, -0.5]}]}]})");
    RenderResult r = render(*scene, RenderOptions{});
    int on = 0, off = 0;
    for (int y = 0; y < scene->height; ++y)
        for (int x = 0; x < scene->width; ++x) {
            Ray ray = scene->camera.generate_ray(x + 0.5f, y + 0.5f);
            double t_centre = D / -double(ray.d.z);
            Vec3d p = Vec3d(ray.o) + t_centre * Vec3d(ray.d);
            double t = 0;
            for (int s = 0; s < scene->spp; ++s) {
                PCG32 rng = PCG32::for_sample(uint64_t(y) * uint64_t(scene->width) + uint64_t(x), uint64_t(s), scene->seed);
                Vec2f off = sample_filter(scene->filter, rng.next_2d());
                t += D / -double(scene->camera.generate_ray(x + 0.5f + off.x, y + 0.5f + off.y).d.z) / scene->spp;
            }
            const float* px = r.image.pixel(x, y);
            if (std::fabs(p.x) < 0.97 * half && std::fabs(p.y) < 0.97 * half) {
                for (int k = 0; k < 3; ++k) EXPECT_NEAR(px[k], t, 1e-6 * t) << x << "," << y;
                ++on;
            } else if (std::fabs(p.x) > 1.03 * half || std::fabs(p.y) > 1.03 * half) {
                EXPECT_EQ(px[0], 0.f) << x << "," << y;
                ++off;
            }
        }
    EXPECT_GT(on, 200);
    EXPECT_GT(off, 50);
}

namespace {
// Albedo AOV of a sphere filling the frame: every pixel's mean against `expected` with a per-pixel
// two-sided z-test (α = 0.01, Šidák over the pixel channels) allowing `bias` for a tabulated
// model, and the image mean at α = 1e-4.
void expect_albedo(const std::string& material, const Spectrum& expected, double bias, const char* what) {
    auto scene = scene_from(std::string(R"({"film": {"width": 12, "height": 12}, "sampler": {"sample_count": 256, "seed": 3},
        "camera": {"type": "perspective", "fov": 20,
                   "to_world": [{"look_at": {"origin": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0]}}]},
        "integrator": {"type": "aov", "aov": "albedo"},
        "shapes": [{"type": "sphere", "radius": 1.5, "material": )") + material + "}]}");
    RenderResult r = render(*scene, RenderOptions{});
    size_t n = r.image.data.size();
    double z = z_two_sided(test::sidak_alpha(0.01, int(n)));
    double sum[3] = {0, 0, 0}, var[3] = {0, 0, 0};
    int fails = 0;
    for (size_t i = 0; i < n; ++i) {
        int k = int(i % 3);
        double d = std::fabs(r.image.data[i] - expected[k]);
        if (d > bias + z * std::sqrt(r.variance.data[i]) + 1e-6) ++fails;
        sum[k] += r.image.data[i];
        var[k] += r.variance.data[i];
    }
    EXPECT_EQ(fails, 0) << what << ": pixel channels beyond bias + |z| > " << z;
    double m = double(n / 3);
    for (int k = 0; k < 3; ++k)
        EXPECT_LT(std::fabs(sum[k] / m - expected[k]), bias + z_two_sided(1e-4) * std::sqrt(var[k]) / m + 1e-6)
            << what << " channel " << k << ": mean " << sum[k] / m;
    EXPECT_EQ(r.stats.invalid_samples, 0u);
}
}  // namespace

TEST(AovAlbedo, LambertianConvergesToItsReflectance) {
    expect_albedo(R"({"type": "lambertian", "reflectance": [0.2, 0.5, 0.8]})", Spectrum(0.2f, 0.5f, 0.8f), 0.0,
                  "lambertian");
}

TEST(AovAlbedo, WhiteRoughConductorWithMultipleScatteringIsOne) {
    // Kulla–Conty compensation makes a white (F ≡ 1) GGX conductor conserve energy; its tables are
    // accurate to 3e-3 (bxdf/test_conductor.cpp, KullaConty.CompensatedWhiteFurnaceAndSkipRule).
    expect_albedo(R"({"type": "rough_conductor", "material": "none", "alpha": 0.5, "multiple_scattering": true})",
                  Spectrum(1.f), 3e-3, "white rough conductor");
}

TEST(AovAlbedo, SingleScatteringConductorLosesEnergy) {
    // The same conductor without compensation must show the well-known energy loss at α = 0.8
    // (so the previous test cannot pass by returning 1 everywhere).
    auto scene = scene_from(R"({"film": {"width": 8, "height": 8}, "sampler": {"sample_count": 256},
        "camera": {"type": "perspective", "fov": 15,
                   "to_world": [{"look_at": {"origin": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0]}}]},
        "integrator": {"type": "aov", "aov": "albedo"},
        "shapes": [{"type": "sphere", "radius": 1.5,
                    "material": {"type": "rough_conductor", "material": "none", "alpha": 0.8}}]})");
    RenderResult r = render(*scene, RenderOptions{});
    double sum = 0;
    for (float v : r.image.data) sum += v;
    EXPECT_LT(sum / double(r.image.data.size()), 0.95);
}

TEST(Aov, ApiMatchesSceneIntegratorAndRejectsUnknownNames) {
    const std::string body = std::string(kSharp) + "," + kCamera + R"(, "sampler": {"sample_count": 3, "seed": 2},
        "shapes": [{"type": "sphere", "material": {"type": "oren_nayar", "reflectance": 0.6, "roughness": 0.7}}])";
    auto path_scene = scene_from("{" + body + "}");
    for (const char* aov : {"albedo", "normal", "depth"}) {
        auto aov_scene = scene_from("{" + body + R"(, "integrator": {"type": "aov", "aov": ")" + aov + "\"}}");
        RenderResult a = render(*aov_scene, RenderOptions{});
        RenderResult b = render_aov(*path_scene, aov, RenderOptions{});
        EXPECT_EQ(a.image.data, b.image.data) << aov;
    }
    try {
        render_aov(*path_scene, "nromal", RenderOptions{});
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()), "aov: unknown aov 'nromal' (known: albedo, depth, normal)");
    }
    try {
        scene_from(R"({"integrator": {"type": "aov", "aov": "nromal"}})");
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()), "test: integrator.aov: unknown aov 'nromal' (known: albedo, depth, normal)");
    }
    try {
        scene_from(R"({"integrator": {"type": "aov", "aov": "depth", "max_depth": 3}})");
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()), "test: integrator.max_depth: unknown parameter");
    }
}
