// Batched BxDF loops and the timing entry point (see batch.h).
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/bxdf/batch.h"

#include <chrono>
#include <vector>

#include "pellucid/sampling/rng.h"
#include "pellucid/sampling/warp.h"
#include "pellucid/util/parallel.h"

namespace pellucid {
namespace {
Vec3f load_dir(const float* p) {
    Vec3f v(p[0], p[1], p[2]);
    float l2 = dot(v, v);
    // Unit inputs (e.g. sampled directions fed back to eval) pass through bit-exactly.
    if (std::fabs(l2 - 1.f) < 1e-6f) return v;
    return l2 > 0.f ? v / std::sqrt(l2) : Vec3f(0.f);
}
void store(float* p, const Spectrum& s) {
    p[0] = s.r;
    p[1] = s.g;
    p[2] = s.b;
}
}  // namespace

void eval_batch(const BxDF& b, const BxDFContext& ctx, const float* wo, const float* wi, size_t n, float* f_out) {
    std::visit([&](const auto& x) {
        for (size_t i = 0; i < n; ++i) store(f_out + 3 * i, x.eval(ctx, load_dir(wo + 3 * i), load_dir(wi + 3 * i)));
    }, b);
}

void pdf_batch(const BxDF& b, const BxDFContext& ctx, const float* wo, const float* wi, size_t n, float* pdf_out) {
    std::visit([&](const auto& x) {
        for (size_t i = 0; i < n; ++i) pdf_out[i] = x.pdf(ctx, load_dir(wo + 3 * i), load_dir(wi + 3 * i));
    }, b);
}

void sample_batch(const BxDF& b, const BxDFContext& ctx, const float* wo, const float* u, size_t n, float* wi_out,
                  float* weight_out, float* pdf_out, uint32_t* lobe_out) {
    std::visit([&](const auto& x) {
        for (size_t i = 0; i < n; ++i) {
            Vec3f o = load_dir(wo + 3 * i);
            const float* ui = u + 3 * i;
            auto s = o == Vec3f(0.f) ? std::nullopt : x.sample(ctx, o, ui[0], Vec2f(ui[1], ui[2]));
            BxDFSample r = s ? *s : BxDFSample{};
            wi_out[3 * i] = r.wi.x;
            wi_out[3 * i + 1] = r.wi.y;
            wi_out[3 * i + 2] = r.wi.z;
            store(weight_out + 3 * i, r.weight);
            pdf_out[i] = r.pdf;
            lobe_out[i] = uint32_t(r.lobe);
        }
    }, b);
}

void albedo_batch(const BxDF& b, const BxDFContext& ctx, const float* wo, size_t n, int n_samples, uint64_t seed,
                  float* albedo_out, int threads) {
    parallel_for(int64_t(n), threads, [&](int64_t row) {
        Vec3f o = load_dir(wo + 3 * row);
        PCG32 rng(mix_bits(seed), uint64_t(row));
        double acc[3] = {0.0, 0.0, 0.0};
        for (int k = 0; k < n_samples && o != Vec3f(0.f); ++k) {
            float ul = rng.next_float();
            auto s = sample(b, ctx, o, ul, rng.next_2d());
            if (!s) continue;
            for (int c = 0; c < 3; ++c) acc[c] += s->weight[c];
        }
        for (int c = 0; c < 3; ++c) albedo_out[3 * row + c] = n_samples > 0 ? float(acc[c] / n_samples) : 0.f;
    });
}

BxDFTiming benchmark_bxdf(const BxDF& b, const BxDFContext& ctx, size_t n, uint64_t seed) {
    std::vector<Vec3f> wo(n), wi(n), u(n);
    PCG32 rng(mix_bits(seed), 7);
    for (size_t i = 0; i < n; ++i) {
        wo[i] = square_to_cosine_hemisphere(rng.next_2d());
        wi[i] = square_to_uniform_sphere(rng.next_2d());
        u[i] = Vec3f(rng.next_float(), rng.next_float(), rng.next_float());
    }
    using clock = std::chrono::steady_clock;
    auto ns_per_call = [&](auto&& body) {
        body();  // warm-up (caches, lazily built tables)
        auto t0 = clock::now();
        body();
        return std::chrono::duration<double, std::nano>(clock::now() - t0).count() / double(n ? n : 1);
    };
    volatile float sink = 0.f;
    BxDFTiming t;
    std::visit([&](const auto& x) {
        t.ns_eval = ns_per_call([&] {
            float acc = 0.f;
            for (size_t i = 0; i < n; ++i) acc += x.eval(ctx, wo[i], wi[i]).r;
            sink = sink + acc;
        });
        t.ns_pdf = ns_per_call([&] {
            float acc = 0.f;
            for (size_t i = 0; i < n; ++i) acc += x.pdf(ctx, wo[i], wi[i]);
            sink = sink + acc;
        });
        t.ns_sample = ns_per_call([&] {
            float acc = 0.f;
            for (size_t i = 0; i < n; ++i)
                if (auto s = x.sample(ctx, wo[i], u[i].x, Vec2f(u[i].y, u[i].z))) acc += s->weight.r;
            sink = sink + acc;
        });
    }, b);
    return t;
}
}  // namespace pellucid
