// The only TBB user: parallel loops with an explicit thread count.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <functional>

namespace pellucid {
/// Number of hardware threads.
int hardware_threads();
/// Run body(i) for i in [0, n) on `threads` threads (0 = all). Each index runs exactly once; the
/// order is unspecified, so bodies must write disjoint data. Exceptions propagate to the caller.
void parallel_for(int64_t n, int threads, const std::function<void(int64_t)>& body);
}  // namespace pellucid
