// Environment map light (lat-long image, Distribution2D importance sampling).
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/light/envmap.h"

#include <cmath>

#include "pellucid/math/constants.h"
#include "pellucid/util/error.h"

namespace pellucid {

EnvmapLight::EnvmapLight(const Image& image, float scale, const Mat3f& rotation, std::string name)
    : m_w(image.width), m_h(image.height), m_rot(rotation), m_name(std::move(name)) {
    PELLUCID_CHECK(m_w >= 2 && m_h >= 3 && image.channels >= 3, "envmap image must be at least 2x3 RGB");
    m_texels.resize(size_t(m_w) * size_t(m_h));
    for (int y = 0; y < m_h; ++y)
        for (int x = 0; x < m_w; ++x) {
            const float* p = image.pixel(x, y);
            m_texels[size_t(y) * size_t(m_w) + size_t(x)] = Spectrum(p[0], p[1], p[2]) * scale;
        }
    // Cell (x, j) spans u' = u − ½/W ∈ [x/W, (x+1)/W) and θ ∈ [θ0, θ1] = π[j, j+1]/(H−1). The
    // radiance is linear in u' (columns x, x+1) and in t = (θ − θ0)/Δθ (rows j, j+1), so with
    // A, B the u'-averages of rows j and j+1:
    //   ∫ L̄ sin θ dθ over the cell = A (I0 − I1) + B I1,
    //   I0 = ∫ sin θ dθ = cos θ0 − cos θ1,  I1 = ∫ t sin θ dθ = (sin θ1 − sin θ0)/Δθ − cos θ1.
    // The cell's weight is its mean of L̄ sin θ over (u', v); its solid-angle integral is 2π²·(cell
    // area)·weight.
    const int nu = m_w, nv = m_h - 1;
    const double dtheta = M_PI / double(nv);
    std::vector<float> weights(size_t(nu) * size_t(nv));
    double total = 0.0;
    for (int j = 0; j < nv; ++j) {
        double t0 = j * dtheta, t1 = (j + 1) * dtheta;
        double i0 = std::cos(t0) - std::cos(t1);
        double i1 = (std::sin(t1) - std::sin(t0)) / dtheta - std::cos(t1);
        for (int x = 0; x < nu; ++x) {
            int x1 = (x + 1) % m_w;
            double a = 0.5 * (double(m_texels[size_t(j) * m_w + x].average()) +
                              double(m_texels[size_t(j) * m_w + x1].average()));
            double b = 0.5 * (double(m_texels[size_t(j + 1) * m_w + x].average()) +
                              double(m_texels[size_t(j + 1) * m_w + x1].average()));
            double w = std::max(0.0, (a * (i0 - i1) + b * i1) / dtheta);  // mean over the cell
            weights[size_t(j) * nu + x] = float(w);
            total += w;
        }
    }
    // Σ weight·(1/nu)·(1/nv)·2π² = ∫ L̄ dω.
    m_integral = total / (double(nu) * double(nv)) * 2.0 * M_PI * M_PI;
    m_dist = Distribution2D(weights, size_t(nu), size_t(nv));
}

Vec3f EnvmapLight::uv_to_direction(Vec2f uv, float* sin_theta) {
    float theta = uv.y * kPi, phi = uv.x * (2.f * kPi);
    float st = std::sin(theta), ct = std::cos(theta);
    if (sin_theta) *sin_theta = st;
    return Vec3f(std::sin(phi) * st, ct, -std::cos(phi) * st);
}

Vec2f EnvmapLight::direction_to_uv(const Vec3f& d) {
    float u = std::atan2(d.x, -d.z) * kInv2Pi;
    if (u < 0.f) u += 1.f;
    return Vec2f(u, safe_acos(d.y) * kInvPi);
}

Spectrum EnvmapLight::lookup(Vec2f uv) const {
    float s = uv.x - half_texel();
    s -= std::floor(s);
    float fx = s * float(m_w), fy = clamp(uv.y, 0.f, 1.f) * float(m_h - 1);
    int x0 = std::min(int(fx), m_w - 1), y0 = std::min(int(fy), m_h - 2);
    float wx = fx - float(x0), wy = fy - float(y0);
    int x1 = (x0 + 1) % m_w;
    const Spectrum* r0 = &m_texels[size_t(y0) * size_t(m_w)];
    const Spectrum* r1 = r0 + m_w;
    Spectrum top = r0[x0] * (1.f - wx) + r0[x1] * wx;
    Spectrum bottom = r1[x0] * (1.f - wx) + r1[x1] * wx;
    return top * (1.f - wy) + bottom * wy;
}

std::optional<LightLiSample> EnvmapLight::sample_li(const LightSampleContext&, Vec2f u) const {
    float pdf_uv;
    Vec2f p = m_dist.sample_continuous(u, &pdf_uv);
    if (!(pdf_uv > 0.f)) return std::nullopt;
    Vec2f uv(p.x + half_texel(), p.y);
    if (uv.x >= 1.f) uv.x -= 1.f;
    float sin_theta;
    Vec3f d = uv_to_direction(uv, &sin_theta);
    if (!(sin_theta > 0.f)) return std::nullopt;
    LightLiSample s;
    s.wi = normalize(m_rot * d);
    s.pdf = pdf_uv / (2.f * kPi * kPi * sin_theta);
    s.L = lookup(uv);
    s.infinite = true;
    if (s.L.is_black() || !std::isfinite(s.pdf)) return std::nullopt;
    return s;
}

float EnvmapLight::pdf_li(const LightSampleContext&, const Vec3f& wi) const {
    Vec3f d = to_local(wi);
    float sin_theta = std::sqrt(d.x * d.x + d.z * d.z);
    if (!(sin_theta > 0.f)) return 0.f;
    Vec2f uv = direction_to_uv(d);
    float s = uv.x - half_texel();
    s -= std::floor(s);
    return m_dist.pdf(Vec2f(s, uv.y)) / (2.f * kPi * kPi * sin_theta);
}

float EnvmapLight::power(float scene_radius) const {
    return float(kPi * double(scene_radius) * scene_radius * m_integral);
}

std::string EnvmapLight::to_string() const {
    return "EnvmapLight[" + (m_name.empty() ? std::string() : "filename=" + m_name + ", ") +
           "resolution=" + std::to_string(m_w) + "x" + std::to_string(m_h) + "]";
}
}  // namespace pellucid
