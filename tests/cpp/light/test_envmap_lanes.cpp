// Environment maps and delta lights on packets (light/envmap.h, light/point.h, light/light_table.h):
// lanes equal scalars, bit for bit (a bound of 0 ulp: the templates use IEEE-exact lane operations
// only, the spot's acos among them (math/lane_atan.h), and the library is built without
// contraction), for the light table's sampling over lanes of mixed kinds (two maps of different
// sizes and rotations, a sphere, a constant environment, a point light, two spot lights, a
// directional light and a mesh area light with no packet form), the maps' density and radiance,
// and the radiance escaping rays take from the lights at infinity. Inputs: fixed-seed random u,
// directions and points, u at 0, 1/2, 1 − 2⁻²⁴ and 1e-7, directions at the poles and on the seam
// u = 0/1 (both signs of zero), points at the point light itself, every third packet partially
// masked; with both maps, and with map A alone (the other a constant environment: every envmap lane
// reads the one map, LightTable::sole_envmap). The float instantiation is EnvmapLight's, PointLight's, SpotLight's and
// DirectionalLight's own sample_li (and the envmap's pdf_li and Le), and the float CDF's density is
// that of the cell each sample lies in; the mapping's angles match libm to float precision.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "light/envmap_probe.h"
#include "light_cases.h"
#include "pellucid/integrator/simd_target.h"
#include "pellucid/light/light.h"
#include "pellucid/sampling/rng.h"
#include "support/probe_outputs.h"

using namespace pellucid;

namespace pellucid::envmap_probe {
#ifdef PELLUCID_ENVMAP_PROBE_AVX512
void run_avx512(const In& in, Out& out);
#endif
#ifdef PELLUCID_ENVMAP_PROBE_AVX2
void run_avx2(const In& in, Out& out);
#endif
#ifdef PELLUCID_ENVMAP_PROBE_SSE4
void run_sse4(const In& in, Out& out);
#endif
}  // namespace pellucid::envmap_probe

namespace {
constexpr int kEnvA = 0, kEnvB = 3;  // the maps' indices in Cases::lights
constexpr int kLights = 9;
const Point3f kPointAt(0.25f, -0.125f, 0.375f);  // the point light (some cases' points lie on it)
const float kPmf[kLights] = {0.1f, 0.1f, 0.2f, 0.15f, 0.1f, 0.1f, 0.1f, 0.05f, 0.1f};

struct Cases {
    static constexpr int kN = 4096;
    std::vector<Light> lights;
    LightTable table;
    std::vector<float> a[9];
    std::unique_ptr<bool[]> active{new bool[kN]}, specular{new bool[kN]};
    std::vector<int32_t> light;
    envmap_probe::In in;

    /// one_map: map B is a second constant environment instead, so that the table's envmap lanes
    /// all read its one map (LightTable::sole_envmap, whose values need no gathers).
    explicit Cases(bool one_map = false) {
        // Map A: 8×5 under a tilted rotation; map B: 13×7, unrotated; both with black columns.
        lights = {EnvmapLight(test::asymmetric_envmap_image(), 1.5f, test::test_rotation()),
                  AreaLight(Point3f(0.3f, 0.2f, -0.1f), 0.5f, false, Spectrum(1.f, 2.f, 3.f), false),
                  ConstantLight(Spectrum(0.25f, 0.5f, 1.f)),
                  one_map ? Light(ConstantLight(Spectrum(0.5f, 0.25f, 0.125f)))
                          : Light(EnvmapLight(test::asymmetric_envmap_image(13, 7), 0.7f, Mat3f(1.f))),
                  PointLight(kPointAt, Spectrum(1.f, 0.5f, 2.f)),
                  // From 2 above, the cases' points span about 25° off the axis: dark, ramp and
                  // full beam all occur.
                  SpotLight(Point3f(0.f, 2.f, 0.f), Vec3f(0.1f, -1.f, 0.05f), Spectrum(3.f, 2.f, 1.f), 20.f, 8.f),
                  DirectionalLight(Vec3f(-0.3f, -1.f, 0.4f), Spectrum(2.f, 1.f, 0.5f), 10.f),
                  AreaLight(test::mesh_of(test::planar_light_triangles()), Spectrum(1.f), false),
                  // Beam 0: all ramp, to 30° off a tilted axis from below (some points lie beyond).
                  SpotLight(Point3f(0.1f, -1.5f, 0.2f), Vec3f(-0.2f, 1.f, 0.3f), Spectrum(0.5f), 30.f, 0.f)};
        table = make_light_table(lights, std::vector<float>(kPmf, kPmf + kLights));
        PCG32 rng(3, 17);
        for (auto& v : a) v.resize(kN);
        light.resize(kN);
        const float us[] = {0.f, 0.5f, kOneMinusEpsilon, 1e-7f};
        // Directions in a map's frame: the poles, the seam (x = ±0 and ±1e-8 toward −z).
        const Vec3f special[] = {{0, 1, 0}, {0, -1, 0}, {0.f, 0.f, -1.f}, {-0.f, 0.f, -1.f},
                                 {1e-8f, 0.3f, -0.95f}, {-1e-8f, -0.3f, -0.95f}, {0.f, 0.6f, 0.8f}};
        for (int i = 0; i < kN; ++i) {
            light[size_t(i)] = int32_t((i / 3 + i / 64) % kLights);
            const Mat3f R = light[size_t(i)] == kEnvA ? test::test_rotation() : Mat3f(1.f);
            for (int c = 0; c < 2; ++c) a[c][size_t(i)] = i % 7 < 3 ? us[(i / 7 + c) % 4] : rng.next_float();
            Vec3f d = square_to_uniform_sphere(Vec2f(rng.next_float(), rng.next_float()));
            if (i % 5 == 0) d = R * normalize(special[(i / 5) % 7]);
            for (int c = 0; c < 3; ++c) a[2 + c][size_t(i)] = d[c];
            for (int c = 0; c < 3; ++c) a[5 + c][size_t(i)] = i % 11 == 4 ? kPointAt[c] : rng.next_float() - 0.5f;
            a[8][size_t(i)] = i % 9 == 0 ? 0.f : (i % 9 == 1 ? kInfinity : 4.f * rng.next_float());
            active[i] = (i / 16) % 3 != 1 || i % 5 != 0;  // every third packet partially masked
            specular[i] = i % 6 == 0;
        }
        in.n = kN;
        in.u[0] = a[0].data(), in.u[1] = a[1].data();
        for (int c = 0; c < 3; ++c) in.d[c] = a[2 + c].data(), in.p[c] = a[5 + c].data();
        in.prev_pdf = a[8].data();
        in.active = active.get();
        in.specular = specular.get();
        in.lights = &table;
        in.light = light.data();
    }
};

using Outputs = test::ProbeOutputs<envmap_probe::Out, envmap_probe::kOutputs, Cases::kN>;
using test::same_bits;
}  // namespace

class EnvmapLanesMaps : public ::testing::TestWithParam<bool> {};
INSTANTIATE_TEST_SUITE_P(Maps, EnvmapLanesMaps, ::testing::Values(false, true),
                         [](const auto& info) { return info.param ? "OneMap" : "TwoMaps"; });

TEST_P(EnvmapLanesMaps, EveryTargetEveryLaneEqualsTheFloatInstantiation) {
    const Cases cases(GetParam());
    EXPECT_EQ(cases.table.sole_envmap, GetParam() ? kEnvA : -1);
    Outputs scalar;
    envmap_probe::run<float>(cases.in, scalar.out);
    size_t env_valid = 0;
    for (int i = 0; i < Cases::kN; ++i)
        env_valid += cases.active[i] && std::holds_alternative<EnvmapLight>(cases.lights[size_t(cases.light[size_t(i)])]) &&
                     scalar.at(0, i) == 1.f;
    EXPECT_GT(env_valid, size_t(Cases::kN) / (GetParam() ? 20 : 10));  // the probe sampled the map(s)
    int targets = 0;
    for (SimdTarget t : available_simd_targets()) {
        Outputs packet;
        switch (t) {
#ifdef PELLUCID_ENVMAP_PROBE_AVX512
            case SimdTarget::AVX512: envmap_probe::run_avx512(cases.in, packet.out); break;
#endif
#ifdef PELLUCID_ENVMAP_PROBE_AVX2
            case SimdTarget::AVX2: envmap_probe::run_avx2(cases.in, packet.out); break;
#endif
#ifdef PELLUCID_ENVMAP_PROBE_SSE4
            case SimdTarget::SSE4: envmap_probe::run_sse4(cases.in, packet.out); break;
#endif
            default: continue;
        }
        ++targets;
        EXPECT_EQ(test::count_differing(scalar, packet, to_string(t).c_str()), 0u) << to_string(t);
    }
    RecordProperty("targets", targets);
}

TEST(EnvmapLanes, ACaseChangedInOneLaneIsSeen) {
    // The comparison itself: one lane's u changed changes that lane's outputs only.
    Cases cases;
    Outputs x, y;
    envmap_probe::run<float>(cases.in, x.out);
    ASSERT_EQ(cases.light[9], kEnvB);
    const_cast<float*>(cases.in.u[0])[9] = 0.37f;
    envmap_probe::run<float>(cases.in, y.out);
    std::vector<int> changed = test::differing_cases(x, y);
    EXPECT_FALSE(changed.empty());
    for (int i : changed) EXPECT_EQ(i, 9);
    // A spot light's lane: its point moved changes that lane only.
    ASSERT_EQ(cases.light[15], 5);
    ASSERT_EQ(x.at(0, 15), 1.f);  // lit
    const_cast<float*>(cases.in.p[0])[15] += 0.01f;
    envmap_probe::run<float>(cases.in, y.out);
    changed = test::differing_cases(x, y);
    EXPECT_EQ(changed, std::vector<int>({9, 15}));
}

TEST_P(EnvmapLanesMaps, FloatInstantiationIsTheScalarLight) {
    // The table's float lanes give exactly what EnvmapLight::sample_li, pdf_li and Le give, and the
    // escaped radiance what the per-light sum gives.
    const Cases cases(GetParam());
    Outputs o;
    envmap_probe::run<float>(cases.in, o.out);
    const LightSampleContext ctx;
    size_t delta_valid[kLights] = {}, delta_invalid[kLights] = {}, mesh_valid = 0, mesh_invalid = 0;
    for (int i = 0; i < Cases::kN; ++i) {
        if (!cases.active[i]) continue;
        const size_t li = size_t(cases.light[size_t(i)]);
        const Vec3f d(cases.a[2][size_t(i)], cases.a[3][size_t(i)], cases.a[4][size_t(i)]);
        const Vec2f u(cases.a[0][size_t(i)], cases.a[1][size_t(i)]);
        auto at = [&](int k) { return o.at(k, i); };
        const Light& light = cases.lights[li];
        if (std::holds_alternative<PointLight>(light) || std::holds_alternative<SpotLight>(light) ||
            std::holds_alternative<DirectionalLight>(light)) {
            // A delta light: its sample_li seen from the case's point, and the shadow ray's ends
            // (a point with zero normal and error bound, or at infinity).
            const LightSampleContext seen{Point3f(cases.a[5][size_t(i)], cases.a[6][size_t(i)], cases.a[7][size_t(i)]),
                                        Normal3f(0.f, 1.f, 0.f)};
            const auto s = std::visit([&](const auto& l) { return l.sample_li(seen, u); }, light);
            ASSERT_EQ(at(0) == 1.f, s.has_value()) << i;
            EXPECT_EQ(at(28), 1.f) << i;  // delta
            ++(s ? delta_valid : delta_invalid)[li];
            if (s) {
                EXPECT_TRUE(s->delta);
                EXPECT_EQ(at(1) == 1.f, s->infinite) << i;
                EXPECT_TRUE(same_bits(at(2), s->wi.x) && same_bits(at(3), s->wi.y) && same_bits(at(4), s->wi.z)) << i;
                EXPECT_TRUE(same_bits(at(5), s->L.r) && same_bits(at(6), s->L.g) && same_bits(at(7), s->L.b)) << i;
                EXPECT_TRUE(same_bits(at(8), s->pdf)) << i;
                if (!s->infinite)
                    for (int c = 0; c < 3; ++c) {
                        EXPECT_TRUE(same_bits(at(19 + c), s->p_light[c])) << i;
                        EXPECT_TRUE(same_bits(at(22 + c), s->n_light[c])) << i;
                        EXPECT_TRUE(same_bits(at(25 + c), s->p_error[c])) << i;
                    }
            }
        } else if (!std::holds_alternative<EnvmapLight>(light)) {
            EXPECT_EQ(at(28), 0.f) << i;  // not a delta light
        }
        if (const auto* m = std::get_if<AreaLight>(&light); m && !m->is_sphere()) {
            // A mesh light: its sample_li seen from the case's point, with the shadow ray's end.
            const LightSampleContext seen{Point3f(cases.a[5][size_t(i)], cases.a[6][size_t(i)], cases.a[7][size_t(i)]),
                                        Normal3f(0.f, 1.f, 0.f)};
            const auto s = m->sample_li(seen, u);
            ASSERT_EQ(at(0) == 1.f, s.has_value()) << i;
            ++(s ? mesh_valid : mesh_invalid);
            if (s) {
                EXPECT_EQ(at(1), 0.f) << i;  // not at infinity
                EXPECT_TRUE(same_bits(at(2), s->wi.x) && same_bits(at(3), s->wi.y) && same_bits(at(4), s->wi.z)) << i;
                EXPECT_TRUE(same_bits(at(5), s->L.r) && same_bits(at(6), s->L.g) && same_bits(at(7), s->L.b)) << i;
                EXPECT_TRUE(same_bits(at(8), s->pdf)) << i;
                for (int c = 0; c < 3; ++c) {
                    EXPECT_TRUE(same_bits(at(19 + c), s->p_light[c])) << i;
                    EXPECT_TRUE(same_bits(at(22 + c), s->n_light[c])) << i;
                    EXPECT_TRUE(same_bits(at(25 + c), s->p_error[c])) << i;
                }
            }
        }
        if (const auto* e = std::get_if<EnvmapLight>(&light)) {
            const auto s = e->sample_li(ctx, u);
            ASSERT_EQ(at(0) == 1.f, s.has_value()) << i;
            EXPECT_EQ(at(1), 1.f);
            if (s) {
                EXPECT_TRUE(same_bits(at(2), s->wi.x) && same_bits(at(3), s->wi.y) && same_bits(at(4), s->wi.z)) << i;
                EXPECT_TRUE(same_bits(at(5), s->L.r) && same_bits(at(6), s->L.g) && same_bits(at(7), s->L.b)) << i;
                EXPECT_TRUE(same_bits(at(8), s->pdf)) << i;
            }
            const Spectrum Le = e->Le(d);
            EXPECT_TRUE(same_bits(at(9), e->pdf_li(ctx, d))) << i;
            EXPECT_TRUE(same_bits(at(10), Le.r) && same_bits(at(11), Le.g) && same_bits(at(12), Le.b)) << i;
        }
        Spectrum esc(0.f);
        for (size_t k = 0; k < cases.lights.size(); ++k) {
            const InfiniteHit h = infinite_hit(cases.lights[k], ctx, d);
            const bool area_at_infinity = std::holds_alternative<ConstantLight>(cases.lights[k]) ||
                                          std::holds_alternative<EnvmapLight>(cases.lights[k]);
            if (!area_at_infinity) continue;
            esc += h.Le * bsdf_hit_weight<float>(true, true, cases.specular[i], cases.a[8][size_t(i)], kPmf[k] * h.pdf);
        }
        EXPECT_TRUE(same_bits(at(13), esc.r) && same_bits(at(14), esc.g) && same_bits(at(15), esc.b))
            << i << ": " << at(13) << " vs " << esc.r;
        // The spot falloff and the point light's sample alone.
        const float cos_theta = cases.a[1][size_t(i)] * 2.f - 1.f;
        EXPECT_TRUE(same_bits(at(29), spot_falloff<float>(cos_theta, 0.9f, 0.45f, 0.2f))) << i;
        const Point3f p(cases.a[5][size_t(i)], cases.a[6][size_t(i)], cases.a[7][size_t(i)]);
        const auto pt = PointLight(kPointAt, Spectrum(3.f)).sample_li({p}, u);
        ASSERT_EQ(at(31) == 1.f, pt.has_value()) << i;
        if (pt) EXPECT_TRUE(same_bits(at(30), pt->L.r)) << i;
    }
    // Every delta light was sampled; the point light was also seen from itself (no sample), and
    // each spot's dark side was reached.
    for (int li : {4, 5, 6, 8}) EXPECT_GT(delta_valid[li], 50u) << li;
    for (int li : {4, 5, 8}) EXPECT_GT(delta_invalid[li], 0u) << li;
    EXPECT_EQ(delta_invalid[6], 0u);
    // The mesh light was sampled (the cases' points all lie on its emitting side).
    EXPECT_GT(mesh_valid, 50u);
    EXPECT_EQ(mesh_invalid, 0u);
}

TEST(EnvmapLanes, SamplesLieInTheCellWhoseDensityTheyCarry) {
    // The float-CDF distribution: each sample lies in the cell it reports, carries exactly that
    // cell's density (which is what pdf() gives there), and never lands in a cell of zero weight.
    const std::vector<float> w = {0.f, 1.f, 3.f, 0.f, 2.f, 0.5f, 0.f, 0.f, 0.f, 1e-9f, 7.f, 1.f};
    std::vector<float> buf;
    const Piecewise2DLayout l = append_piecewise_2d(buf, w, 4, 3);
    const Piecewise2DLanes<float> d{buf.data(), l.marginal, l.conditional, l.nu, l.nv};
    PCG32 rng(5, 9);
    int inside = 0;
    for (int n = 0; n < 20000; ++n) {
        const Vec2f u = n < 4 ? Vec2f(n % 2 ? kOneMinusEpsilon : 0.f, n / 2 ? kOneMinusEpsilon : 0.f) : rng.next_2d();
        const Piecewise2DSample<float> s = sample_piecewise_2d<float>(d, u);
        ASSERT_GT(s.pdf, 0.f);
        ASSERT_GT(w[size_t(s.j * 4 + s.i)], 0.f) << s.i << "," << s.j;
        EXPECT_GE(s.p.x * 4.f, float(s.i));
        EXPECT_LE(s.p.x * 4.f, float(s.i + 1));
        EXPECT_GE(s.p.y * 3.f, float(s.j));
        EXPECT_LE(s.p.y * 3.f, float(s.j + 1));
        EXPECT_EQ(s.pdf, piecewise_2d_cell_pdf<float>(d, s.i, s.j));
        if (int(s.p.x * 4.f) == s.i && int(s.p.y * 3.f) == s.j) {
            ++inside;
            EXPECT_EQ(s.pdf, piecewise_2d_pdf<float>(d, s.p));
        }
    }
    EXPECT_GT(inside, 19990);
    // The density is the weights' (sum 14.500000001 over 12 cells of area 1/12), up to float CDFs.
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 4; ++i)
            EXPECT_NEAR(piecewise_2d_cell_pdf<float>(d, i, j), double(w[size_t(j * 4 + i)]) * 12.0 / 14.500000001, 1e-5)
                << i << "," << j;
    // All zero: uniform.
    std::vector<float> b2;
    const Piecewise2DLayout z = append_piecewise_2d(b2, std::vector<float>(6, 0.f), 3, 2);
    const Piecewise2DLanes<float> dz{b2.data(), z.marginal, z.conditional, z.nu, z.nv};
    EXPECT_FLOAT_EQ(piecewise_2d_pdf<float>(dz, Vec2f(0.7f, 0.2f)), 1.f);
}

// The guided search finds the cell a search of the whole CDF finds: on a 37 × 11 distribution of
// high contrast with empty cells and runs of them, at every CDF value and every guide boundary k/n
// and one float either side of each, and at random u. (A guide entry off by one cell fails here.)
TEST(EnvmapLanes, GuidedCdfSearchFindsTheWholeSearchsCell) {
    constexpr int nu = 37, nv = 11;
    std::vector<float> w(size_t(nu) * nv);
    PCG32 rng(77, 3);
    for (size_t k = 0; k < w.size(); ++k) {
        const float r = rng.next_float();
        w[k] = r < 0.3f ? 0.f : r < 0.95f ? r : 1e4f * r;  // empty cells, a few very bright ones
    }
    for (int i = 5; i < 20; ++i) w[size_t(4 * nu + i)] = 0.f;  // a run of empty cells
    std::vector<float> buf;
    const Piecewise2DLayout l = append_piecewise_2d(buf, w, nu, nv);
    const Piecewise2DLanes<float> d{buf.data(), l.marginal, l.conditional, l.nu, l.nv};
    // The reference: the largest i < n with cdf[i] ≤ u (std::upper_bound over the whole CDF).
    auto whole = [](const float* cdf, int n, float u) {
        return int(std::min<std::ptrdiff_t>(std::upper_bound(cdf + 1, cdf + n + 1, u) - (cdf + 1), n - 1));
    };
    auto probes = [](const float* cdf, int n) {
        std::vector<float> us;
        auto around = [&](float u) {
            for (float v : {std::nextafter(u, 0.f), u, std::nextafter(u, 1.f)})
                if (v >= 0.f && v < 1.f) us.push_back(v);
        };
        for (int i = 0; i <= n; ++i) around(cdf[i]);
        for (int k = 0; k <= n; ++k) around(float(k) / float(n));
        return us;
    };
    int checked = 0;
    const float* marginal = buf.data() + l.marginal;
    for (float uy : probes(marginal, nv)) {
        const int j = whole(marginal, nv, uy);
        EXPECT_EQ(detail::cdf_find<float>(d.base, l.marginal, nv, uy, d.guide_offset()), j) << uy;
        const int32_t row = l.conditional + j * (nu + 1);
        std::vector<float> uxs = probes(buf.data() + row, nu);
        for (int r = 0; r < 64; ++r) uxs.push_back(rng.next_float());
        for (float ux : uxs) {
            const Piecewise2DSample<float> s = sample_piecewise_2d<float>(d, Vec2f(ux, uy));
            ASSERT_EQ(s.j, j) << ux << ", " << uy;
            ASSERT_EQ(s.i, whole(buf.data() + row, nu, ux)) << ux << ", " << uy;
            ++checked;
        }
    }
    EXPECT_GT(checked, 5000);
}

TEST(EnvmapLanes, LaneAcosMatchesLibm) {
    // The spot falloff's angle (lane_math::acos_t, math/lane_atan.h) against double libm over a
    // 2⁻²² grid of [−1, 1] and its ends, absolute error (float resolution of angles up to π).
    double worst = 0.0;
    for (int i = -(1 << 22); i <= (1 << 22); ++i) {
        const float c = float(i) * 0x1p-22f;
        worst = std::max(worst, std::abs(double(lane_math::acos_t(c)) - std::acos(double(c))));
    }
    for (float c : {1.f, -1.f, 0.f, 1.f - 0x1p-24f, -1.f + 0x1p-24f, 0.5f, 0.90630779f, 0.81915206f})
        worst = std::max(worst, std::abs(double(lane_math::acos_t(c)) - std::acos(double(c))));
    EXPECT_EQ(lane_math::acos_t(1.f), 0.f);
    EXPECT_EQ(lane_math::acos_t(1.5f), 0.f);  // clamped
    EXPECT_LT(worst, 4e-7);  // measured 2.9e-7 (the float ulp of π is 2.4e-7)
}

TEST(EnvmapLanes, AnglesMatchLibmToFloatPrecision) {
    // The lat-long mapping's own atan2 and sin/cos (no libm, envmap.h) against double libm: u and v
    // within 1.5e-7 (a few float ulps of 1; u compared around the seam), directions within 2e-7
    // (measured: 1.0e-7 and 1.3e-7).
    PCG32 rng(21, 4);
    double worst_uv = 0.0, worst_d = 0.0;
    for (int n = 0; n < 200000; ++n) {
        const Vec3f d = square_to_uniform_sphere(rng.next_2d());
        const Vec2f uv = EnvmapLight::direction_to_uv(d);
        ASSERT_GE(uv.x, 0.f);
        ASSERT_LT(uv.x, 1.f);
        double u = std::atan2(double(d.x), -double(d.z)) / (2.0 * M_PI);
        u -= std::floor(u);
        double du = std::abs(double(uv.x) - u);
        du = std::min(du, 1.0 - du);
        // (θ from atan2(sin θ, cos θ) of the float direction: acos of a nearly unit d.y is
        // ill-conditioned at the poles.)
        const double v = std::atan2(std::hypot(double(d.x), double(d.z)), double(d.y)) / M_PI;
        worst_uv = std::max({worst_uv, du, std::abs(double(uv.y) - v)});
        const Vec2f q = rng.next_2d();
        float st;
        const Vec3f w = EnvmapLight::uv_to_direction(q, &st);
        const double th = M_PI * double(q.y), ph = 2.0 * M_PI * double(q.x);
        worst_d = std::max({worst_d, std::abs(double(w.x) - std::sin(ph) * std::sin(th)), std::abs(double(w.y) - std::cos(th)),
                            std::abs(double(w.z) + std::cos(ph) * std::sin(th)), std::abs(double(st) - std::sin(th))});
    }
    EXPECT_LT(worst_uv, 1.5e-7);
    EXPECT_LT(worst_d, 2e-7);
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.3g / %.3g", worst_uv, worst_d);
    RecordProperty("worst_uv_and_direction", buf);
}
