// form_lanes_probe.h on avx512bw packets (built with that target's flags; see tests/cpp/CMakeLists.txt).
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/simd/packet.h"  // before the templates, which name its lane operations
#include "integrator/form_lanes_probe.h"

namespace pellucid::form_lanes_probe {
Result run_avx512(const In& in) { return run<xsimd::batch<float, xsimd::avx512bw>>(in); }
}  // namespace pellucid::form_lanes_probe
