// Lanes equal scalars: the packet code of the path tracer (simd/lane_probe.h: the packet Lambertian's
// eval, pdf and sample, the Fresnel terms, the smooth conductor and the GGX and Beckmann rough
// conductors with their distributions' D, Λ, G, visible-normal density and sampling, the Beckmann
// model's own exp, ln, erfc and erf⁻¹, the concentric-disk and triangle warps, the power heuristic,
// ray offsets, frames, the shading-leak test, emitter sampling, the uniform sphere warp and the
// packet lights' sampling: spheres seen from outside, from inside and as narrow cones, and constant
// environments, mixed within packets with lights that have no packet form) gives on every lane of every SIMD target exactly
// the bits the float instantiation gives for that lane's inputs: a bound of 0 ulp, since the library
// is built without contraction and these functions use only IEEE-exact lane operations. The inputs
// mix reflectances (materials) within a packet, include partially masked packets, and cover the
// edge cases of the property suite's grid: directions on and near the horizon, opposite hemispheres,
// normals at the frame's singular point (0, 0, -1), u at 0, 1/2 and 1 - 2^-24, infinite and zero pdfs.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "pellucid/integrator/simd_target.h"
#include "pellucid/light/light.h"
#include "pellucid/sampling/rng.h"
#include "simd/lane_probe.h"
#include "support/probe_outputs.h"

using namespace pellucid;

namespace pellucid::probe {
#ifdef PELLUCID_PROBE_AVX512
void run_avx512(const In& in, Out& out);
#endif
#ifdef PELLUCID_PROBE_AVX2
void run_avx2(const In& in, Out& out);
#endif
#ifdef PELLUCID_PROBE_SSE4
void run_sse4(const In& in, Out& out);
#endif
}  // namespace pellucid::probe

namespace {
struct Cases {
    static constexpr int kN = 4096;
    std::vector<float> a[3 * 7 + 2];
    std::unique_ptr<bool[]> active{new bool[kN]};
    EmitterTable emitters;
    LightTable lights;
    std::vector<int32_t> light;
    probe::In in;

    Cases() {
        PCG32 rng(7, 11);
        for (auto& v : a) v.resize(kN);
        auto dir = [&](int i, std::vector<float>* d) {
            const Vec3f w = square_to_uniform_sphere(Vec2f(rng.next_float(), rng.next_float()));
            for (int c = 0; c < 3; ++c) d[c][size_t(i)] = w[c];
        };
        std::vector<float>*wo = &a[0], *wi = &a[3], *n = &a[6], *alb = &a[9], *u = &a[12], *p = &a[15], *err = &a[18];
        const float us[] = {0.f, 0.5f, kOneMinusEpsilon, 1e-7f};
        for (int i = 0; i < kN; ++i) {
            dir(i, wo), dir(i, wi), dir(i, n);
            switch (i % 8) {  // edge cases
                case 1: wo[2][size_t(i)] = 0.f; break;                                   // wo on the horizon
                case 2: wi[2][size_t(i)] = 1e-7f; break;                                 // wi grazing
                case 3: n[0][size_t(i)] = n[1][size_t(i)] = 0.f, n[2][size_t(i)] = -1.f; break;  // Duff's singular normal
                case 4: for (int c = 0; c < 3; ++c) n[c][size_t(i)] = wo[c][size_t(i)]; break;    // x parallel to n
                default: break;
            }
            for (int c = 0; c < 3; ++c) {
                alb[c][size_t(i)] = i % 5 == 0 ? 0.f : rng.next_float();
                u[c][size_t(i)] = i % 7 < 4 ? us[(i / 7 + c) % 4] : rng.next_float();
                p[c][size_t(i)] = (rng.next_float() - 0.5f) * (i % 3 == 0 ? 1e4f : 2.f);
                err[c][size_t(i)] = rng.next_float() * 1e-5f;
            }
            a[21][size_t(i)] = i % 9 == 0 ? kInfinity : (i % 9 == 1 ? 0.f : rng.next_float());
            a[22][size_t(i)] = i % 11 == 0 ? 0.f : rng.next_float();
            active[i] = (i / 16) % 3 != 1 || i % 5 != 0;  // every third packet partially masked
        }
        // Five emitting triangles, one-sided and two-sided, with unequal probabilities.
        const float pr[] = {0.1f, 0.3f, 0.15f, 0.25f, 0.2f};
        float acc = 0.f;
        emitters.cdf.push_back(0.f);
        for (int t = 0; t < 5; ++t) {
            for (int k = 0; k < 9; ++k) emitters.data.push_back(float(t) + (rng.next_float() - 0.5f) * 2.f);
            const Vec3f e1(emitters.data[20 * size_t(t) + 3] - emitters.data[20 * size_t(t)],
                           emitters.data[20 * size_t(t) + 4] - emitters.data[20 * size_t(t) + 1],
                           emitters.data[20 * size_t(t) + 5] - emitters.data[20 * size_t(t) + 2]);
            const Vec3f e2(emitters.data[20 * size_t(t) + 6] - emitters.data[20 * size_t(t)],
                           emitters.data[20 * size_t(t) + 7] - emitters.data[20 * size_t(t) + 1],
                           emitters.data[20 * size_t(t) + 8] - emitters.data[20 * size_t(t) + 2]);
            const Vec3f nn = normalize(cross(e1, e2));
            for (int c = 0; c < 3; ++c) emitters.data.push_back(nn[c]);
            for (int c = 0; c < 3; ++c) emitters.data.push_back(1e-6f);
            for (int c = 0; c < 3; ++c) emitters.data.push_back(float(c + t + 1));
            emitters.data.push_back(t % 2 ? 1.f : 0.f);
            emitters.data.push_back(pr[t] * 2.f);
            acc += pr[t];
            emitters.cdf.push_back(t == 4 ? 1.f : acc);
        }
        emitters.search_top = 4;
        emitters.data.insert(emitters.data.end(), EmitterTable::kPad, 0.f);  // (as make_emitter_table pads it)
        // Spheres: one the points see from outside or inside (|p| ≤ 1 or ~5000), a small one (narrow
        // cones), a flipped two-sided one around every point; a constant environment; a point light;
        // a one-sided mesh of three triangles of different areas and one of zero area, above the
        // points, and a two-sided one of one triangle.
        TriangleMesh quads, tri;
        quads.positions = {Point3f(-0.5f, 2.f, -0.5f), Point3f(0.5f, 2.f, -0.5f), Point3f(0.5f, 2.1f, 0.5f),
                           Point3f(-0.5f, 2.f, 0.5f), Point3f(1.5f, 2.f, 0.5f), Point3f(1.5f, 2.f, 0.5f)};
        quads.indices = {0, 1, 2, 0, 2, 3, 1, 4, 2, 4, 5, 5};
        tri.positions = {Point3f(0.f, 0.f, 0.7f), Point3f(0.9f, 0.1f, 0.6f), Point3f(0.1f, 0.8f, 0.8f)};
        tri.indices = {0, 1, 2};
        const std::vector<Light> ls = {AreaLight(Point3f(0.3f, 0.2f, -0.1f), 0.5f, false, Spectrum(1.f, 2.f, 3.f), false),
                                       AreaLight(Point3f(-0.5f, 0.4f, 0.2f), 1e-3f, false, Spectrum(4.f), false),
                                       AreaLight(Point3f(0.f), 1e5f, true, Spectrum(0.5f), true),
                                       ConstantLight(Spectrum(0.25f, 0.5f, 1.f)), PointLight(Point3f(1.f), Spectrum(1.f)),
                                       AreaLight(quads, Spectrum(2.f, 1.f, 0.5f), false),
                                       AreaLight(tri, Spectrum(0.7f), true)};
        lights = make_light_table(ls);
        light.resize(kN);
        for (int i = 0; i < kN; ++i) light[size_t(i)] = int32_t((i / 3 + i / 64) % 7);
        in.lights = &lights;
        in.light = light.data();
        in.n = kN;
        for (int c = 0; c < 3; ++c) {
            in.wo[c] = wo[c].data(), in.wi[c] = wi[c].data(), in.n_[c] = n[c].data(), in.albedo[c] = alb[c].data();
            in.u[c] = u[c].data(), in.p[c] = p[c].data(), in.err[c] = err[c].data();
        }
        in.pdf_a = a[21].data();
        in.pdf_b = a[22].data();
        in.active = active.get();
        in.emitters = &emitters;
    }
};

using Outputs = test::ProbeOutputs<probe::Out, probe::kOutputs, Cases::kN>;
using test::same_bits;

void expect_equal(const Outputs& scalar, const Outputs& packet, const char* target) {
    EXPECT_EQ(test::count_differing(scalar, packet, target), 0u) << target;
}
}  // namespace

TEST(LanesEqualScalars, EveryTargetEveryLane) {
    const Cases cases;
    Outputs scalar;
    probe::run<float>(cases.in, scalar.out);
    // The probe produced something: non-trivial values in the Lambertian and emitter outputs.
    size_t nonzero = 0;
    for (int k = 0; k < probe::kOutputs; ++k)
        for (float v : scalar.storage[k]) nonzero += v != 0.f;
    EXPECT_GT(nonzero, size_t(Cases::kN) * 20);
    int targets = 0;
    for (SimdTarget t : available_simd_targets()) {
        Outputs packet;
        switch (t) {
#ifdef PELLUCID_PROBE_AVX512
            case SimdTarget::AVX512: probe::run_avx512(cases.in, packet.out); break;
#endif
#ifdef PELLUCID_PROBE_AVX2
            case SimdTarget::AVX2: probe::run_avx2(cases.in, packet.out); break;
#endif
#ifdef PELLUCID_PROBE_SSE4
            case SimdTarget::SSE4: probe::run_sse4(cases.in, packet.out); break;
#endif
            default: continue;
        }
        ++targets;
        expect_equal(scalar, packet, to_string(t).c_str());
    }
    RecordProperty("targets", targets);
}

TEST(LanesEqualScalars, ACaseChangedInOneLaneIsSeen) {
    // The comparison itself: perturbing one input of one lane must change that lane's outputs only.
    Cases cases;
    Outputs a, b;
    probe::run<float>(cases.in, a.out);
    const_cast<float*>(cases.in.albedo[0])[37] += 0.25f;
    probe::run<float>(cases.in, b.out);
    const std::vector<int> changed = test::differing_cases(a, b);
    EXPECT_FALSE(changed.empty());
    for (int i : changed) EXPECT_EQ(i, 37);
}
