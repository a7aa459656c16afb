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
/// As parallel_for, but the indices start in increasing order: each thread, once free, takes the
/// lowest index not yet taken. Listing the longest tasks first then keeps the threads busy to the
/// end (longest processing time first: the last task to start is the shortest). After an
/// exception no further index starts, and the first exception propagates to the caller.
void parallel_for_in_order(int64_t n, int threads, const std::function<void(int64_t)>& body);
}  // namespace pellucid
