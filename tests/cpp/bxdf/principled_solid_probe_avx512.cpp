// principled_solid_probe.h on avx512bw packets (built with that target's flags; see tests/cpp/CMakeLists.txt).
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/simd/packet.h"  // before the templates, which name its lane operations
#include "bxdf/principled_solid_probe.h"

namespace pellucid::principled_solid_probe {
void run_avx512(const In& in, Out& out) { run<xsimd::batch<float, xsimd::avx512bw>>(in, out); }
}  // namespace pellucid::principled_solid_probe
