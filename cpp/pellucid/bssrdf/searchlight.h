// The random-walk ground truth for diffusion profiles: an analog Monte Carlo walk in a slab (finite or
// semi-infinite) under a smooth dielectric boundary, lit by a normal searchlight at r = 0.
// SPDX-License-Identifier: Apache-2.0
//
// Geometry: the medium fills depth z ∈ [0, T] below the top face z = 0 (T = +∞: a half-space); both
// faces are smooth boundaries to a medium of index 1, the slab's index being eta relative to it. The
// searchlight is a thin beam at normal incidence through r = 0; results are normalised per ENTERED
// photon (the beam's Fresnel reflection at entry, F(1), is not counted), so the reflectance is the
// quantity a diffusion profile's total() predicts.
//
// The walk: exponential free flights with σt = σa + σs; at each collision the photon scatters with
// probability σs/σt (Henyey–Greenstein, medium/phase.h) or is absorbed (analog absorption: every photon
// carries weight 1, so each tally is a count and its error binomial); at a face it is reflected with
// the exact Fresnel probability (total internal reflection included) or leaves. A photon leaving
// the top face is tallied at its exit radius.
//
// Determinism: photons are processed in fixed chunks of kSearchlightChunk, each with its own PCG32
// stream derived from (seed, chunk index); the chunk tallies are summed in chunk order. The result is
// therefore the same for every thread count, and two runs with the same seed that differ only in T
// follow identical paths until a photon first reaches depth T (common random numbers, used by the
// thin-slab study to measure R(∞) − R(T) with a small variance).
#pragma once
#include <cmath>
#include <cstdint>
#include <vector>

namespace pellucid::bssrdf {

/// Photons per chunk (one PCG32 stream each).
constexpr int64_t kSearchlightChunk = 4096;

struct SearchlightSetup {
    float sigma_a = 0.f;  ///< absorption coefficient, 1/length, ≥ 0
    float sigma_s = 1.f;  ///< scattering coefficient, 1/length, ≥ 0
    float g = 0.f;        ///< HG asymmetry in [−1, 1]
    float eta = 1.f;      ///< index of the slab relative to the outside, > 0
    double thickness = INFINITY;  ///< T > 0 in length units; +∞ for the half-space
    int64_t photons = 100000;     ///< entered photons, ≥ 1
    uint64_t seed = 1;
    std::vector<double> r_edges;  ///< radial bin edges of the top-face exitance (ascending, ≥ 0; may be empty)
    /// A photon still inside after this many interactions (collisions and face reflections) is
    /// counted as lost (neither reflected, transmitted nor absorbed): it bounds the run time of an
    /// albedo-1 half-space, where walks end with probability 1 but have no finite mean length.
    int64_t max_collisions = 10000000;
    int threads = 0;  ///< 0 = all
};

struct SearchlightResult {
    int64_t photons = 0;
    double reflectance = 0.0;         ///< fraction leaving through the top face
    double transmittance = 0.0;       ///< fraction leaving through the bottom face
    double absorbed = 0.0;            ///< fraction absorbed
    double lost = 0.0;                ///< fraction stopped by max_collisions
    double reflectance_single = 0.0;  ///< fraction leaving the top face after exactly one scattering
    double mean_collisions = 0.0;     ///< collisions (scattering or absorbing) per photon
    /// Per bin [r_edges[i], r_edges[i+1]): top-face exitance per unit area per entered photon
    /// (count / (photons · π(r₁² − r₀²))), its single-scattered part, and the raw counts.
    std::vector<double> exitance, exitance_single;
    std::vector<int64_t> counts, counts_single;
    /// The reflectance of each chunk (for batch-means error estimates and paired comparisons).
    std::vector<double> chunk_reflectance;
};

/// Run the walk. Throws pellucid::Error naming the parameter for invalid input (negative or
/// non-finite coefficients, g outside [−1, 1], eta ≤ 0, thickness not > 0, photons < 1, bin edges
/// not ascending).
SearchlightResult searchlight(const SearchlightSetup& setup);
}  // namespace pellucid::bssrdf
