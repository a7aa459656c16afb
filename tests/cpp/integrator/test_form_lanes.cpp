// The packet forms' calls on the half-width packet (integrator/form_lanes.h, FormLanesHalf) against
// their calls on the whole packet (FormLanesWhole), on the AVX-512 target, the one with a half-width
// packet (integrator/form_lanes_probe.h): the same bits on every lane, a bound of 0 ulp (the lanes
// that take part compute exactly the same operations; the others keep their values).
//
// Cases: the rough dielectrics and rough conductors over GGX and Beckmann with α from 0.01 to 1
// (anisotropic included, either shadowing form), η on both sides of 1; directions over the whole
// sphere, so below the horizon too; each packet's lanes that take part drawn at random, 1 to 16 of
// them, so that every count the half-width packet takes (1 to 8) and the lanes' positions vary.
// Fixed seed.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "integrator/form_lanes_probe.h"
#include "pellucid/integrator/simd_target.h"
#include "pellucid/sampling/rng.h"

using namespace pellucid;

namespace pellucid::form_lanes_probe {
#ifdef PELLUCID_FORM_LANES_PROBE_AVX512
Result run_avx512(const In& in);
#endif
}  // namespace pellucid::form_lanes_probe

TEST(FormLanes, HalfPacketCallsEqualWholePacketCalls) {
    const auto targets = available_simd_targets();
    if (std::find(targets.begin(), targets.end(), SimdTarget::AVX512) == targets.end())
        GTEST_SKIP() << "no AVX-512 target on this build or CPU: no half-width packet";
#ifdef PELLUCID_FORM_LANES_PROBE_AVX512
    constexpr int kPackets = 6000, kN = 16 * kPackets;
    PCG32 rng(20261130u, 7u);
    auto U = [&] { return rng.next_float(); };
    std::vector<float> q[12], d[6], u[3];
    std::vector<char> on(kN);
    for (auto& v : q) v.resize(kN);
    for (auto& v : d) v.resize(kN);
    for (auto& v : u) v.resize(kN);
    auto direction = [&](int i, std::vector<float>* c) {
        const float z = 2.f * U() - 1.f, phi = 6.2831853f * U(), r = std::sqrt(std::max(0.f, 1.f - z * z));
        c[0][size_t(i)] = r * std::cos(phi), c[1][size_t(i)] = r * std::sin(phi), c[2][size_t(i)] = z;
    };
    for (int p = 0; p < kPackets; ++p) {
        const int count = 1 + int(U() * 16.f) % 16;
        int lanes[16];
        for (int i = 0; i < 16; ++i) lanes[i] = i;
        for (int i = 15; i > 0; --i) std::swap(lanes[i], lanes[int(U() * float(i + 1)) % (i + 1)]);
        for (int k = 0; k < count; ++k) on[size_t(16 * p + lanes[k])] = 1;
        for (int i = 16 * p; i < 16 * p + 16; ++i) {
            const float eta = U() < 0.5f ? 1.05f + 1.5f * U() : 0.4f + 0.55f * U();
            q[0][size_t(i)] = eta;
            for (int k = 1; k < 9; ++k) q[k][size_t(i)] = U() * (k < 6 ? 3.f : 1.f);
            const float ax = std::exp(std::log(0.01f) * U());
            q[9][size_t(i)] = ax, q[10][size_t(i)] = U() < 0.5f ? ax : std::exp(std::log(0.01f) * U());
            q[11][size_t(i)] = U() < 0.5f ? 1.f : 0.f;
            direction(i, d), direction(i, d + 3);
            for (auto& v : u) v[size_t(i)] = U();
        }
    }
    form_lanes_probe::In in;
    in.n = kN;
    for (int k = 0; k < 12; ++k) in.q[k] = q[k].data();
    for (int c = 0; c < 3; ++c) in.wo[c] = d[c].data(), in.wi[c] = d[3 + c].data(), in.u[c] = u[c].data();
    in.on = reinterpret_cast<const bool*>(on.data());
    const form_lanes_probe::Result r = form_lanes_probe::run_avx512(in);
    EXPECT_EQ(r.differing, 0) << "of " << r.compared;
    EXPECT_GT(r.half_calls, kPackets / 3);  // counts of 1 to 8 of 16
#endif
}
