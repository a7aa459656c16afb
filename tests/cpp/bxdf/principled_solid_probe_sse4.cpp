// principled_solid_probe.h on sse4_2 packets (built with that target's flags; see tests/cpp/CMakeLists.txt).
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/simd/packet.h"  // before the templates, which name its lane operations
#include "bxdf/principled_solid_probe.h"

namespace pellucid::principled_solid_probe {
void run_sse4(const In& in, Out& out) { run<xsimd::batch<float, xsimd::sse4_2>>(in, out); }
}  // namespace pellucid::principled_solid_probe
