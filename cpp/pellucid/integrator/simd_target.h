// Runtime choice of the path tracer's SIMD target. The library is baseline x86-64 (or arm64) code;
// the path tracer is instantiated once per instruction set in its own translation unit
// (integrator/kernels/kernel_*.cpp, built with that set's flags), and the render picks the widest
// one the CPU runs. A wheel built on one machine therefore runs on any x86-64 or arm64 machine.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "pellucid/integrator/path_services.h"

namespace pellucid {

/// The SIMD targets, narrowest first. Scalar is the width-1 instantiation (always available).
enum class SimdTarget { Scalar, SSE4, NEON, AVX2, AVX512 };
std::string to_string(SimdTarget t);
/// Parse "scalar", "sse4", "neon", "avx2" or "avx512"; throws pellucid::Error naming `what`.
SimdTarget parse_simd_target(const std::string& name, const std::string& what);
/// Lanes per packet of a target (1, 4, 4, 8, 16).
int lane_width(SimdTarget t);
/// Targets compiled into this build whose instructions this CPU has, narrowest first.
std::vector<SimdTarget> available_simd_targets();
/// The target renders use: the override if set, else the environment variable PELLUCID_SIMD if
/// set (an error if this build or CPU lacks it), else the widest available.
SimdTarget simd_target();
/// Force a target for this process (tests, benchmarks); nullopt restores the automatic choice.
/// Throws pellucid::Error if the target is not available.
void set_simd_target(std::optional<SimdTarget> t);

using PathTileFn = uint64_t (*)(const PathSetup&, const TileJob&, Film&);
/// The path tracer's tile function on target t (which must be available).
PathTileFn path_tile_function(SimdTarget t);
}  // namespace pellucid
