// Searchlight random walk in a slab under a smooth dielectric boundary (see searchlight.h).
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/bssrdf/searchlight.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "pellucid/bxdf/fresnel.h"
#include "pellucid/medium/phase.h"
#include "pellucid/sampling/rng.h"
#include "pellucid/util/error.h"
#include "pellucid/util/parallel.h"

namespace pellucid::bssrdf {
namespace {
constexpr double kPiD = 3.14159265358979323846;

struct Tally {
    int64_t top = 0, bottom = 0, absorbed = 0, lost = 0, single = 0, collisions = 0;
    std::vector<int64_t> bins, bins_single;
};

enum class Fate { Top, Bottom, Absorbed, Lost };

/// One photon's walk; on Top, *r_exit is the exit radius and *scatterings the number of scatterings.
Fate walk(const SearchlightSetup& s, double sigma_t, double albedo, PCG32& rng, double* r_exit, int64_t* scatterings,
          int64_t* collisions) {
    double x = 0.0, y = 0.0, z = 0.0;
    Vec3f w(0.f, 0.f, 1.f);  // into the slab (+z is deeper)
    const double T = s.thickness;
    const double inv_eta = 1.0 / double(s.eta);  // the outside's index relative to the slab's
    int64_t n_scatter = 0;
    for (int64_t c = 0;; ++c) {
        if (c > s.max_collisions) return Fate::Lost;
        // Free flight; exponential with rate σt (infinite in a vacuum).
        const double u = rng.next_double();
        const double t = sigma_t > 0.0 ? -std::log1p(-u) / sigma_t : INFINITY;
        const double wz = double(w.z);
        const double to_face = wz > 0.0 ? (T - z) / wz : (wz < 0.0 ? -z / wz : INFINITY);
        if (t >= to_face) {
            if (!std::isfinite(to_face)) return Fate::Lost;  // parallel to the faces in a vacuum
            x += to_face * double(w.x);
            y += to_face * double(w.y);
            const bool top = wz < 0.0;
            z = top ? 0.0 : T;
            // Reflect with the exact Fresnel probability for light inside meeting the face.
            const double F = fresnel_dielectric_d(std::fabs(wz), inv_eta);
            if (rng.next_double() < F) {
                w.z = -w.z;
                continue;
            }
            if (top) {
                *r_exit = std::hypot(x, y);
                *scatterings = n_scatter;
                return Fate::Top;
            }
            return Fate::Bottom;
        }
        x += t * double(w.x);
        y += t * double(w.y);
        z += t * wz;
        ++*collisions;
        if (rng.next_double() >= albedo) return Fate::Absorbed;
        ++n_scatter;
        float om, op;
        hg_sample<float>(rng.next_float(), s.g, &om, &op);
        w = normalize(phase_direction<float>(-w, om, op, rng.next_float()));
    }
}

void check(bool ok, const std::string& msg) {
    if (!ok) throw Error("searchlight: " + msg);
}
}  // namespace

SearchlightResult searchlight(const SearchlightSetup& s) {
    check(std::isfinite(s.sigma_a) && s.sigma_a >= 0.f, "sigma_a: value " + std::to_string(s.sigma_a) + " must be finite and >= 0");
    check(std::isfinite(s.sigma_s) && s.sigma_s >= 0.f, "sigma_s: value " + std::to_string(s.sigma_s) + " must be finite and >= 0");
    check(s.g >= -1.f && s.g <= 1.f, "g: value " + std::to_string(s.g) + " must lie in [-1, 1]");
    check(std::isfinite(s.eta) && s.eta > 0.f, "eta: value " + std::to_string(s.eta) + " must be finite and > 0");
    check(s.thickness > 0.0, "thickness: value " + std::to_string(s.thickness) + " must be > 0 (inf: a half-space)");
    check(s.photons >= 1, "photons: value " + std::to_string(s.photons) + " must be >= 1");
    check(s.max_collisions >= 1, "max_collisions: value " + std::to_string(s.max_collisions) + " must be >= 1");
    for (size_t i = 0; i < s.r_edges.size(); ++i) {
        check(std::isfinite(s.r_edges[i]) && s.r_edges[i] >= 0.0, "r_edges[" + std::to_string(i) + "]: value " +
                                                                       std::to_string(s.r_edges[i]) + " must be finite and >= 0");
        check(i == 0 || s.r_edges[i] > s.r_edges[i - 1], "r_edges[" + std::to_string(i) + "]: edges must be ascending");
    }
    const double sigma_t = double(s.sigma_a) + double(s.sigma_s);
    const double albedo = sigma_t > 0.0 ? double(s.sigma_s) / sigma_t : 0.0;
    const size_t n_bins = s.r_edges.size() > 1 ? s.r_edges.size() - 1 : 0;
    const int64_t n_chunks = (s.photons + kSearchlightChunk - 1) / kSearchlightChunk;
    std::vector<Tally> tallies(static_cast<size_t>(n_chunks));

    parallel_for(n_chunks, s.threads, [&](int64_t chunk) {
        Tally& t = tallies[size_t(chunk)];
        t.bins.assign(n_bins, 0);
        t.bins_single.assign(n_bins, 0);
        PCG32 rng(mix_bits(s.seed ^ 0x5ea4c41a7e5eedULL), mix_bits(uint64_t(chunk) + 0x9E3779B97F4A7C15ULL));
        const int64_t begin = chunk * kSearchlightChunk, end = std::min(s.photons, begin + kSearchlightChunk);
        for (int64_t i = begin; i < end; ++i) {
            double r = 0.0;
            int64_t scatterings = 0;
            const Fate f = walk(s, sigma_t, albedo, rng, &r, &scatterings, &t.collisions);
            if (f == Fate::Bottom) ++t.bottom;
            if (f == Fate::Absorbed) ++t.absorbed;
            if (f == Fate::Lost) ++t.lost;
            if (f != Fate::Top) continue;
            ++t.top;
            const bool single = scatterings == 1;
            t.single += single;
            if (n_bins == 0 || r < s.r_edges.front() || r >= s.r_edges.back()) continue;
            const size_t k = size_t(std::upper_bound(s.r_edges.begin(), s.r_edges.end(), r) - s.r_edges.begin()) - 1;
            ++t.bins[k];
            if (single) ++t.bins_single[k];
        }
    });

    // Sum in chunk order.
    SearchlightResult res;
    res.photons = s.photons;
    res.counts.assign(n_bins, 0);
    res.counts_single.assign(n_bins, 0);
    int64_t top = 0, bottom = 0, absorbed = 0, lost = 0, single = 0, collisions = 0;
    for (int64_t c = 0; c < n_chunks; ++c) {
        const Tally& t = tallies[size_t(c)];
        top += t.top;
        bottom += t.bottom;
        absorbed += t.absorbed;
        lost += t.lost;
        single += t.single;
        collisions += t.collisions;
        for (size_t k = 0; k < n_bins; ++k) {
            res.counts[k] += t.bins[k];
            res.counts_single[k] += t.bins_single[k];
        }
        const int64_t n = std::min(s.photons, (c + 1) * kSearchlightChunk) - c * kSearchlightChunk;
        res.chunk_reflectance.push_back(double(t.top) / double(n));
    }
    const double n = double(s.photons);
    res.reflectance = double(top) / n;
    res.transmittance = double(bottom) / n;
    res.absorbed = double(absorbed) / n;
    res.lost = double(lost) / n;
    res.reflectance_single = double(single) / n;
    res.mean_collisions = double(collisions) / n;
    for (size_t k = 0; k < n_bins; ++k) {
        const double area = kPiD * (s.r_edges[k + 1] * s.r_edges[k + 1] - s.r_edges[k] * s.r_edges[k]);
        res.exitance.push_back(double(res.counts[k]) / (n * area));
        res.exitance_single.push_back(double(res.counts_single[k]) / (n * area));
    }
    return res;
}
}  // namespace pellucid::bssrdf
