// Build (and, for small films, render) a scene description produced by a harness: the path every
// JSON or XML input takes after its reader.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <atomic>
#include <cstdio>
#include <cstdlib>

#include "pellucid/api.h"
#include "pellucid/scene/scene.h"

namespace fuzz {

/// Samples the renders dropped as NaN, infinite or negative, over the whole run (printed at exit):
/// not a crash, but a number that a valid scene should not produce.
inline std::atomic<uint64_t>& invalid_samples() {
    static std::atomic<uint64_t> n{0};
    static const bool registered = [] {
        std::atexit([] {
            std::fprintf(stderr, "fuzz: invalid (dropped) samples over the run: %llu\n",
                         (unsigned long long)invalid_samples().load());
        });
        return true;
    }();
    (void)registered;
    return n;
}

inline void build_and_render(const pellucid::SceneDesc& desc) {
    std::shared_ptr<const pellucid::Scene> scene = pellucid::load_desc(desc);
    if (int64_t(scene->width) * scene->height > 32 * 32) return;  // keep each run short
    pellucid::RenderOptions opts;
    opts.spp = 1;
    opts.threads = 1;
    pellucid::RenderResult r = pellucid::render(*scene, opts);
    invalid_samples() += r.stats.invalid_samples;
}
}  // namespace fuzz
