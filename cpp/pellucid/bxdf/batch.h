// Batched BxDF queries over arrays of local-frame directions: the loops behind the Python testing
// surface (`pellucid.bsdf`), the chart script (bench/bxdf/) and the per-BxDF timing entry point.
// SPDX-License-Identifier: Apache-2.0
//
// Arrays are row-major float: directions and spectra are (n, 3), pdfs (n,), lobe flags (n,) uint32.
// Directions are in the local shading frame (z = normal) and are normalised before use (a zero
// vector gives 0 / a failed sample). Conventions are those of bxdf_types.h: eval = f·|cos θi|,
// pdf per solid angle, weight = f·|cos θi|/pdf. A failed sample writes wi = 0, weight = 0,
// pdf = 0, lobe = 0. No allocation and no locking: callers may release the GIL around them.
#pragma once
#include <cstddef>
#include <cstdint>

#include "pellucid/bxdf/bxdf.h"

namespace pellucid {

void eval_batch(const BxDF& b, const BxDFContext& ctx, const float* wo, const float* wi, size_t n, float* f_out);
void pdf_batch(const BxDF& b, const BxDFContext& ctx, const float* wo, const float* wi, size_t n, float* pdf_out);
/// u is (n, 3): u_lobe, u1, u2.
void sample_batch(const BxDF& b, const BxDFContext& ctx, const float* wo, const float* u, size_t n, float* wi_out,
                  float* weight_out, float* pdf_out, uint32_t* lobe_out);
/// Directional albedo ρ(wo) = E[weight] per row of wo: the mean sample weight over n_samples
/// (failed samples count as 0; delta lobes included). Row i uses the PCG32 stream (seed, i), so the
/// result does not depend on `threads` (0 = all cores).
void albedo_batch(const BxDF& b, const BxDFContext& ctx, const float* wo, size_t n, int n_samples, uint64_t seed,
                  float* albedo_out, int threads = 0);

/// Single-thread timing of one BxDF: wall nanoseconds per eval(), pdf() and sample() call, each
/// averaged over n calls on pre-generated inputs (wo cosine-distributed over the upper hemisphere,
/// wi uniform over the sphere, u uniform), after one warm-up pass.
struct BxDFTiming {
    double ns_eval = 0.0, ns_pdf = 0.0, ns_sample = 0.0;
};
BxDFTiming benchmark_bxdf(const BxDF& b, const BxDFContext& ctx, size_t n, uint64_t seed = 1);
}  // namespace pellucid
