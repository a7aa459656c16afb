// Environment map light (lat-long image, importance-sampled by a piecewise-bilinear distribution).
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/light/envmap.h"

#include <cmath>
#include <cstdint>
#include <string>

#include "pellucid/math/constants.h"
#include "pellucid/util/error.h"

namespace pellucid {

EnvmapLight::EnvmapLight(const Image& image, float scale, const Mat3f& rotation, std::string name)
    : m_w(image.width), m_h(image.height), m_rot(rotation), m_name(std::move(name)) {
    PELLUCID_CHECK(m_w >= 2 && m_h >= 3 && image.channels >= 3, "envmap image must be at least 2x3 RGB");
    // (The lane code converts texel and cell coordinates through floats: exact below 2²³.)
    PELLUCID_CHECK(m_w < (1 << 23) && m_h < (1 << 23),
                   "envmap image too large: " + std::to_string(m_w) + "x" + std::to_string(m_h));
    std::vector<Spectrum> texels(size_t(m_w) * size_t(m_h));
    for (int y = 0; y < m_h; ++y)
        for (int x = 0; x < m_w; ++x) {
            const float* p = image.pixel(x, y);
            texels[size_t(y) * size_t(m_w) + size_t(x)] = Spectrum(p[0], p[1], p[2]) * scale;
        }
    // Cell (x, j) spans u' = u − ½/W ∈ [x/W, (x+1)/W) and θ ∈ [θ0, θ1] = π[j, j+1]/(H−1); its
    // corners are texels (x, j), (x+1, j), (x, j+1), (x+1, j+1). Sampling follows the bilinear
    // interpolation in (u', v) of g = Y sin θ at the texels (Y the luminance; envmap.h): a cell is
    // chosen by the mean of its corners' g (the integral of the bilinear g over it, relative to its
    // area), then placed by the bilinear density through them (uniformly where all four are 0).
    // The power uses the exact integral of the channel average L̄: the radiance is linear in u'
    // (columns x, x+1) and in t = (θ − θ0)/Δθ (rows j, j+1), so with A, B the u'-averages of L̄ on
    // rows j and j+1,
    //   ∫ L̄ sin θ dθ over the cell = A (I0 − I1) + B I1,
    //   I0 = ∫ sin θ dθ = cos θ0 − cos θ1,  I1 = ∫ t sin θ dθ = (sin θ1 − sin θ0)/Δθ − cos θ1,
    // and Σ over cells of (that / Δθ)·(1/nu)·(1/nv)·2π² = ∫ L̄ dω.
    const int nu = m_w, nv = m_h - 1;
    const double dtheta = M_PI / double(nv);
    std::vector<float> g(size_t(m_w) * size_t(m_h));  // Y sin θ at the texels (0 on the pole rows)
    for (int y = 0; y < m_h; ++y) {
        const double st = (y == 0 || y == m_h - 1) ? 0.0 : std::sin(y * dtheta);
        for (int x = 0; x < m_w; ++x)
            g[size_t(y) * m_w + x] = float(double(texels[size_t(y) * m_w + x].luminance()) * st);
    }
    std::vector<float> weights(size_t(nu) * size_t(nv));
    double total = 0.0;
    for (int j = 0; j < nv; ++j) {
        double t0 = j * dtheta, t1 = (j + 1) * dtheta;
        double i0 = std::cos(t0) - std::cos(t1);
        double i1 = (std::sin(t1) - std::sin(t0)) / dtheta - std::cos(t1);
        for (int x = 0; x < nu; ++x) {
            int x1 = (x + 1) % m_w;
            double a = 0.5 * (double(texels[size_t(j) * m_w + x].average()) +
                              double(texels[size_t(j) * m_w + x1].average()));
            double b = 0.5 * (double(texels[size_t(j + 1) * m_w + x].average()) +
                              double(texels[size_t(j + 1) * m_w + x1].average()));
            const double exact = std::max(0.0, (a * (i0 - i1) + b * i1) / dtheta);  // mean of L̄ sin θ (Y = 0 only where L̄ = 0)
            total += exact;
            const size_t r0 = size_t(j) * m_w, r1 = r0 + size_t(m_w);
            const float corners = float(0.25 * ((double(g[r0 + x]) + double(g[r0 + x1])) +
                                                (double(g[r1 + x]) + double(g[r1 + x1]))));
            // A cell whose only light is on a pole row has g = 0 at all four corners: it keeps its
            // exact mean, and inside it the point is uniform (bilinear_density is 1 there).
            weights[size_t(j) * nu + x] = corners > 0.f ? corners : float(exact);
        }
    }
    m_integral = total / (double(nu) * double(nv)) * 2.0 * M_PI * M_PI;
    // One buffer: the CDFs and their guides, then the texels (RGB), then g, then each cell's
    // density (piecewise_2d_cell_pdf, so that envmap_pdf reads it with one load), addressed by
    // 32-bit offsets (g at texels + 3·W·H, the cells at texels + 4·W·H).
    const size_t n = 2 * (size_t(nv) + 1 + size_t(nv) * (size_t(nu) + 1)) + 5 * texels.size();
    PELLUCID_CHECK(n < size_t(INT32_MAX), "envmap image too large: " + std::to_string(m_w) + "x" + std::to_string(m_h));
    auto data = std::make_shared<std::vector<float>>();
    data->reserve(n);
    m_dist = append_piecewise_2d(*data, weights, size_t(nu), size_t(nv));
    m_texels = int32_t(data->size());
    for (const Spectrum& t : texels) data->insert(data->end(), {t.r, t.g, t.b});
    data->insert(data->end(), g.begin(), g.end());
    const Piecewise2DLanes<float> dist{data->data(), m_dist.marginal, m_dist.conditional, m_dist.nu, m_dist.nv};
    std::vector<float> cells(size_t(nu) * size_t(nv));
    for (int j = 0; j < nv; ++j)
        for (int x = 0; x < nu; ++x) cells[size_t(j) * nu + x] = piecewise_2d_cell_pdf<float>(dist, x, j);
    data->insert(data->end(), cells.begin(), cells.end());
    m_data = std::move(data);
}

std::optional<LightLiSample> EnvmapLight::sample_li(const LightSampleContext&, Vec2f u) const {
    const EnvmapSampleT<float> e = envmap_sample<float>(lanes(), u);
    if (!e.valid) return std::nullopt;
    LightLiSample s;
    s.wi = e.wi;
    s.pdf = e.pdf;
    s.L = e.L;
    s.infinite = true;
    return s;
}

float EnvmapLight::power(float scene_radius) const {
    return float(kPi * double(scene_radius) * scene_radius * m_integral);
}

std::string EnvmapLight::to_string() const {
    return "EnvmapLight[" + (m_name.empty() ? std::string() : "filename=" + m_name + ", ") +
           "resolution=" + std::to_string(m_w) + "x" + std::to_string(m_h) + "]";
}
}  // namespace pellucid
