// NEE's pick of a light (pick_light_lanes, light/light_table.h): every u in [0, 1) picks a light
// of nonzero probability and reports that light's probability; u in [cdf_i, cdf_{i+1}) picks
// light i, so the measure of u picking light i is its probability up to the running sums'
// rounding; lights of probability 0 at the start, in the middle and at the end are never picked.
// Lanes equal scalars for the pick: tests/cpp/light/test_envmap_lanes.cpp (its probe's last
// outputs).
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "pellucid/light/light.h"
#include "pellucid/light/light_table.h"
#include "pellucid/math/constants.h"
#include "pellucid/sampling/rng.h"

using namespace pellucid;

namespace {
LightTable table_of(const std::vector<float>& pmf) {
    std::vector<Light> lights;
    for (size_t i = 0; i < pmf.size(); ++i) lights.emplace_back(PointLight(Point3f(float(i), 0.f, 0.f), Spectrum(1.f)));
    return make_light_table(lights, pmf);
}
}  // namespace

TEST(LightPick, EveryUPicksALightOfNonzeroProbabilityInItsInterval) {
    const std::vector<float> pmf = {0.f, 0.1f, 0.f, 0.f, 0.35f, 0.2f, 0.f, 0.35f, 0.f};
    const LightTable t = table_of(pmf);
    ASSERT_EQ(t.pick_cdf.size(), pmf.size() + 1);
    std::vector<float> us = {0.f, 1e-30f, kOneMinusEpsilon, 0.5f};
    for (size_t i = 0; i <= pmf.size(); ++i) {  // each running sum, and the floats beside it
        const float c = t.pick_cdf[i];
        us.push_back(c);
        us.push_back(std::nextafter(c, 0.f));
        us.push_back(std::nextafter(c, 1.f));
    }
    PCG32 rng(9, 4);
    for (int k = 0; k < 100000; ++k) us.push_back(rng.next_float());
    std::vector<int> count(pmf.size(), 0);
    int random = 0;
    for (size_t k = 0; k < us.size(); ++k) {
        const float u = us[k];
        if (!(u >= 0.f && u < 1.f)) continue;
        float p = -1.f;
        const int i = pick_light_lanes<float>(t, u, &p);
        ASSERT_GE(i, 0);
        ASSERT_LT(i, int(pmf.size()));
        EXPECT_GT(pmf[size_t(i)], 0.f) << "u " << u;
        EXPECT_EQ(p, pmf[size_t(i)]) << "u " << u;
        if (u < t.pick_cdf[pmf.size() - 1] || pmf.back() > 0.f)
            EXPECT_TRUE(t.pick_cdf[size_t(i)] <= u && u < t.pick_cdf[size_t(i) + 1]) << "u " << u << " light " << i;
        if (k >= us.size() - 100000) ++count[size_t(i)], ++random;
    }
    // Frequencies of the random u: within 5 standard deviations of each probability (fixed seed).
    for (size_t i = 0; i < pmf.size(); ++i) {
        const double sd = std::sqrt(double(pmf[i]) * (1.0 - pmf[i]) / random);
        EXPECT_NEAR(double(count[i]) / random, pmf[i], 5.0 * sd + 1e-12) << "light " << i;
    }
}

TEST(LightPick, ALastLightOfProbabilityZeroIsNeverPicked) {
    // u past every nonzero interval (there the running sums round below 1; here the
    // probabilities sum to 0.9 to make the gap wide): the last light of nonzero probability, not
    // the empty one after it.
    const LightTable t = table_of({0.6f, 0.3f, 0.f});
    float p;
    for (float u : {0.95f, kOneMinusEpsilon}) {
        EXPECT_EQ(pick_light_lanes<float>(t, u, &p), 1) << u;
        EXPECT_EQ(p, 0.3f);
    }
    const LightTable first = table_of({0.f, 0.f, 1.f});
    EXPECT_EQ(pick_light_lanes<float>(first, 0.f, &p), 2);
    EXPECT_EQ(pick_light_lanes<float>(first, 0.999f, &p), 2);
}
