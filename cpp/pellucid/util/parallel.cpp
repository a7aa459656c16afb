// Parallel loops through oneTBB.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/util/parallel.h"

#include <algorithm>
#include <atomic>

#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace pellucid {
int hardware_threads() { return tbb::info::default_concurrency(); }

void parallel_for(int64_t n, int threads, const std::function<void(int64_t)>& body) {
    if (n <= 0) return;
    int nt = threads > 0 ? threads : hardware_threads();
    if (nt == 1) {
        for (int64_t i = 0; i < n; ++i) body(i);
        return;
    }
    tbb::task_arena arena(nt);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<int64_t>(0, n, 1),
                          [&](const tbb::blocked_range<int64_t>& r) {
                              for (int64_t i = r.begin(); i != r.end(); ++i) body(i);
                          });
    });
}

void parallel_for_in_order(int64_t n, int threads, const std::function<void(int64_t)>& body) {
    if (n <= 0) return;
    const int nt = int(std::min<int64_t>(n, threads > 0 ? threads : hardware_threads()));
    if (nt == 1) {
        for (int64_t i = 0; i < n; ++i) body(i);
        return;
    }
    // One task per thread, each taking indices from a shared counter until none is left (TBB's own
    // partitioners split the range by halves, in no fixed order).
    std::atomic<int64_t> next{0};
    tbb::task_arena arena(nt);
    arena.execute([&] {
        tbb::parallel_for(
            tbb::blocked_range<int>(0, nt, 1),
            [&](const tbb::blocked_range<int>&) {
                for (int64_t i; (i = next.fetch_add(1, std::memory_order_relaxed)) < n;) {
                    try {
                        body(i);
                    } catch (...) {
                        next.store(n, std::memory_order_relaxed);  // nothing more starts
                        throw;
                    }
                }
            },
            tbb::simple_partitioner());
    });
}
}  // namespace pellucid
