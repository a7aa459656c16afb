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

// ---- render_aovs: every AOV of one render, against known answers --------------------------------
namespace {
/// A grey Lambertian rectangle [-1.5, 1.5]² in z = −0.5 (shape 1, material "grey") and a small
/// sphere outside the view (shape 0, material "red"); the camera at z = 2.5 looks down −z, so the
/// rectangle is at distance D = 3 along the axis. `extra` is spliced into the scene object. The
/// camera is off the axis by a fraction of a pixel, so that no pixel-centre ray runs exactly along
/// the rectangle's diagonal, where Embree's non-robust triangle test may miss both triangles.
std::shared_ptr<const Scene> plane_scene(const std::string& extra = "") {
    return scene_from(std::string("{") + kSharp + R"(, "sampler": {"sample_count": 4, "seed": 5},
        "camera": {"type": "perspective", "fov": 70,
                   "to_world": [{"look_at": {"origin": [0.0123, -0.0371, 2.5], "target": [0.0123, -0.0371, 0],
                                             "up": [0, 1, 0]}}]},
        "materials": {"grey": {"type": "lambertian", "reflectance": 0.3},
                      "red": {"type": "lambertian", "reflectance": [0.9, 0.1, 0.1]}},
        "shapes": [{"type": "sphere", "center": [0, 0, 40], "radius": 0.5, "material": "red"},
                   {"type": "rectangle", "material": "grey",
                    "to_world": [{"scale": 1.5}, {"translate": [0, 0, -0.5]}]}])" + extra + "}");
}

const ImageLayer& layer(const std::vector<ImageLayer>& ls, const std::string& name) {
    for (const ImageLayer& l : ls)
        if (l.name == name) return l;
    throw Error("no layer " + name);
}

std::vector<Aov> all_aovs() { return parse_aov_list(known_aovs()); }
}  // namespace

TEST(RenderAovs, PlaneKnownAnswersForEveryAov) {
    auto scene = plane_scene();
    RenderOptions o;
    RenderResult beauty = render(*scene, o);
    std::vector<ImageLayer> ls = render_aovs(*scene, all_aovs(), beauty, o);
    ASSERT_EQ(ls.size(), 9u);
    const std::vector<std::string> names = {"albedo", "normal", "depth", "position", "uv", "shape_id",
                                            "material_id", "variance", "sample_count"};
    for (size_t i = 0; i < names.size(); ++i) {
        EXPECT_EQ(ls[i].name, names[i]);
        EXPECT_EQ(int(ls[i].channels.size()), ls[i].image.channels) << names[i];
    }
    EXPECT_EQ(layer(ls, "depth").channels, std::vector<std::string>{"Z"});
    EXPECT_EQ(layer(ls, "normal").channels, (std::vector<std::string>{"X", "Y", "Z"}));
    EXPECT_EQ(layer(ls, "uv").channels, (std::vector<std::string>{"U", "V"}));
    uint32_t grey = 0;
    while (scene->material_names[grey] != "grey") ++grey;
    const double D = 3.0, half = 1.5;
    int on = 0, off = 0;
    for (int y = 0; y < scene->height; ++y)
        for (int x = 0; x < scene->width; ++x) {
            const Ray ray = scene->camera.generate_ray(x + 0.5f, y + 0.5f);
            const double t = D / -double(ray.d.z);
            const Vec3d p = Vec3d(ray.o) + t * Vec3d(ray.d);
            const float* alb = layer(ls, "albedo").image.pixel(x, y);
            const float* n = layer(ls, "normal").image.pixel(x, y);
            const float* pos = layer(ls, "position").image.pixel(x, y);
            const float* uv = layer(ls, "uv").image.pixel(x, y);
            const float depth = *layer(ls, "depth").image.pixel(x, y);
            const float sid = *layer(ls, "shape_id").image.pixel(x, y), mid = *layer(ls, "material_id").image.pixel(x, y);
            EXPECT_EQ(*layer(ls, "sample_count").image.pixel(x, y), 4.f);
            if (std::fabs(p.x) < 0.97 * half && std::fabs(p.y) < 0.97 * half) {
                // Lambertian with cosine sampling: every sample weight is ρ exactly.
                for (int k = 0; k < 3; ++k) EXPECT_NEAR(alb[k], 0.3, 1e-6) << x << "," << y;
                EXPECT_NEAR(n[0], 0.0, 1e-6);
                EXPECT_NEAR(n[1], 0.0, 1e-6);
                EXPECT_NEAR(n[2], 1.0, 1e-6);
                // The samples lie within 0.001 px of the centre (box of radius 0.001).
                EXPECT_NEAR(depth, t, 1e-4 * t) << x << "," << y;
                EXPECT_NEAR(pos[0], p.x, 2e-4);
                EXPECT_NEAR(pos[1], p.y, 2e-4);
                EXPECT_NEAR(pos[2], -0.5, 1e-5);
                EXPECT_NEAR(uv[0], (p.x / half + 1.0) / 2.0, 2e-4) << x << "," << y;
                EXPECT_NEAR(uv[1], (p.y / half + 1.0) / 2.0, 2e-4) << x << "," << y;
                EXPECT_EQ(sid, 1.f);
                EXPECT_EQ(mid, float(grey));
                ++on;
            } else if (std::fabs(p.x) > 1.03 * half || std::fabs(p.y) > 1.03 * half) {
                for (int k = 0; k < 3; ++k) {
                    EXPECT_EQ(alb[k], 0.f);
                    EXPECT_EQ(n[k], 0.f);
                    EXPECT_EQ(pos[k], 0.f);
                }
                EXPECT_EQ(depth, 0.f);
                EXPECT_EQ(uv[0], 0.f);
                EXPECT_EQ(uv[1], 0.f);
                EXPECT_EQ(sid, -1.f);
                EXPECT_EQ(mid, -1.f);
                ++off;
            }
        }
    EXPECT_GT(on, 200);
    EXPECT_GT(off, 50);
    EXPECT_EQ(layer(ls, "variance").image.data, beauty.variance.data);
}

TEST(RenderAovs, SphereNormalsAreAnalytic) {
    const Vec3d c(0.1, -0.1, 0.0);
    const double rad = 1.1;
    auto scene = scene_from(std::string("{") + kSharp + "," + kCamera + R"(, "sampler": {"sample_count": 2},
        "shapes": [{"type": "sphere", "center": [0.1, -0.1, 0], "radius": 1.1}]})");
    RenderResult beauty = render(*scene, RenderOptions{});
    std::vector<ImageLayer> ls = render_aovs(*scene, {Aov::Normal}, beauty, RenderOptions{});
    ASSERT_EQ(ls.size(), 1u);
    int on = 0;
    for (int y = 0; y < scene->height; ++y)
        for (int x = 0; x < scene->width; ++x) {
            Ray ray = scene->camera.generate_ray(x + 0.5f, y + 0.5f);
            double t, miss;
            if (hit_sphere(ray, c, rad, &t, &miss) && miss < 0.98 * rad) {
                const Vec3d n = (Vec3d(ray.o) + t * Vec3d(ray.d) - c) / rad;
                for (int k = 0; k < 3; ++k) EXPECT_NEAR(ls[0].image.pixel(x, y)[k], n[k], 1e-3) << x << "," << y;
                ++on;
            }
        }
    EXPECT_GT(on, 200);
}

TEST(RenderAovs, GuidesFollowDeltaBounces) {
    // A perfect mirror (conductor, F ≡ 1) in z = 0 facing the camera at z = 4 reflects every camera
    // ray onto a Lambertian wall (ρ = 0.3) in z = 6 facing −z: albedo and normal are the wall's
    // (0.3 and (0, 0, −1)), depth and position the mirror's (first hit). The camera is off the axis
    // so that no ray runs exactly along a rectangle's diagonal (see plane_scene).
    auto scene = scene_from(std::string("{") + kSharp + R"(, "sampler": {"sample_count": 2},
        "camera": {"type": "perspective", "fov": 40,
                   "to_world": [{"look_at": {"origin": [0.0123, -0.0371, 4], "target": [0.0123, -0.0371, 0],
                                             "up": [0, 1, 0]}}]},
        "shapes": [{"type": "rectangle", "to_world": [{"scale": 10}], "material": {"type": "conductor"}},
                   {"type": "rectangle", "flip_normals": true, "to_world": [{"scale": 100}, {"translate": [0, 0, 6]}],
                    "material": {"type": "lambertian", "reflectance": 0.3}}]})");
    RenderResult beauty = render(*scene, RenderOptions{});
    std::vector<ImageLayer> ls = render_aovs(*scene, {Aov::Albedo, Aov::Normal, Aov::Depth, Aov::Position}, beauty,
                                             RenderOptions{});
    for (int y = 0; y < scene->height; ++y)
        for (int x = 0; x < scene->width; ++x) {
            const Ray ray = scene->camera.generate_ray(x + 0.5f, y + 0.5f);
            const double t = 4.0 / -double(ray.d.z);
            for (int k = 0; k < 3; ++k) EXPECT_NEAR(ls[0].image.pixel(x, y)[k], 0.3, 1e-5) << x << "," << y;
            EXPECT_NEAR(ls[1].image.pixel(x, y)[2], -1.0, 1e-5) << x << "," << y;
            EXPECT_NEAR(*ls[2].image.pixel(x, y), t, 1e-4 * t);
            EXPECT_NEAR(ls[3].image.pixel(x, y)[2], 0.0, 1e-5);
        }
}

TEST(RenderAovs, SameCameraRaysAsTheBeautyAndTheAovIntegrator) {
    // The AOV pass takes the beauty's seed, sampler and spp: its depth is the AOV integrator's
    // depth bit for bit, for filter sampling and for splatting films, and whatever seed the beauty used.
    for (const char* film : {R"("film": {"width": 20, "height": 14})",
                             R"("film": {"width": 20, "height": 14, "reconstruction": "splatting"})"}) {
        auto scene = scene_from(std::string("{") + film + "," + kCamera + R"(, "sampler": {"sample_count": 3},
            "shapes": [{"type": "sphere", "material": {"type": "oren_nayar", "reflectance": 0.6, "roughness": 0.7}}]})");
        RenderOptions o;
        o.seed = 11;
        o.sampler = "sobol";
        RenderResult beauty = render(*scene, o);
        std::vector<ImageLayer> ls = render_aovs(*scene, {Aov::Depth, Aov::Albedo}, beauty, RenderOptions{});
        RenderResult depth = render_aov(*scene, "depth", o), albedo = render_aov(*scene, "albedo", o);
        for (size_t p = 0; p < size_t(scene->width) * size_t(scene->height); ++p) {
            ASSERT_EQ(ls[0].image.data[p], depth.image.data[3 * p]) << film << " pixel " << p;
            for (int k = 0; k < 3; ++k) ASSERT_EQ(ls[1].image.data[3 * p + size_t(k)], albedo.image.data[3 * p + size_t(k)]);
        }
    }
}

TEST(RenderAovs, ParsesListsAndRejectsUnknownNames) {
    EXPECT_EQ(parse_aov_list(" albedo, normal ,albedo"), (std::vector<Aov>{Aov::Albedo, Aov::Normal}));
    EXPECT_EQ(known_aovs(), "albedo, normal, depth, position, uv, shape_id, material_id, variance, sample_count");
    try {
        parse_aov_list("albedo,nromal", "--aovs");
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()), "--aovs: unknown aov 'nromal' (known: " + known_aovs() + ")");
    }
    EXPECT_THROW(parse_aov_list("albedo,,normal"), Error);
    EXPECT_THROW(parse_aov_list(""), Error);
}
