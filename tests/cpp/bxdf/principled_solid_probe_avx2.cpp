// principled_solid_probe.h on avx2 packets (built with that target's flags; see tests/cpp/CMakeLists.txt).
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/simd/packet.h"  // before the templates, which name its lane operations
#include "bxdf/principled_solid_probe.h"

namespace pellucid::principled_solid_probe {
void run_avx2(const In& in, Out& out) { run<xsimd::batch<float, xsimd::avx2>>(in, out); }
}  // namespace pellucid::principled_solid_probe
