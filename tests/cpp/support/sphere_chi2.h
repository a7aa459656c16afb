// χ² of a direction sampler against its density over the whole sphere (equal-area θ/φ cells),
// shared by the BxDF property suite (local frame) and the bumped-surface suite (world frame).
// SPDX-License-Identifier: Apache-2.0
//
// The sampler is any callable (float u_lobe, Vec2f u) -> std::optional<BxDFSample> and the density
// any callable (Vec3f w) -> float; both see directions in the frame whose z axis the cells are
// built around. A sampler may fail (nullopt): the failures form one extra cell, which expects the
// mass the density and the delta lobes leave missing (Mitsuba 0.6 / REFERENCE.md §2.3).
#pragma once
#include <atomic>
#include <optional>
#include <thread>
#include <vector>

#include "pellucid/bxdf/bxdf_types.h"
#include "pellucid/math/constants.h"
#include "pellucid/sampling/rng.h"
#include "support/chi2.h"

namespace pellucid::test {

struct SphereChi2Options {
    int theta_bins = 32, phi_bins = 64;  ///< equal-area cells: uniform in cos θ and φ
    int samples = 1000000;
    int chunks = 4;  ///< fixed work split: results do not depend on the thread count
};

inline int sphere_cell_of(const Vec3f& w, const SphereChi2Options& o) {
    int it = clamp(int((w.z + 1.f) * 0.5f * o.theta_bins), 0, o.theta_bins - 1);
    float phi = std::atan2(w.y, w.x);
    if (phi < 0.f) phi += 2.f * kPi;
    int ip = clamp(int(phi * kInv2Pi * o.phi_bins), 0, o.phi_bins - 1);
    return it * o.phi_bins + ip;
}

struct SphereHistogram {
    struct Delta {
        Vec3f w;
        double p;
    };
    std::vector<double> obs;  ///< one count per cell, then the failures
    std::vector<Delta> deltas;
    void add_delta(const Delta& d) {
        for (const auto& e : deltas)
            if (length2(d.w - e.w) < 1e-10f) return;
        deltas.push_back(d);
    }
};

/// Sample in o.chunks fixed chunks of PCG32(seed, 2·chunk + 1) (threads only change who runs a
/// chunk) and merge. Distinct delta directions are recorded with their discrete probability.
template <class SampleFn>
SphereHistogram sphere_histogram(const SampleFn& sample, uint64_t seed, const SphereChi2Options& o) {
    const size_t cells = size_t(o.theta_bins) * o.phi_bins + 1;
    std::vector<SphereHistogram> parts(o.chunks);
    std::vector<std::thread> threads;
    std::atomic<int> next{0};
    auto run_chunk = [&](int chunk) {
        SphereHistogram& h = parts[chunk];
        h.obs.assign(cells, 0.0);
        PCG32 rng(seed, 2 * uint64_t(chunk) + 1);
        for (int k = 0; k < o.samples / o.chunks; ++k) {
            float ul = rng.next_float();
            Vec2f u = rng.next_2d();
            std::optional<BxDFSample> s = sample(ul, u);
            if (!s) {
                h.obs.back() += 1;
                continue;
            }
            h.obs[sphere_cell_of(s->wi, o)] += 1;
            if (s->is_specular()) h.add_delta({s->wi, double(s->pdf)});
        }
    };
    unsigned nt = std::max(1u, std::min(unsigned(o.chunks), std::thread::hardware_concurrency()));
    for (unsigned t = 0; t < nt; ++t)
        threads.emplace_back([&] {
            for (int c; (c = next++) < o.chunks;) run_chunk(c);
        });
    for (auto& t : threads) t.join();
    SphereHistogram h;
    h.obs.assign(cells, 0.0);
    for (auto& p : parts) {
        for (size_t i = 0; i < cells; ++i) h.obs[i] += p.obs[i];
        for (const auto& d : p.deltas) h.add_delta(d);
    }
    return h;
}

/// ∫ pdf dω over cell (it, ip) (cos θ and φ ranges), with an n × n Gauss rule on each of
/// sub × sub sub-cells.
template <class PdfFn>
double sphere_cell_integral(const PdfFn& pdf, int it, int ip, int sub, int n, const SphereChi2Options& o) {
    double z0 = -1.0 + 2.0 * it / o.theta_bins, dz = 2.0 / o.theta_bins / sub;
    double p0 = 2.0 * M_PI * ip / o.phi_bins, dp = 2.0 * M_PI / o.phi_bins / sub, sum = 0.0;
    auto f = [&](double z, double phi) {
        double s = std::sqrt(std::max(0.0, 1.0 - z * z));
        return double(pdf(Vec3f(float(s * std::cos(phi)), float(s * std::sin(phi)), float(z))));
    };
    for (int a = 0; a < sub; ++a)
        for (int c = 0; c < sub; ++c)
            sum += integrate_2d_gauss(f, z0 + a * dz, z0 + (a + 1) * dz, p0 + c * dp, p0 + (c + 1) * dp, n);
    return sum;
}

/// ∫ pdf dω over the whole sphere (6 × 6 Gauss per cell; sub × sub sub-cells each).
template <class PdfFn>
double sphere_integral(const PdfFn& pdf, const SphereChi2Options& o, int sub = 1) {
    double sum = 0.0;
    for (int it = 0; it < o.theta_bins; ++it)
        for (int ip = 0; ip < o.phi_bins; ++ip) sum += sphere_cell_integral(pdf, it, ip, sub, 6, o);
    return sum;
}

/// Pearson χ² of the sampler against its density: the smooth density integrated per cell, plus
/// discrete probability × N for each distinct delta direction, plus the 'failed' cell expecting
/// the missing mass.
template <class SampleFn, class PdfFn>
Chi2Result sphere_chi2(const SampleFn& sample, const PdfFn& pdf, uint64_t seed, const SphereChi2Options& o = {}) {
    SphereHistogram h = sphere_histogram(sample, seed, o);
    const double n = double(o.chunks) * (o.samples / o.chunks);
    std::vector<double> expected(h.obs.size(), 0.0), delta(h.obs.size(), 0.0);
    for (const auto& d : h.deltas) delta[sphere_cell_of(d.w, o)] += d.p * n;
    for (int it = 0; it < o.theta_bins; ++it)
        for (int ip = 0; ip < o.phi_bins; ++ip) {
            int k = it * o.phi_bins + ip;
            expected[k] = n * sphere_cell_integral(pdf, it, ip, 1, 6, o) + delta[k];
            // A cell that disagrees with the observation by > 4σ is re-integrated with a 32 × 32
            // composite 3-point rule: the pdf may be discontinuous inside a cell (the rough-dielectric
            // transmission cut-off where the generalised half vector reaches the horizon; the
            // shading horizon of a bumped surface), which one 6 × 6 rule cannot see. This only
            // makes the expectation more accurate. A cell the 6 × 6 rule sees as empty is always
            // re-integrated when it holds samples (4 samples against 0 sit exactly on the 4σ line).
            if (sqr(float(h.obs[k] - expected[k])) > 16.0 * std::max(expected[k], 1.0) ||
                (expected[k] == 0.0 && h.obs[k] > 0.0))
                expected[k] = n * sphere_cell_integral(pdf, it, ip, 32, 3, o) + delta[k];
        }
    double mass = 0.0;
    for (size_t i = 0; i + 1 < expected.size(); ++i) mass += expected[i];
    expected.back() = std::max(0.0, n - mass);
    // A distribution concentrated in one cell (a pure mirror) leaves no degrees of freedom: then the
    // observation must match exactly.
    int nonzero = 0;
    for (double e : expected) nonzero += e > 0.5;
    if (nonzero <= 1) {
        Chi2Result r;
        r.p_value = 1.0;
        for (size_t i = 0; i < expected.size(); ++i)
            if (std::fabs(h.obs[i] - expected[i]) > 1e-6 * n) r.p_value = 0.0;
        r.message = "single-cell distribution";
        return r;
    }
    return chi2_test(h.obs, expected);
}
}  // namespace pellucid::test
