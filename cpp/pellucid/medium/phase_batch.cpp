// Phase functions over arrays (medium/phase_batch.h).
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/medium/phase_batch.h"

#include "pellucid/medium/medium_builder.h"

namespace pellucid {
namespace {
Vec3f row(const float* a, size_t i) {
    const Vec3f v(a[3 * i], a[3 * i + 1], a[3 * i + 2]);
    const float l = length(v);
    return l > 0.f ? v / l : v;
}
}  // namespace

PhaseFunction phase_from_desc(const Node& node, const std::string& source) { return build_phase(node, source, ""); }

void phase_eval_batch(const PhaseFunction& p, const float* wo, const float* wi, size_t n, float* out) {
    for (size_t i = 0; i < n; ++i) out[i] = eval(p, row(wo, i), row(wi, i));
}
void phase_pdf_batch(const PhaseFunction& p, const float* wo, const float* wi, size_t n, float* out) {
    for (size_t i = 0; i < n; ++i) out[i] = pdf(p, row(wo, i), row(wi, i));
}
void phase_sample_batch(const PhaseFunction& p, const float* wo, const float* u, size_t n, float* wi, float* weight,
                        float* pdf_out, bool* delta) {
    for (size_t i = 0; i < n; ++i) {
        const auto s = sample(p, row(wo, i), Vec2f(u[2 * i], u[2 * i + 1]));
        const Vec3f w = s ? s->wi : Vec3f(0.f);
        for (int k = 0; k < 3; ++k) wi[3 * i + k] = w[k];
        weight[i] = s ? s->weight : 0.f;
        pdf_out[i] = s ? s->pdf : 0.f;
        delta[i] = s && s->delta;
    }
}
}  // namespace pellucid
