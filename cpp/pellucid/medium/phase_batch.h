// Phase functions over arrays: the loops behind the Python testing surface pellucid.phase
// (bindings/bind_bxdf.cpp). Rows are float32 triples; directions are normalised first.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstddef>
#include <string>

#include "pellucid/medium/phase.h"

namespace pellucid {

class Node;

/// A phase function from a description node ({"type": "hg", "g": 0.7}); errors name `source`.
PhaseFunction phase_from_desc(const Node& node, const std::string& source = "<dict>");

/// out[i] = p(wo_i, wi_i) [1/sr].
void phase_eval_batch(const PhaseFunction& p, const float* wo, const float* wi, size_t n, float* out);
/// out[i] = pdf(wo_i, wi_i) (solid angle).
void phase_pdf_batch(const PhaseFunction& p, const float* wo, const float* wi, size_t n, float* out);
/// One sample per row from u_i = (u1, u2) ∈ [0, 1)²; a failed row gets wi = 0, weight = pdf = 0.
void phase_sample_batch(const PhaseFunction& p, const float* wo, const float* u, size_t n, float* wi, float* weight,
                        float* pdf, bool* delta);
}  // namespace pellucid
