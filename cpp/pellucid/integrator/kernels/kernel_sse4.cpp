// The path tracer (integrator/path_kernel.h) instantiated on sse4_2 packets of xsimd. This
// translation unit alone is built with that instruction set's flags (cpp/CMakeLists.txt), and it
// instantiates nothing but packet code: every scalar helper it calls is compiled once, elsewhere
// (integrator/path_services.h), which tests/cpp/integrator/check_kernel_symbols.py verifies.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/simd/packet.h"
#include "pellucid/integrator/path_kernel.h"

namespace pellucid {
uint64_t render_tile_sse4(const PathSetup& ps, const TileJob& job, Film& film) {
    return render_tile_kernel<xsimd::batch<float, xsimd::sse4_2>>(ps, job, film);
}
}  // namespace pellucid
