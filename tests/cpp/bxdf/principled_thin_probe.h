// What tests/cpp/bxdf/test_principled_lanes.cpp compares across lane types: the thin-sheet
// principled BSDF's packet form (PrincipledThinT) built from packet parameters by
// principled_thin_lanes, as the path tracer builds it, evaluated over arrays of cases,
// kLaneWidth<F> lanes at a time (bxdf/form_probe.h). It is instantiated on float in the test and on
// each SIMD target's packet in principled_thin_probe_<target>.cpp (built with that target's flags,
// exporting only its entry point, as the renderer's kernels do).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include "bxdf/form_probe.h"
#include "pellucid/bxdf/principled_bsdf.h"

namespace pellucid::principled_thin_probe {

using In = form_probe::In<kPrincipledThinParams>;
using form_probe::kAllowed;
using form_probe::kContexts;
using form_probe::kMode;
using form_probe::kOutputs;
using form_probe::kPerContext;
using form_probe::Out;

template <class F>
void run(const In& in, Out& out) {
    form_probe::run<F>(in, out, [](const MaskT<F>& mine, auto q) { return principled_thin_lanes<F>(mine, q); });
}
}  // namespace pellucid::principled_thin_probe
