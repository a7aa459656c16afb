// The parallel loops: every index once, parallel_for_in_order's order, and exceptions.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <map>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include "pellucid/util/parallel.h"

using namespace pellucid;

TEST(Parallel, EveryIndexOnce) {
    for (int threads : {1, 2, 4})
        for (int64_t n : {0, 1, 7, 1000}) {
            std::vector<std::atomic<int>> runs(static_cast<size_t>(n));
            for (auto& r : runs) r = 0;
            parallel_for(n, threads, [&](int64_t i) { ++runs[size_t(i)]; });
            for (int64_t i = 0; i < n; ++i) EXPECT_EQ(runs[size_t(i)].load(), 1) << "parallel_for n " << n << " index " << i;
            for (auto& r : runs) r = 0;
            parallel_for_in_order(n, threads, [&](int64_t i) { ++runs[size_t(i)]; });
            for (int64_t i = 0; i < n; ++i)
                EXPECT_EQ(runs[size_t(i)].load(), 1) << "parallel_for_in_order n " << n << " index " << i;
        }
}

// Each thread takes the lowest index not yet taken, so the indices any one thread runs increase.
// TBB's partitioners, which split the range by halves and steal, often break it: with
// parallel_for in its place this test failed in 4 of 5 tries here (each try is 20 runs of each
// thread count).
TEST(Parallel, InOrderEachThreadRunsIncreasingIndices) {
    for (int threads : {1, 2, 4})
        for (int run = 0; run < 20; ++run) {
            std::mutex m;
            std::map<std::thread::id, std::vector<int64_t>> seen;
            parallel_for_in_order(4000, threads, [&](int64_t i) {
                volatile double x = 0;  // some work, so that the threads interleave
                for (int k = 0; k < 200; ++k) x = x + double(k);
                std::lock_guard<std::mutex> l(m);
                seen[std::this_thread::get_id()].push_back(i);
            });
            size_t total = 0;
            for (const auto& [id, v] : seen) {
                total += v.size();
                for (size_t k = 1; k < v.size(); ++k) ASSERT_LT(v[k - 1], v[k]) << threads << " threads, run " << run;
            }
            ASSERT_EQ(total, 4000u);
            if (threads == 1) ASSERT_EQ(seen.size(), 1u);
        }
}

// An exception reaches the caller and no further index starts. Index 0 throws once another thread
// has started a body (TBB would not start a task that had not begun when the loop was cancelled, so
// the test waits until one has), while a full run of the others would take five seconds or more
// (each sleeps 100 µs): the other thread starts 1000 only if the throwing one is held off for 0.1 s
// between its throw and its catch.
TEST(Parallel, InOrderExceptionStopsTheLoop) {
    for (int threads : {1, 2}) {
        std::atomic<int64_t> started{0};
        EXPECT_THROW(parallel_for_in_order(100000, threads,
                                           [&](int64_t i) {
                                               ++started;
                                               if (i == 0) {
                                                   const auto t0 = std::chrono::steady_clock::now();
                                                   while (threads > 1 && started.load() < 2 &&
                                                          std::chrono::steady_clock::now() - t0 < std::chrono::seconds(5))
                                                       std::this_thread::yield();
                                                   throw std::runtime_error("tile 0 failed");
                                               }
                                               std::this_thread::sleep_for(std::chrono::microseconds(100));
                                           }),
                     std::runtime_error);
        EXPECT_LT(started.load(), 1000) << threads << " threads";
        if (threads > 1) EXPECT_GE(started.load(), 2) << "the second thread never started a body";
    }
}
