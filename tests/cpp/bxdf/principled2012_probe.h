// What tests/cpp/bxdf/test_principled2012_lanes.cpp compares across lane types: the Burley 2012
// principled BRDF's packet form (Principled2012T) built from packet parameters by
// principled2012_lanes, as the path tracer builds it, evaluated over arrays of cases, kLaneWidth<F>
// lanes at a time: eval_pdf and sample in both transport modes and under three sets of allowed
// lobes. It is instantiated on float in the test and on each SIMD target's packet in
// principled2012_probe_<target>.cpp (built with that target's flags, exporting only its entry
// point, as the renderer's kernels do).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include "bxdf/form_probe.h"
#include "pellucid/bxdf/principled.h"

namespace pellucid::principled2012_probe {

using In = form_probe::In<kPrincipled2012Params>;
using form_probe::kAllowed;
using form_probe::kContexts;
using form_probe::kMode;
using form_probe::kOutputs;
using form_probe::kPerContext;
using form_probe::Out;

template <class F>
void run(const In& in, Out& out) {
    form_probe::run<F>(in, out, [](const MaskT<F>& mine, auto q) { return principled2012_lanes<F>(mine, q); });
}
}  // namespace pellucid::principled2012_probe
