// The lanes-equal-scalars tests' common part: a lane probe's outputs (one array of floats per
// quantity, one entry per case) and their bit-for-bit comparison. NaNs compare equal to NaNs (a
// packet's NaN payload may differ), every other value by its bits, so +0 and -0 differ.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

namespace pellucid::test {

inline bool same_bits(float x, float y) { return std::memcmp(&x, &y, sizeof x) == 0 || (std::isnan(x) && std::isnan(y)); }

/// K arrays of N floats, zeroed, with the probe's Out::v pointing into them.
template <class Out, int K, int N>
struct ProbeOutputs {
    std::vector<float> storage[K];
    Out out;
    ProbeOutputs() {
        for (int k = 0; k < K; ++k) {
            storage[k].assign(size_t(N), 0.f);
            out.v[k] = storage[k].data();
        }
    }
    float at(int k, int i) const { return storage[k][size_t(i)]; }
};

/// The (output, case) entries whose bits differ between a and b; the first five are reported as
/// failures, named by `what`.
template <class Out, int K, int N>
size_t count_differing(const ProbeOutputs<Out, K, N>& a, const ProbeOutputs<Out, K, N>& b, const char* what) {
    size_t differ = 0;
    for (int k = 0; k < K; ++k)
        for (int i = 0; i < N; ++i)
            if (!same_bits(a.at(k, i), b.at(k, i)) && ++differ <= 5)
                ADD_FAILURE() << what << ": output " << k << " case " << i << ": " << a.at(k, i) << " vs " << b.at(k, i);
    return differ;
}

/// The cases (lanes) in which some output's bits differ between a and b.
template <class Out, int K, int N>
std::vector<int> differing_cases(const ProbeOutputs<Out, K, N>& a, const ProbeOutputs<Out, K, N>& b) {
    std::vector<int> cases;
    for (int i = 0; i < N; ++i)
        for (int k = 0; k < K; ++k)
            if (!same_bits(a.at(k, i), b.at(k, i))) {
                cases.push_back(i);
                break;
            }
    return cases;
}
}  // namespace pellucid::test
