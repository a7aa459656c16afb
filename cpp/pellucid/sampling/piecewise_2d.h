// Piecewise-constant 2D distribution on [0,1)² with float CDFs, sampled over a lane type F
// (simd/lane.h): the environment map's importance sampling, one lane or a packet at a time.
// SPDX-License-Identifier: Apache-2.0
//
// The density is constant on each of the nu × nv cells: a marginal CDF over the rows, then one
// conditional CDF per row (Pharr, Jakob & Humphreys, pbrt-v4 §A.5.3). The CDFs are float arrays in
// one buffer that the sampler reads by offsets, so a packet reads its lanes' entries with gathers and
// lanes may belong to different distributions.
//
// The density is defined by the CDFs themselves: cell (i, j) has probability
// (cdf_v[j+1] − cdf_v[j]) · (cdf_u,j[i+1] − cdf_u,j[i]), and inside it the point is uniform (u is
// remapped linearly within the cell's CDF interval). pdf() returns that probability times nu·nv, so
// it equals the density sampling produces, also for cells whose float CDF width rounded away from
// the weight's share (a cell of zero width is never sampled and has density 0).
//
// Every operation is an IEEE-exact lane operation (+, −, ·, /, comparisons, selects, gathers,
// integer arithmetic), so each lane of a packet gives the bits the float instantiation gives.
//
// Finding u's cell in a CDF of n cells starts from a guide table (the cutpoint method: Chen & Asau
// 1974, "On Generating Random Variates from an Empirical Distribution", AIIE Transactions 6(2)):
// entry k is the cell of the smallest float u with ⌊u·n⌋ = k, so u's cell lies between the entries
// k and k + 1 of its k = ⌊u·n⌋, and the binary search runs over that range only (one or two steps
// for a map of moderate contrast, instead of log₂ n dependent gathers). The cell found is the same
// as a search of the whole CDF gives. Each CDF's guide has its shape (n + 1 entries, whole numbers
// as floats) and sits at a fixed distance after it in the buffer, past all the CDFs.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "pellucid/math/lane_types.h"

namespace pellucid {

/// The CDFs of one distribution, appended to a float buffer.
struct Piecewise2DLayout {
    int32_t marginal = 0;     ///< offset of the marginal CDF (nv + 1 floats, 0 … 1)
    int32_t conditional = 0;  ///< offset of row 0's conditional CDF (nv rows of nu + 1 floats)
    int32_t nu = 0, nv = 0;
};

namespace detail {
/// The CDF of non-negative weights w[0..n) in steps of `stride`, normalised to end at exactly 1
/// (summed in double); all zero gives the uniform CDF.
inline void append_cdf(std::vector<float>& out, const double* w, size_t n) {
    double total = 0.0;
    for (size_t i = 0; i < n; ++i) total += std::max(0.0, w[i]);
    out.push_back(0.f);
    double acc = 0.0;
    for (size_t i = 0; i < n; ++i) {
        acc += total > 0.0 ? std::max(0.0, w[i]) : 1.0;
        out.push_back(i + 1 == n ? 1.f : float(acc / (total > 0.0 ? total : double(n))));
    }
}

/// Integer of a float lane holding a whole number in [0, 2²³) (exact on every lane type).
template <class F>
inline IntT<F> whole_to_int(const F& k) {
    return lane::as_int(k + F(8388608.f)) - lane::as_int(F(8388608.f));
}

/// The cell ⌊u·n⌋ of u in [0, 1) among n equal intervals, clamped to [0, n − 1] (u ≥ 1: n − 1;
/// below 0 or NaN: 0).
template <class F>
inline IntT<F> guide_cell(const F& u, const IntT<F>& n) {
    const F c = lane::select(u > F(0.f), lane::select(u < F(1.f), u, F(0.f)), F(0.f));
    const IntT<F> k = whole_to_int<F>(lane::floor(c * lane::to_float(n)));
    return lane::select(lane::int_mask(u < F(1.f)), lane::min(k, n - IntT<F>(1)), n - IntT<F>(1));
}

/// Largest index i in [0, n) with cdf[i] ≤ u, for cdf[0] = 0 ≤ u < 1 = cdf[n]: then
/// cdf[i] ≤ u < cdf[i+1], so the cell is never empty. The guide of the CDF (at cdf + guide) bounds
/// it to [g[k], g[k + 1]], k = guide_cell(u, n); a branch-free binary search of that range whose
/// steps are the same on every lane type (lanes of shorter ranges stop moving at length 1).
template <class F>
inline IntT<F> cdf_find(const float* base, const IntT<F>& cdf, const IntT<F>& n, const F& u, const IntT<F>& guide) {
    using I = IntT<F>;
    const I g = cdf + guide + guide_cell<F>(u, n);
    I at = whole_to_int<F>(lane::gather(base, g));
    I len = whole_to_int<F>(lane::gather(base, g + I(1))) - at + I(1);
    while (lane::any(len > I(1))) {
        const I half = len >> 1;
        const auto ok = lane::int_mask(lane::gather(base, cdf + at + half) <= u);
        at = lane::select(ok, at + half, at);
        len = len - half;
    }
    return lane::min(at, n - I(1));
}

/// The guide of the CDF cdf[0..n] (see the header comment): n + 1 whole numbers, appended to `out`.
/// Entry k < n is the cell of the smallest float u with guide_cell(u) = k, the last n − 1.
inline void append_guide(std::vector<float>& out, const float* cdf, int32_t n) {
    const float nf = float(n);
    auto cell_of = [&](float u) {  // what cdf_find returns: the largest i < n with cdf[i] ≤ u
        return int32_t(std::upper_bound(cdf + 1, cdf + n, u) - (cdf + 1));
    };
    auto k_of = [&](float u) { return std::min(int32_t(std::floor(u * nf)), n - 1); };  // guide_cell on [0, 1)
    for (int32_t k = 0; k < n; ++k) {
        // The smallest float u ≥ 0 with k_of(u) = k (u·n rounds monotonically, so no k is skipped).
        float u = float(k) / nf;
        while (u > 0.f && k_of(std::nextafter(u, 0.f)) >= k) u = std::nextafter(u, 0.f);
        while (k_of(u) < k) u = std::nextafter(u, 1.f);
        out.push_back(float(cell_of(u)));
    }
    out.push_back(float(n - 1));
}
}  // namespace detail

/// Append the CDFs of weights (nv rows of nu values, row-major, ≥ 0) to `buffer`, then their guides.
inline Piecewise2DLayout append_piecewise_2d(std::vector<float>& buffer, const std::vector<float>& weights, size_t nu,
                                             size_t nv) {
    Piecewise2DLayout l;
    l.nu = int32_t(nu), l.nv = int32_t(nv);
    std::vector<double> row(nu), row_sums(nv);
    for (size_t v = 0; v < nv; ++v) {
        double s = 0.0;
        for (size_t u = 0; u < nu; ++u) s += std::max(0.0, double(weights[v * nu + u]));
        row_sums[v] = s;
    }
    l.marginal = int32_t(buffer.size());
    detail::append_cdf(buffer, row_sums.data(), nv);
    l.conditional = int32_t(buffer.size());
    for (size_t v = 0; v < nv; ++v) {
        for (size_t u = 0; u < nu; ++u) row[u] = double(weights[v * nu + u]);
        detail::append_cdf(buffer, row.data(), nu);
    }
    // The guides, in the CDFs' shape, at guide_offset() past each (reserved first: append_guide
    // reads the CDFs in the buffer it appends to).
    buffer.reserve(buffer.size() + (nv + 1) + nv * (nu + 1));
    detail::append_guide(buffer, buffer.data() + l.marginal, l.nv);
    for (size_t v = 0; v < nv; ++v)
        detail::append_guide(buffer, buffer.data() + l.conditional + v * (nu + 1), l.nu);
    return l;
}

/// A distribution as lanes read it: the buffer, and per lane its offsets and size.
template <class F>
struct Piecewise2DLanes {
    const float* base;
    IntT<F> marginal, conditional, nu, nv;
    /// How far past each CDF its guide lies: past the marginal and the nv conditional CDFs.
    IntT<F> guide_offset() const { return conditional - marginal + nv * (nu + IntT<F>(1)); }
};

template <class F>
struct Piecewise2DSample {
    V2<F> p;   ///< in [0,1)²
    F pdf;     ///< density at p (> 0 for every sample of a valid u)
    IntT<F> i, j;  ///< the cell: column i, row j
    F du, dv;      ///< where p lies in its cell, each in [0, 1] (uniform, independent, given the cell)
};

/// Sample a point with u ∈ [0,1)² by inverting the marginal CDF (u.y), then row j's conditional
/// CDF (u.x); the point is linear in u inside the chosen cell.
template <class F>
inline Piecewise2DSample<F> sample_piecewise_2d(const Piecewise2DLanes<F>& d, const V2<F>& u) {
    using I = IntT<F>;
    const I guide = d.guide_offset();
    const I j = detail::cdf_find<F>(d.base, d.marginal, d.nv, u.y, guide);
    const F v0 = lane::gather(d.base, d.marginal + j), v1 = lane::gather(d.base, d.marginal + j + I(1));
    const I row = d.conditional + j * (d.nu + I(1));
    const I i = detail::cdf_find<F>(d.base, row, d.nu, u.x, guide);
    const F u0 = lane::gather(d.base, row + i), u1 = lane::gather(d.base, row + i + I(1));
    const F nu = lane::to_float(d.nu), nv = lane::to_float(d.nv);
    const F wv = v1 - v0, wu = u1 - u0;
    // (Both widths are > 0 for u in [0,1); the selects keep lanes with invalid u finite.)
    const F dv = (u.y - v0) / lane::select(wv > F(0.f), wv, F(1.f));
    const F du = (u.x - u0) / lane::select(wu > F(0.f), wu, F(1.f));
    Piecewise2DSample<F> s;
    s.p = V2<F>{lane::min((lane::to_float(i) + du) / nu, F(0x1.fffffep-1f)),
                lane::min((lane::to_float(j) + dv) / nv, F(0x1.fffffep-1f))};
    s.pdf = (wv * nv) * (wu * nu);
    s.i = i, s.j = j;
    s.du = du, s.dv = dv;
    return s;
}

// A bilinear density inside a cell. The environment map's sampling picks a cell by its weight
// (sample_piecewise_2d), then places the point in it by the bilinear density through the cell's
// corner values a (s, t) = (0, 0), b (1, 0), c (0, 1), d (1, 1) instead of uniformly, so that over
// the whole map the density is piecewise bilinear (where the weights are the corners' means).

/// t ∈ [0, 1) with the linear density through (0, e0) and (1, e1) (both ≥ 0, not both 0), from
/// ξ ∈ [0, 1): the root of (e1 − e0) t²/2 + e0 t = ξ (e0 + e1)/2, in the form without cancellation,
/// t = ξ (e0 + e1) / (e0 + √((1 − ξ) e0² + ξ e1²)) (the quadratic's numerator rationalised).
template <class F>
inline F sample_linear(const F& xi, const F& e0, const F& e1) {
    const F den = e0 + lane::sqrt((F(1.f) - xi) * (e0 * e0) + xi * (e1 * e1));
    const F t = xi * (e0 + e1) / lane::select(den > F(0.f), den, F(1.f));
    return lane::select(den > F(0.f), lane::min(t, F(0x1.fffffep-1f)), xi);
}
/// The bilinear density through corners a, b, c, d (≥ 0) at (s, t) ∈ [0, 1]², relative to its mean
/// (a + b + c + d)/4 (1 where all four are 0: the uniform density).
template <class F>
inline F bilinear_density(const F& s, const F& t, const F& a, const F& b, const F& c, const F& d) {
    const F f = (F(1.f) - t) * ((F(1.f) - s) * a + s * b) + t * ((F(1.f) - s) * c + s * d);
    const F m = F(0.25f) * ((a + b) + (c + d));
    return lane::select(m > F(0.f), f / lane::select(m > F(0.f), m, F(1.f)), F(1.f));
}
/// A point (s, t) of the bilinear density from (ξs, ξt) ∈ [0, 1)²: t by its marginal, linear through
/// a + b and c + d, then s by the linear density through (1 − t) a + t c and (1 − t) b + t d.
template <class F>
inline V2<F> sample_bilinear(const F& xs, const F& xt, const F& a, const F& b, const F& c, const F& d) {
    const F t = sample_linear<F>(xt, a + b, c + d);
    const F s = sample_linear<F>(xs, (F(1.f) - t) * a + t * c, (F(1.f) - t) * b + t * d);
    return V2<F>{s, t};
}

/// The density of cell (i, j), as sample_piecewise_2d gives it.
template <class F>
inline F piecewise_2d_cell_pdf(const Piecewise2DLanes<F>& d, const IntT<F>& i, const IntT<F>& j) {
    using I = IntT<F>;
    const F wv = lane::gather(d.base, d.marginal + j + I(1)) - lane::gather(d.base, d.marginal + j);
    const I row = d.conditional + j * (d.nu + I(1));
    const F wu = lane::gather(d.base, row + i + I(1)) - lane::gather(d.base, row + i);
    return (wv * lane::to_float(d.nv)) * (wu * lane::to_float(d.nu));
}

/// The density at p ∈ [0,1]² (points outside are clamped to the border cells, NaN to cell 0).
template <class F>
inline F piecewise_2d_pdf(const Piecewise2DLanes<F>& d, const V2<F>& p) {
    using I = IntT<F>;
    auto cell = [](const F& t, const I& n) {  // ⌊t·n⌋ clamped to [0, n − 1]
        const F c = lane::select(t > F(0.f), lane::select(t < F(1.f), t, F(1.f)), F(0.f));
        const F x = lane::floor(c * lane::to_float(n));
        return lane::min(detail::whole_to_int<F>(x), n - I(1));
    };
    return piecewise_2d_cell_pdf<F>(d, cell(p.x, d.nu), cell(p.y, d.nv));
}
}  // namespace pellucid
