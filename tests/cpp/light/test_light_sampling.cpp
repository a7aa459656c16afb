// Light sampling: χ² tests of the directions sample_li produces against pdf_li, and pdf_li equal to
// the pdf sample_li reports. pdf_li is evaluated at the point where the direction meets the light,
// found by the tests' own ray casts (light_cases.h), never by the light's sampling code.
// Significance: α = 0.01 family-wise over the kChi2Tests χ² tests of this file (Šidák).
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "light_cases.h"
#include "pellucid/math/constants.h"
#include "pellucid/math/frame.h"
#include "pellucid/sampling/rng.h"
#include "support/chi2.h"

using namespace pellucid;
using test::chi2_test;

namespace {
constexpr int kSamples = 1000000;
constexpr int kChi2Tests = 11;  // 6 light tests and 5 bilinear cells
const double kAlpha = test::sidak_alpha(0.01, kChi2Tests);

using SampleFn = std::function<std::optional<Vec3f>(Vec2f)>;
using PdfFn = std::function<double(const Vec3f&)>;

// Directions binned on an equal-area grid (z = cos θ uniform in [z_min, 1], φ uniform) of a cone
// about `axis`; z_min = -1 is the whole sphere. The expected count of a cell is N ∫ pdf dω with
// dω = dz dφ, by an 8×8 midpoint rule, refined to 64×64 where the pdf jumps (by more than 2 %
// between the nodes of the cell and its 8 neighbours: a triangle's silhouette or corner, an envmap
// cell edge, a 1/sin θ pole).
// Samples outside the cone fail the test.
void chi2_cone(const SampleFn& sample, const PdfFn& pdf, const Vec3f& axis, double z_min, uint64_t seed,
               int nz = 32, int nphi = 64) {
    Frame f = Frame::from_z(normalize(axis));
    std::vector<double> obs(size_t(nz * nphi), 0.0), expct(size_t(nz * nphi), 0.0);
    PCG32 rng(seed, 3);
    int outside = 0;
    for (int i = 0; i < kSamples; ++i) {
        auto w = sample(rng.next_2d());
        if (!w) continue;
        ASSERT_NEAR(length(*w), 1.f, 1e-4f);
        Vec3f l = f.to_local(*w);
        double z = clamp(double(l.z), -1.0, 1.0), phi = std::atan2(double(l.y), double(l.x));
        if (phi < 0) phi += 2 * M_PI;
        if (z < z_min) {
            ++outside;
            continue;
        }
        int iz = std::min(nz - 1, int((z - z_min) / (1 - z_min) * nz)), ip = std::min(nphi - 1, int(phi / (2 * M_PI) * nphi));
        obs[size_t(iz * nphi + ip)] += 1;
    }
    EXPECT_EQ(outside, 0) << "samples outside the light's cone of directions";
    auto cell = [&](double z0, double z1, double p0, double p1, int res, double* lo_out, double* hi_out) {
        double hz = (z1 - z0) / res, hp = (p1 - p0) / res, sum = 0, lo = 1e300, hi = 0;
        for (int a = 0; a < res; ++a)
            for (int b = 0; b < res; ++b) {
                double z = z0 + (a + 0.5) * hz, p = p0 + (b + 0.5) * hp, s = std::sqrt(std::max(0.0, 1 - z * z));
                Vec3f w = f.to_world(Vec3f(float(s * std::cos(p)), float(s * std::sin(p)), float(z)));
                double v = pdf(normalize(w));
                sum += v;
                lo = std::min(lo, v);
                hi = std::max(hi, v);
            }
        if (lo_out) *lo_out = lo;
        if (hi_out) *hi_out = hi;
        return sum * hz * hp;
    };
    auto bounds = [&](int iz, int ip, double out[4]) {
        out[0] = z_min + (1 - z_min) * iz / nz, out[1] = z_min + (1 - z_min) * (iz + 1) / nz;
        out[2] = 2 * M_PI * ip / nphi, out[3] = 2 * M_PI * (ip + 1) / nphi;
    };
    std::vector<double> lo(expct.size()), hi(expct.size());
    for (int iz = 0; iz < nz; ++iz)
        for (int ip = 0; ip < nphi; ++ip) {
            double b[4];
            bounds(iz, ip, b);
            size_t k = size_t(iz * nphi + ip);
            expct[k] = cell(b[0], b[1], b[2], b[3], 8, &lo[k], &hi[k]);
        }
    double total = 0;
    for (int iz = 0; iz < nz; ++iz)
        for (int ip = 0; ip < nphi; ++ip) {
            double l = 1e300, h = 0;
            for (int dz = -1; dz <= 1; ++dz)
                for (int dp = -1; dp <= 1; ++dp) {
                    int jz = iz + dz, jp = (ip + dp + nphi) % nphi;
                    if (jz < 0 || jz >= nz) continue;
                    l = std::min(l, lo[size_t(jz * nphi + jp)]);
                    h = std::max(h, hi[size_t(jz * nphi + jp)]);
                }
            size_t k = size_t(iz * nphi + ip);
            if (h > 1.02 * l) {
                double b[4];
                bounds(iz, ip, b);
                expct[k] = cell(b[0], b[1], b[2], b[3], 64, nullptr, nullptr);
            }
            total += expct[k];
            expct[k] *= kSamples;
        }
    EXPECT_NEAR(total, 1.0, 3e-3) << "pdf_li must integrate to 1 over the light's directions";
    auto r = chi2_test(obs, expct);
    EXPECT_GT(r.p_value, kAlpha) << r.message;
}

// pdf_li at the sampled direction equals the pdf sample_li reported (relative 1e-3).
template <class L, class Pdf>
void expect_pdf_consistent(const L& light, const LightSampleContext& ctx, Pdf&& pdf_at, uint64_t seed) {
    PCG32 rng(seed, 11);
    int valid = 0;
    for (int i = 0; i < 20000; ++i) {
        auto s = light.sample_li(ctx, rng.next_2d());
        if (!s) continue;
        ++valid;
        ASSERT_GT(s->pdf, 0.f);
        ASSERT_TRUE(s->L.is_finite() && !s->L.has_negative());
        float p = pdf_at(*s);
        ASSERT_NEAR(p, s->pdf, 1e-3f * s->pdf) << "sample " << i << " wi " << to_string(s->wi);
    }
    EXPECT_GT(valid, 10000);
}
}  // namespace

TEST(LightChi2, AreaTrianglesByArea) {
    auto tris = test::planar_light_triangles();
    AreaLight light(test::mesh_of(tris), Spectrum(1.f), /*two_sided=*/true);
    LightSampleContext ctx{Point3f(0.3f, 0.f, 0.2f), Normal3f(0, 1, 0)};
    Vec3f axis = normalize(Point3f(0.6f, 2.f, 0.3f) - ctx.p);
    double z_min = 1;
    for (const auto& v : tris) z_min = std::min(z_min, double(dot(normalize(v - ctx.p), axis)));
    z_min -= 0.02;
    auto pdf = [&](const Vec3f& w) -> double {
        auto h = test::hit_triangles(tris, ctx.p, w);
        return h ? light.pdf_li(ctx, w, h->first, h->second) : 0.0;
    };
    chi2_cone([&](Vec2f u) -> std::optional<Vec3f> {
        auto s = light.sample_li(ctx, u);
        return s ? std::optional<Vec3f>(s->wi) : std::nullopt;
    }, pdf, axis, z_min, 1);
    expect_pdf_consistent(light, ctx, [&](const LightLiSample& s) {
        return light.pdf_li(ctx, s.wi, s.p_light, s.n_light);
    }, 2);
}

TEST(LightChi2, AreaSphereFromOutsideByCone) {
    const Point3f c(0.4f, 3.f, -0.2f);
    const float r = 1.2f;
    AreaLight light(c, r, false, Spectrum(2.f), false);
    LightSampleContext ctx{Point3f(0.f), Normal3f(0, 1, 0)};
    Vec3f to_c = c - ctx.p;
    double z_min = std::sqrt(1.0 - double(r) * r / double(length2(to_c)));
    auto pdf = [&](const Vec3f& w) -> double {
        auto h = test::hit_sphere(c, r, ctx.p, w);
        return h ? light.pdf_li(ctx, w, h->first, h->second) : 0.0;
    };
    chi2_cone([&](Vec2f u) -> std::optional<Vec3f> {
        auto s = light.sample_li(ctx, u);
        return s ? std::optional<Vec3f>(s->wi) : std::nullopt;
    }, pdf, to_c, z_min, 3);
    expect_pdf_consistent(light, ctx, [&](const LightLiSample& s) {
        return light.pdf_li(ctx, s.wi, s.p_light, s.n_light);
    }, 4);
    // The sampled point is on the sphere, on the side facing the receiver.
    PCG32 rng(5, 1);
    for (int i = 0; i < 1000; ++i) {
        auto s = light.sample_li(ctx, rng.next_2d());
        ASSERT_TRUE(s);
        EXPECT_NEAR(length(s->p_light - c), r, 1e-4f * r);
        EXPECT_LT(dot(s->n_light, s->wi), 0.f);
    }
}

TEST(LightSampling, AreaSphereNarrowCone) {
    // A sphere under 1° wide (sin²θmax = 1e-4 < sin² 1.5°): the cone is sampled with sin²θ =
    // u sin²θmax, so sin²θ/sin²θmax of the samples is uniform on [0, 1): its mean is 1/2 within
    // 5σ (σ = 1/√(12 N); a false alarm has probability 6e-7). Every sample is a point on the sphere
    // facing the receiver, on the ray ctx.p + t wi, with the density pdf_li gives.
    const Point3f c(3.f, 100.f, -2.f);
    const float r = 1.0045f;
    AreaLight light(c, r, false, Spectrum(1.f), false);
    LightSampleContext ctx{Point3f(0.f), Normal3f(0, 1, 0)};
    const Vec3d axis = glm::normalize(Vec3d(c - ctx.p));
    const double sin2_max = double(r) * r / glm::dot(Vec3d(c), Vec3d(c));
    ASSERT_LT(sin2_max, double(kSphereNarrowSin2));
    PCG32 rng(12, 5);
    constexpr int kN = 100000;
    double sum = 0.0;
    for (int i = 0; i < kN; ++i) {
        auto s = light.sample_li(ctx, rng.next_2d());
        ASSERT_TRUE(s);
        const double cos_t = glm::dot(Vec3d(s->wi), axis);
        sum += std::max(0.0, 1.0 - cos_t * cos_t) / sin2_max;
        ASSERT_NEAR(length(s->p_light - c), r, 1e-4f * r);
        ASSERT_LT(dot(s->n_light, s->wi), 0.f);
        const Vec3d off = glm::cross(Vec3d(s->p_light - ctx.p), Vec3d(s->wi));  // distance of p_light off the ray
        ASSERT_LT(glm::length(off), 1e-3);
        ASSERT_NEAR(light.pdf_li(ctx, s->wi, s->p_light, s->n_light), s->pdf, 1e-6f * s->pdf);
    }
    EXPECT_NEAR(sum / kN, 0.5, 5.0 / std::sqrt(12.0 * kN));
}

TEST(LightChi2, AreaSphereFromInsideByArea) {
    const Point3f c(0.f);
    const float r = 2.f;
    AreaLight light(c, r, /*flip_normals=*/true, Spectrum(1.f), false);
    LightSampleContext ctx{Point3f(0.5f, 0.3f, -0.4f), Normal3f(0.f)};
    auto pdf = [&](const Vec3f& w) -> double {
        auto h = test::hit_sphere(c, r, ctx.p, w);
        return h ? light.pdf_li(ctx, w, h->first, -h->second) : 0.0;
    };
    chi2_cone([&](Vec2f u) -> std::optional<Vec3f> {
        auto s = light.sample_li(ctx, u);
        return s ? std::optional<Vec3f>(s->wi) : std::nullopt;
    }, pdf, Vec3f(0, 0, 1), -1.0, 6);
    expect_pdf_consistent(light, ctx, [&](const LightLiSample& s) {
        return light.pdf_li(ctx, s.wi, s.p_light, s.n_light);
    }, 7);
}

TEST(LightChi2, ConstantUniformSphere) {
    ConstantLight light(Spectrum(0.7f));
    LightSampleContext ctx{Point3f(1.f, 2.f, 3.f), Normal3f(0, 0, 1)};
    chi2_cone([&](Vec2f u) -> std::optional<Vec3f> {
        auto s = light.sample_li(ctx, u);
        return s ? std::optional<Vec3f>(s->wi) : std::nullopt;
    }, [&](const Vec3f& w) { return double(light.pdf_li(ctx, w)); }, Vec3f(0, 0, 1), -1.0, 8);
    expect_pdf_consistent(light, ctx, [&](const LightLiSample& s) { return light.pdf_li(ctx, s.wi); }, 9);
}

TEST(LightChi2, EnvmapOnAnEqualAreaGrid) {
    // A generic sphere grid, independent of the map's cells (the pdf is refined where it jumps).
    EnvmapLight light(test::asymmetric_envmap_image(), 1.5f, test::test_rotation());
    LightSampleContext ctx{Point3f(0.f), Normal3f(0.f)};
    chi2_cone([&](Vec2f u) -> std::optional<Vec3f> {
        auto s = light.sample_li(ctx, u);
        return s ? std::optional<Vec3f>(s->wi) : std::nullopt;
    }, [&](const Vec3f& w) { return double(light.pdf_li(ctx, w)); }, Vec3f(0, 0, 1), -1.0, 10, 40, 80);
    expect_pdf_consistent(light, ctx, [&](const LightLiSample& s) { return light.pdf_li(ctx, s.wi); }, 11);
}

TEST(LightChi2, EnvmapOnItsOwnCells) {
    // Bins are the map's sampling cells (u' = u − ½/W, v = θ/π) halved each way, reached through
    // the inverse of to_world: the expected counts are then exact (N·p(u,v)·area), so the test
    // resolves the density cell by cell. Sampled directions must never land in black cells.
    const int W = 8, H = 5;
    const Mat3f R = test::test_rotation();
    EnvmapLight light(test::asymmetric_envmap_image(W, H), 1.f, R);
    const int nu = 2 * W, nv = 2 * (H - 1);
    std::vector<double> obs(size_t(nu * nv), 0.0), expct(size_t(nu * nv), 0.0);
    PCG32 rng(12, 5);
    LightSampleContext ctx;
    for (int i = 0; i < kSamples; ++i) {
        auto s = light.sample_li(ctx, rng.next_2d());
        if (!s) continue;
        Vec2f uv = EnvmapLight::direction_to_uv(glm::transpose(R) * s->wi);
        double up = double(uv.x) - 0.5 / W;
        up -= std::floor(up);
        int iu = std::min(nu - 1, int(up * nu)), iv = std::min(nv - 1, int(double(uv.y) * nv));
        obs[size_t(iv * nu + iu)] += 1;
    }
    double total = 0;
    for (int iv = 0; iv < nv; ++iv)
        for (int iu = 0; iu < nu; ++iu) {
            // ∫ pdf dω over the bin = ∫∫ pdf(ω(u,v)) 2π² sin θ du dv; the integrand is bilinear in
            // (u, v) inside a sampling cell (each bin lies in one), so its midpoint value is its mean.
            double u = (iu + 0.5) / nu + 0.5 / W, v = (iv + 0.5) / nv;
            float st;
            Vec3f w = R * EnvmapLight::uv_to_direction(Vec2f(float(u), float(v)), &st);
            double p = double(light.pdf_li(ctx, normalize(w))) * 2 * M_PI * M_PI * st / (double(nu) * nv);
            expct[size_t(iv * nu + iu)] = p * kSamples;
            total += p;
        }
    EXPECT_NEAR(total, 1.0, 1e-4);
    auto r = chi2_test(obs, expct);
    EXPECT_GT(r.p_value, kAlpha) << r.message;
}

// The environment map's placement inside a cell (sampling/piecewise_2d.h, sample_bilinear): the
// points follow bilinear_density, which integrates to 1, for corners of mixed size, with zeros on an
// edge and in three corners, equal (uniform) and all zero (uniform). 16 × 16 bins; the density is
// bilinear, so its value at a bin's midpoint is its mean there and the expected counts are exact.
TEST(LightChi2, BilinearCellSampling) {
    const float corners[5][4] = {{1.f, 2.f, 3.f, 4.f}, {0.f, 0.f, 1.f, 5.f}, {0.f, 3.f, 0.f, 0.f}, {2.f, 2.f, 2.f, 2.f}, {0.f, 0.f, 0.f, 0.f}};
    constexpr int n = 16;
    for (int c = 0; c < 5; ++c) {
        const float a = corners[c][0], b = corners[c][1], cc = corners[c][2], d = corners[c][3];
        std::vector<double> obs(n * n, 0.0), expct(n * n, 0.0);
        double total = 0.0;
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const double p = double(bilinear_density<float>((float(i) + 0.5f) / n, (float(j) + 0.5f) / n, a, b, cc, d));
                expct[size_t(j * n + i)] = p * kSamples / (n * n);
                total += p / (n * n);
            }
        EXPECT_NEAR(total, 1.0, 1e-6) << c;
        PCG32 rng(31, uint64_t(c));
        for (int k = 0; k < kSamples; ++k) {
            const Vec2f u = rng.next_2d();
            const V2<float> st = sample_bilinear<float>(u.x, u.y, a, b, cc, d);
            ASSERT_TRUE(st.x >= 0.f && st.x < 1.f && st.y >= 0.f && st.y < 1.f) << c << ": " << st.x << ", " << st.y;
            obs[size_t(std::min(n - 1, int(st.y * n)) * n + std::min(n - 1, int(st.x * n)))] += 1;
        }
        auto r = chi2_test(obs, expct);
        EXPECT_GT(r.p_value, kAlpha) << "corners " << c << ": " << r.message;
    }
    // The linear warp: identity for equal ends, √ξ from a zero end, and its ends.
    EXPECT_EQ(sample_linear<float>(0.3f, 2.f, 2.f), 0.3f);
    EXPECT_FLOAT_EQ(sample_linear<float>(0.25f, 0.f, 7.f), 0.5f);
    EXPECT_EQ(sample_linear<float>(0.f, 1.f, 3.f), 0.f);
    EXPECT_LT(sample_linear<float>(0x1.fffffep-1f, 3.f, 0.f), 1.f);
}
