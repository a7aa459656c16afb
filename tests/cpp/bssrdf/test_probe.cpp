// The separable BSSRDF's sampling (bssrdf/separable.h): the exit lobe's normalisation and weights,
// and probe-ray exit sampling against its own density (χ², Šidák-corrected α = 0.01 over the cases)
// and its expectation (z-test, α = 1e-4), on the flat face of a large cube; fixed seeds.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "pellucid/bssrdf/separable.h"
#include "pellucid/bxdf/fresnel.h"
#include "pellucid/sampling/rng.h"
#include "pellucid/scene/scene.h"
#include "support/chi2.h"
#include "support/scene_util.h"

using namespace pellucid;
using pellucid::test::scene_from;

namespace {
// A 20-unit cube whose top face is the plane y = 0, thousands of mean free paths across; a probe
// from the centre of that face sees the half-space of the profiles.
std::shared_ptr<const Scene> cube_scene(const std::string& model) {
    return scene_from(R"({"camera": {"type": "perspective", "fov": 30,
            "to_world": [{"look_at": {"origin": [0, 3, 3], "target": [0, 0, 0], "up": [0, 1, 0]}}]},
        "film": {"width": 8, "height": 8},
        "materials": {"m": {"type": "subsurface", "model": ")" + model + R"(", "albedo": [0.9, 0.6, 0.3],
                            "mfp": [0.05, 0.02, 0.01], "int_ior": 1.4}},
        "shapes": [{"type": "cube", "material": "m", "to_world": [{"scale": [10, 10, 10]}, {"translate": [0, -10, 0]}]}],
        "lights": [{"type": "constant", "radiance": 1}]})");
}
SurfaceInteraction entry_point(const Scene& s) {
    SurfaceInteraction si;
    EXPECT_TRUE(s.intersect(Ray{Point3f(0.01f, 1.f, 0.02f), Vec3f(0.f, -1.f, 0.f), kInfinity}, si));
    return si;
}
const int kCases = 2;  // models
}  // namespace

TEST(BSSRDFExitLobe, IntegratesToOneAndItsSampleWeightIsEvalOverPdf) {
    for (float eta : {1.f, 1.0001f, 1.33f, 1.5f, 2.4f}) {
        SeparableBSSRDF b;
        b.eta = eta;
        b.exit_norm = bssrdf::exit_lobe_norm(eta);
        // ∫ Sw cos dω over the outside hemisphere, by a fine midpoint rule in cos θ.
        const int n = 20000;
        double sum = 0;
        for (int i = 0; i < n; ++i) {
            const float mu = (float(i) + 0.5f) / float(n);
            float pdf;
            sum += b.exit_eval(Vec3f(std::sqrt(1.f - mu * mu), 0.f, mu), &pdf).r * 2.0 * M_PI / n;
        }
        EXPECT_NEAR(sum, 1.0, 1e-4) << "eta " << eta;
        PCG32 rng(7, 3);
        for (int k = 0; k < 1000; ++k) {
            BxDFSample s;
            ASSERT_TRUE(b.exit_sample(Vec2f(rng.next_float(), rng.next_float()), &s));
            float pdf;
            const Spectrum f = b.exit_eval(s.wi, &pdf);
            ASSERT_NEAR(pdf, s.pdf, 1e-6f);
            ASSERT_NEAR(s.weight.r, f.r / pdf, 1e-5f * s.weight.r);
            ASSERT_GE(s.weight.r, 0.f);
        }
        float pdf;
        EXPECT_EQ(b.exit_eval(Vec3f(0.f, 0.f, -1.f), &pdf).r, 0.f);  // never into the object
    }
}

TEST(BSSRDFProbe, ExitPointsFollowTheirDensity) {
    // Exit points on the face, binned by radius (equal steps of log r) and angle, against the
    // mixture density probe_pdf integrated over each bin; a cell for "no exit", whose probability is
    // 1/2 on a plane (probes along the two tangents run parallel to it).
    const double alpha = pellucid::test::sidak_alpha(0.01, kCases);
    for (const char* model : {"dipole", "better_dipole"}) {
        auto scene = cube_scene(model);
        ASSERT_EQ(scene->subsurface.size(), 1u);
        const SeparableBSSRDF& b = scene->subsurface[0];
        const SurfaceInteraction e = entry_point(*scene);
        const float r_top = std::max(b.r_max[0], std::max(b.r_max[1], b.r_max[2]));
        const float r_lo = 1e-4f * r_top;
        const int nr = 40, nphi = 4;
        auto bin_of = [&](float r) { return r < r_lo ? 0 : std::min(nr - 1, 1 + int((nr - 1) * std::log(r / r_lo) / std::log(r_top / r_lo))); };
        auto edge = [&](int k) { return k == 0 ? 0.0 : double(r_lo) * std::pow(double(r_top / r_lo), double(k - 1) / (nr - 1)); };
        const int N = 200000;
        std::vector<double> obs(nr * nphi + 1, 0.0), expct(nr * nphi + 1, 0.0);
        PCG32 rng(11, 5);
        for (int i = 0; i < N; ++i) {
            SurfaceInteraction x;
            Spectrum w;
            const float ua = rng.next_float(), u1 = rng.next_float(), u2 = rng.next_float(), uh = rng.next_float();
            if (!sample_probe(*scene, b, e, ua, Vec2f(u1, u2), uh, &x, &w)) {
                obs[nr * nphi] += 1;
                continue;
            }
            const Vec3f d = e.shading.to_local(x.p - e.p);
            const float r = std::sqrt(d.x * d.x + d.y * d.y);
            float phi = std::atan2(d.y, d.x);
            if (phi < 0.f) phi += 2.f * float(M_PI);
            obs[bin_of(r) * nphi + std::min(nphi - 1, int(phi / (2.f * float(M_PI)) * nphi))] += 1;
        }
        // Expected: N ∫ pdf dA per bin (the density depends on r only), by a fine midpoint rule.
        double covered = 0;
        for (int k = 0; k < nr; ++k) {
            const double r0 = edge(k), r1 = k + 1 < nr ? edge(k + 1) : double(r_top) * 1.001;
            const int m = 400;
            double mass = 0;
            for (int j = 0; j < m; ++j) {
                const double r = r0 + (r1 - r0) * (j + 0.5) / m;
                const Point3f pi = e.p + float(r) * e.shading.s;
                mass += probe_pdf(b, e, pi, e.ng) * 2.0 * M_PI * r * (r1 - r0) / m;
            }
            covered += mass;
            for (int a = 0; a < nphi; ++a) expct[k * nphi + a] = N * mass / nphi;
        }
        EXPECT_NEAR(covered, 0.5, 2e-3) << model;
        expct[nr * nphi] = N * (1.0 - covered);
        const auto res = pellucid::test::chi2_test(obs, expct);
        EXPECT_GT(res.p_value, alpha) << model << ": " << res.message;
    }
}

TEST(BSSRDFProbe, WeightsAverageToTheTotalReflectanceOnAPlane) {
    // E[Sp/pdf] over probes (0 for a probe that finds no exit) = ∫ Sp dA = the profile's total, per
    // channel, for any mixture of axes and channels (unbiased one-sample MIS).
    for (const char* model : {"dipole", "better_dipole"}) {
        auto scene = cube_scene(model);
        const SeparableBSSRDF& b = scene->subsurface[0];
        const SurfaceInteraction e = entry_point(*scene);
        const int N = 200000;
        double sum[3] = {0, 0, 0}, sq[3] = {0, 0, 0};
        PCG32 rng(17, 9);
        for (int i = 0; i < N; ++i) {
            SurfaceInteraction x;
            Spectrum w(0.f);
            const float ua = rng.next_float(), u1 = rng.next_float(), u2 = rng.next_float(), uh = rng.next_float();
            if (!sample_probe(*scene, b, e, ua, Vec2f(u1, u2), uh, &x, &w)) w = Spectrum(0.f);
            for (int c = 0; c < 3; ++c) sum[c] += w[c], sq[c] += double(w[c]) * w[c];
        }
        const Spectrum total = b.total();
        for (int c = 0; c < 3; ++c) {
            const double mean = sum[c] / N, se = std::sqrt((sq[c] / N - mean * mean) / (N - 1));
            // The profile's sampling covers 99.9 % of its mass (bssrdf/profile.h): the far 0.1 % is
            // not reached by any probe.
            EXPECT_NEAR(mean, 0.999 * total[c], pellucid::test::z_two_sided(1e-4) * se + 1e-4 * total[c])
                << model << " channel " << c << " (total " << total[c] << ")";
        }
    }
}
