// Runtime choice of the path tracer's SIMD target (simd_target.h).
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/integrator/simd_target.h"

#include <atomic>
#include <cstdlib>

#include "pellucid/integrator/path_kernel.h"
#include "pellucid/util/error.h"

namespace pellucid {

// The per-target instantiations (integrator/kernels/), present as this build's CMake defines say.
#ifdef PELLUCID_KERNEL_AVX512
uint64_t render_tile_avx512(const PathSetup& ps, const TileJob& job, Film& film);
#endif
#ifdef PELLUCID_KERNEL_AVX2
uint64_t render_tile_avx2(const PathSetup& ps, const TileJob& job, Film& film);
#endif
#ifdef PELLUCID_KERNEL_SSE4
uint64_t render_tile_sse4(const PathSetup& ps, const TileJob& job, Film& film);
#endif
#ifdef PELLUCID_KERNEL_NEON
uint64_t render_tile_neon(const PathSetup& ps, const TileJob& job, Film& film);
#endif

namespace {
uint64_t render_tile_scalar(const PathSetup& ps, const TileJob& job, Film& film) {
    return render_tile_kernel<float>(ps, job, film);
}

bool cpu_has(SimdTarget t) {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_cpu_init();
    switch (t) {
        case SimdTarget::Scalar: return true;
        case SimdTarget::SSE4: return __builtin_cpu_supports("sse4.2") && __builtin_cpu_supports("popcnt");
        case SimdTarget::AVX2: return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
        case SimdTarget::AVX512:
            return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
                   __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512vl") &&
                   __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
        case SimdTarget::NEON: return false;
    }
    return false;
#elif defined(__aarch64__)
    return t == SimdTarget::Scalar || t == SimdTarget::NEON;  // NEON is part of AArch64
#else
    return t == SimdTarget::Scalar;
#endif
}

bool built(SimdTarget t) {
    switch (t) {
        case SimdTarget::Scalar: return true;
#ifdef PELLUCID_KERNEL_SSE4
        case SimdTarget::SSE4: return true;
#endif
#ifdef PELLUCID_KERNEL_AVX2
        case SimdTarget::AVX2: return true;
#endif
#ifdef PELLUCID_KERNEL_AVX512
        case SimdTarget::AVX512: return true;
#endif
#ifdef PELLUCID_KERNEL_NEON
        case SimdTarget::NEON: return true;
#endif
        default: return false;
    }
}

std::atomic<int> g_override{-1};
}  // namespace

std::string to_string(SimdTarget t) {
    switch (t) {
        case SimdTarget::Scalar: return "scalar";
        case SimdTarget::SSE4: return "sse4";
        case SimdTarget::NEON: return "neon";
        case SimdTarget::AVX2: return "avx2";
        case SimdTarget::AVX512: return "avx512";
    }
    return "?";
}

SimdTarget parse_simd_target(const std::string& name, const std::string& what) {
    for (SimdTarget t : {SimdTarget::Scalar, SimdTarget::SSE4, SimdTarget::NEON, SimdTarget::AVX2, SimdTarget::AVX512})
        if (name == to_string(t)) return t;
    throw Error(what + ": unknown SIMD target '" + name + "' (expected scalar, sse4, neon, avx2 or avx512)");
}

int lane_width(SimdTarget t) {
    switch (t) {
        case SimdTarget::Scalar: return 1;
        case SimdTarget::SSE4:
        case SimdTarget::NEON: return 4;
        case SimdTarget::AVX2: return 8;
        case SimdTarget::AVX512: return 16;
    }
    return 1;
}

std::vector<SimdTarget> available_simd_targets() {
    std::vector<SimdTarget> out;
    for (SimdTarget t : {SimdTarget::Scalar, SimdTarget::SSE4, SimdTarget::NEON, SimdTarget::AVX2, SimdTarget::AVX512})
        if (built(t) && cpu_has(t)) out.push_back(t);
    return out;
}

namespace {
void require_available(SimdTarget t, const std::string& what) {
    if (!built(t)) throw Error(what + ": SIMD target '" + to_string(t) + "' is not built into this pellucid");
    if (!cpu_has(t)) throw Error(what + ": this CPU cannot run SIMD target '" + to_string(t) + "'");
}
}  // namespace

SimdTarget simd_target() {
    const int o = g_override.load();
    if (o >= 0) return SimdTarget(o);
    if (const char* env = std::getenv("PELLUCID_SIMD"); env && *env) {
        const SimdTarget t = parse_simd_target(env, "PELLUCID_SIMD");
        require_available(t, "PELLUCID_SIMD");
        return t;
    }
    return available_simd_targets().back();
}

void set_simd_target(std::optional<SimdTarget> t) {
    if (t) require_available(*t, "simd target");
    g_override.store(t ? int(*t) : -1);
}

PathTileFn path_tile_function(SimdTarget t) {
    require_available(t, "simd target");
    switch (t) {
#ifdef PELLUCID_KERNEL_AVX512
        case SimdTarget::AVX512: return &render_tile_avx512;
#endif
#ifdef PELLUCID_KERNEL_AVX2
        case SimdTarget::AVX2: return &render_tile_avx2;
#endif
#ifdef PELLUCID_KERNEL_SSE4
        case SimdTarget::SSE4: return &render_tile_sse4;
#endif
#ifdef PELLUCID_KERNEL_NEON
        case SimdTarget::NEON: return &render_tile_neon;
#endif
        default: return &render_tile_scalar;
    }
}
}  // namespace pellucid
