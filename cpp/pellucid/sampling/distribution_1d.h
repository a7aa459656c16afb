// Piecewise-constant 1D distribution (discrete and continuous sampling by inverting the CDF).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <algorithm>
#include <vector>

namespace pellucid {

class Distribution1D {
public:
    Distribution1D() = default;
    /// weights must be ≥ 0; if all are 0 the distribution falls back to uniform.
    explicit Distribution1D(const std::vector<float>& weights) : m_func(weights) {
        size_t n = m_func.size();
        m_cdf.assign(n + 1, 0.0);
        for (size_t i = 0; i < n; ++i) m_cdf[i + 1] = m_cdf[i] + double(std::max(0.f, m_func[i]));
        m_total = m_cdf[n];
        if (!(m_total > 0.0)) {
            for (size_t i = 0; i < n; ++i) m_cdf[i + 1] = double(i + 1);
            m_total = double(n);
            std::fill(m_func.begin(), m_func.end(), 1.f);
        }
        for (auto& c : m_cdf) c /= m_total;
        m_inv_width.resize(n);
        for (size_t i = 0; i < n; ++i)
            m_inv_width[i] = m_cdf[i + 1] > m_cdf[i] ? 1.0 / (m_cdf[i + 1] - m_cdf[i]) : 0.0;
    }
    size_t size() const { return m_func.size(); }
    double total() const { return m_total; }
    /// Discrete probability of index i.
    float pmf(size_t i) const { return float(m_cdf[i + 1] - m_cdf[i]); }

    /// Sample an index with probability pmf(i); u_remapped receives u rescaled to [0,1) within the
    /// chosen cell, so it can be reused.
    size_t sample_discrete(float u, float* pmf_out = nullptr, float* u_remapped = nullptr) const {
        size_t i = find(u);
        double lo = m_cdf[i], hi = m_cdf[i + 1];
        if (pmf_out) *pmf_out = float(hi - lo);
        if (u_remapped) *u_remapped = float(std::min(0.99999994, (u - lo) * m_inv_width[i]));
        return i;
    }
    /// Sample x in [0,1) with density func(x)/integral; pdf receives that density.
    float sample_continuous(float u, float* pdf, size_t* index = nullptr) const {
        size_t i = find(u);
        const double lo = m_cdf[i];
        double du = (u - lo) * m_inv_width[i];
        if (pdf) *pdf = float(double(m_func[i]) * double(size()) / m_total);
        if (index) *index = i;
        return float(std::min(0.99999994, (double(i) + du) / double(size())));
    }
    float pdf_continuous(float x) const {
        size_t i = std::min(size() - 1, size_t(std::max(0.f, x) * float(size())));
        return float(double(m_func[i]) * double(size()) / m_total);
    }

private:
    size_t find(float u) const {
        // Largest i with cdf[i] <= u: cdf[i] <= u < cdf[i+1] makes cell i non-empty, except when u
        // is clamped past the last cell (u rounds to ≥ cdf[n]); then step back over empty cells.
        // Branch-free binary search (the comparisons of a random u are unpredictable): `base` stays
        // the largest index with cdf[base] <= u, or 0.
        const double* c = m_cdf.data();
        const double x = double(u);
        size_t base = 0, len = m_cdf.size();
        while (len > 1) {
            const size_t half = len / 2;
            base = c[base + half] <= x ? base + half : base;
            len -= half;
        }
        size_t i = std::min(base, size() - 1);
        while (i > 0 && m_cdf[i + 1] == m_cdf[i]) --i;
        return i;
    }
    std::vector<float> m_func;
    std::vector<double> m_cdf;
    std::vector<double> m_inv_width;  ///< 1 / (cdf[i+1] - cdf[i]), 0 for an empty cell
    double m_total = 0.0;
};
}  // namespace pellucid
