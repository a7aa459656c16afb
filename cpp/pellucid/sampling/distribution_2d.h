// Piecewise-constant 2D distribution on [0,1)² by a marginal over rows and one conditional per row.
// SPDX-License-Identifier: Apache-2.0
//
// Pharr, Jakob & Humphreys, "Physically Based Rendering" (4th ed.), §A.5.3: the density is
// f(u, v) / ∫f, constant on each of the nu × nv cells; sampling inverts the marginal CDF of v, then
// the conditional CDF of u in the chosen row.
#pragma once
#include <vector>

#include "pellucid/math/vec.h"
#include "pellucid/sampling/distribution_1d.h"

namespace pellucid {

class Distribution2D {
public:
    Distribution2D() = default;
    /// weights: nv rows of nu non-negative values, row-major (weights[v * nu + u]). All zero falls
    /// back to uniform (as Distribution1D does).
    Distribution2D(const std::vector<float>& weights, size_t nu, size_t nv) : m_nu(nu), m_nv(nv) {
        m_rows.reserve(nv);
        std::vector<float> row_sums(nv);
        for (size_t v = 0; v < nv; ++v) {
            std::vector<float> row(weights.begin() + std::ptrdiff_t(v * nu), weights.begin() + std::ptrdiff_t((v + 1) * nu));
            m_rows.emplace_back(row);
            double s = 0.0;
            for (float w : row) s += double(std::max(0.f, w));
            row_sums[v] = float(s);
        }
        m_marginal = Distribution1D(row_sums);
    }
    size_t nu() const { return m_nu; }
    size_t nv() const { return m_nv; }
    /// Integral of the weights over the unit square (the mean weight).
    double integral() const { return m_nu && m_nv ? m_marginal.total() / double(m_nu * m_nv) : 0.0; }

    /// A point of [0,1)² with density pdf(p) (returned through *pdf).
    Vec2f sample_continuous(Vec2f u, float* pdf) const {
        float pdf_v, pdf_u;
        size_t row;
        float v = m_marginal.sample_continuous(u.y, &pdf_v, &row);
        float x = m_rows[row].sample_continuous(u.x, &pdf_u);
        if (pdf) *pdf = pdf_v * pdf_u;
        return Vec2f(x, v);
    }
    /// Density at p ∈ [0,1)² (points outside are clamped to the border cells).
    float pdf(Vec2f p) const {
        size_t row = std::min(m_nv - 1, size_t(std::max(0.f, p.y) * float(m_nv)));
        // pdf_v · pdf_u = (rowsum · nv / total) · (f · nu / rowsum) = f · nu · nv / total.
        return m_marginal.pdf_continuous(p.y) * m_rows[row].pdf_continuous(p.x);
    }

private:
    size_t m_nu = 0, m_nv = 0;
    std::vector<Distribution1D> m_rows;
    Distribution1D m_marginal;
};
}  // namespace pellucid
