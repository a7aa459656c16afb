// Area lights.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/light/area.h"

#include "pellucid/light/light.h"

#include <cmath>

#include "pellucid/math/constants.h"
#include "pellucid/math/frame.h"
#include "pellucid/sampling/warp.h"

namespace pellucid {

AreaLight::AreaLight(const TriangleMesh& mesh, const Spectrum& radiance, bool two_sided)
    : m_radiance(radiance), m_two_sided(two_sided), m_is_sphere(false) {
    size_t n = mesh.triangle_count();
    std::vector<float> areas(n);
    m_tri.reserve(3 * n);
    m_tri_n.reserve(n);
    m_tri_err.reserve(n);
    for (size_t t = 0; t < n; ++t) {
        const Point3f& a = mesh.positions[mesh.indices[3 * t]];
        const Point3f& b = mesh.positions[mesh.indices[3 * t + 1]];
        const Point3f& c = mesh.positions[mesh.indices[3 * t + 2]];
        m_tri.insert(m_tri.end(), {a, b, c});
        Vec3f ng = cross(b - a, c - a);
        areas[t] = 0.5f * length(ng);
        ng = areas[t] > 0.f ? normalize(ng) : Vec3f(0, 0, 1);
        // Emission follows the shading normals' side when the mesh has them (as the hit record does).
        if (!mesh.normals.empty()) {
            Vec3f ns = mesh.normals[mesh.indices[3 * t]] + mesh.normals[mesh.indices[3 * t + 1]] +
                       mesh.normals[mesh.indices[3 * t + 2]];
            if (dot(ns, ng) < 0.f) ng = -ng;
        }
        m_tri_n.push_back(ng);
        m_tri_err.push_back(gamma(6) * (abs(a) + abs(b) + abs(c)));
        m_area += areas[t];
    }
    // sample_mesh_light's rows and CDF: the triangles of nonzero area, their areas summed in double.
    double total = 0.0;
    for (size_t t = 0; t < n; ++t) total += areas[t] > 0.f ? double(areas[t]) : 0.0;
    double acc = 0.0;
    m_cdf.push_back(0.f);
    for (size_t t = 0; t < n; ++t) {
        if (!(areas[t] > 0.f)) continue;
        for (int c = 0; c < 9; ++c) m_rows.push_back(m_tri[3 * t + size_t(c / 3)][c % 3]);
        for (int c = 0; c < 3; ++c) m_rows.push_back(m_tri_n[t][c]);
        for (int c = 0; c < 3; ++c) m_rows.push_back(m_tri_err[t][c]);
        m_rows.push_back(0.f);
        acc += double(areas[t]);
        m_cdf.push_back(float(acc / total));
    }
    if (m_cdf.size() > 1) m_cdf.back() = 1.f;
    const size_t count = m_cdf.size() - 1;
    while (size_t(m_top ? 2 * m_top : 1) < count) m_top = m_top ? 2 * m_top : 1;
}

AreaLight::AreaLight(const Point3f& center, float radius, bool flip_normals, const Spectrum& radiance,
                     bool two_sided)
    : m_radiance(radiance), m_two_sided(two_sided), m_is_sphere(true), m_center(center),
      m_radius(radius), m_flip(flip_normals) {
    m_area = 4.f * kPi * radius * radius;
}

std::optional<LightLiSample> AreaLight::sample_li(const LightSampleContext& ctx, Vec2f u) const {
    // The packet path tracer's sampling, one lane: sample_sphere, or sample_mesh_light.
    auto to_sample = [&](const auto& x) -> std::optional<LightLiSample> {
        if (!x.valid) return std::nullopt;
        LightLiSample s;
        s.p_light = x.p;
        s.n_light = x.n;
        s.p_error = x.err;
        s.wi = x.wi;
        s.pdf = x.pdf;
        s.L = L(s.n_light, -s.wi);
        if (s.L.is_black()) return std::nullopt;
        return s;
    };
    if (m_is_sphere) return to_sample(sample_sphere<float>(m_center, m_radius, m_flip, ctx.p, u));
    if (m_cdf.size() < 2) return std::nullopt;  // no triangle of nonzero area
    return to_sample(sample_mesh_light<float>(m_rows.data(), m_cdf.data(), 0, 0, int32_t(m_cdf.size() - 1), m_top, m_area,
                                              ctx.p, u));
}

float AreaLight::pdf_li(const LightSampleContext& ctx, const Vec3f& wi, const Point3f& p_light,
                        const Normal3f& n_light) const {
    if (m_is_sphere) {
        const Vec3f to_c = m_center - ctx.p;
        const float d2 = dot(to_c, to_c), r2 = m_radius * m_radius;
        if (sphere_outside<float>(d2, r2)) {  // sample_sphere's cone density
            float sin2_max, omc;
            sphere_cone<float>(d2, r2, &sin2_max, &omc);
            return 1.f / ((2.f * kPi) * omc);
        }
        // Inside: by area, as sample_sphere (its area 4π r², computed as there).
        const float dist2 = length2(p_light - ctx.p);
        const float cos_l = absdot(n_light, wi);
        return cos_l > 0.f ? dist2 / (cos_l * ((4.f * kPi) * r2)) : 0.f;
    }
    float dist2 = length2(p_light - ctx.p);
    float cos_l = absdot(n_light, wi);
    return cos_l > 0.f ? dist2 / (cos_l * m_area) : 0.f;
}

template <class LightT>
EmitterTable make_emitter_table(const std::vector<LightT>& lights, const std::vector<float>& pmf) {
    EmitterTable t;
    std::vector<double> weights;
    for (size_t li = 0; li < lights.size(); ++li) {
        const AreaLight* al = std::get_if<AreaLight>(&lights[li]);
        if (!al || al->is_sphere()) return EmitterTable{};
        if (!(pmf[li] > 0.f) || !(al->area() > 0.f)) continue;
        const std::vector<Point3f>& v = al->triangles();
        for (size_t k = 0; 3 * k + 2 < v.size(); ++k) {
            const double area = 0.5 * double(length(cross(v[3 * k + 1] - v[3 * k], v[3 * k + 2] - v[3 * k])));
            if (!(area > 0.0)) continue;
            for (int c = 0; c < 9; ++c) t.data.push_back(v[3 * k + size_t(c / 3)][c % 3]);
            for (int c = 0; c < 3; ++c) t.data.push_back(al->triangle_normals()[k][c]);
            for (int c = 0; c < 3; ++c) t.data.push_back(al->triangle_errors()[k][c]);
            for (int c = 0; c < 3; ++c) t.data.push_back(al->radiance()[c]);
            t.data.push_back(al->two_sided() ? 1.f : 0.f);
            t.data.push_back(pmf[li] / al->area());
            weights.push_back(double(pmf[li]) * area / double(al->area()));
        }
    }
    if (weights.empty()) return EmitterTable{};
    t.data.insert(t.data.end(), EmitterTable::kPad, 0.f);
    double sum = 0.0, acc = 0.0;
    for (double w : weights) sum += w;
    t.cdf.push_back(0.f);
    for (double w : weights) {
        acc += w;
        t.cdf.push_back(float(acc / sum));
    }
    t.cdf.back() = 1.f;
    while (size_t(t.search_top ? 2 * t.search_top : 1) < weights.size()) t.search_top = t.search_top ? 2 * t.search_top : 1;
    return t;
}
template EmitterTable make_emitter_table<Light>(const std::vector<Light>&, const std::vector<float>&);

float AreaLight::power() const { return kPi * m_area * m_radiance.average() * (m_two_sided ? 2.f : 1.f); }

std::string AreaLight::to_string() const {
    return std::string("AreaLight[") + (m_is_sphere ? "sphere" : "mesh") + ", radiance=" + m_radiance.to_string() +
           ", area=" + std::to_string(m_area) + (m_two_sided ? ", two_sided" : "") + "]";
}
}  // namespace pellucid
