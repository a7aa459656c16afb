// Diffuse area emitter bound to a triangle mesh (sampled by area) or an analytic sphere (sampled by
// the solid angle of its cone from outside, by area from inside).
// SPDX-License-Identifier: Apache-2.0
//
// | parameter | type     | default | meaning                                              |
// |-----------|----------|---------|------------------------------------------------------|
// | radiance  | spectrum | 1       | emitted radiance (W·m⁻²·sr⁻¹), ≥ 0                   |
// | two_sided | bool     | false   | emit from both sides (else along the surface normal) |
// JSON (inside a shape): "emitter": {"type": "area", "radiance": [18.4, 14.0, 6.75]}
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "pellucid/geometry/mesh.h"
#include "pellucid/light/light_types.h"
#include "pellucid/math/ray.h"
#include "pellucid/sampling/distribution_1d.h"
#include "pellucid/sampling/warp.h"

namespace pellucid {

class AreaLight {
public:
    /// Emitter on a mesh (the light keeps a copy of the triangles it needs).
    AreaLight(const TriangleMesh& mesh, const Spectrum& radiance, bool two_sided);
    /// Emitter on a sphere; normals point outward unless flip_normals.
    AreaLight(const Point3f& center, float radius, bool flip_normals, const Spectrum& radiance, bool two_sided);

    /// Radiance leaving a point with normal n in direction w.
    Spectrum L(const Normal3f& n, const Vec3f& w) const {
        return (m_two_sided || dot(n, w) > 0.f) ? m_radiance : Spectrum(0.f);
    }
    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx, Vec2f u) const;
    /// Solid-angle density that sample_li produces direction wi reaching (p_light, n_light).
    float pdf_li(const LightSampleContext& ctx, const Vec3f& wi, const Point3f& p_light,
                 const Normal3f& n_light) const;
    /// Total emitted power (W).
    float power() const;
    float area() const { return m_area; }
    bool is_sphere() const { return m_is_sphere; }
    bool two_sided() const { return m_two_sided; }
    const Spectrum& radiance() const { return m_radiance; }
    /// Mesh emitter: its triangles' corners (3 per triangle), unit normals (the side that emits)
    /// and sampled-point error bounds, as sample_li uses them.
    const std::vector<Point3f>& triangles() const { return m_tri; }
    const std::vector<Normal3f>& triangle_normals() const { return m_tri_n; }
    const std::vector<Vec3f>& triangle_errors() const { return m_tri_err; }
    std::string to_string() const;

private:
    Spectrum m_radiance;
    bool m_two_sided;
    bool m_is_sphere;
    // Mesh emitter: triangle corners (3 per triangle) and face normals, area distribution.
    std::vector<Point3f> m_tri;
    std::vector<Normal3f> m_tri_n;
    std::vector<Vec3f> m_tri_err;  ///< error bound of a sampled point, per triangle (its vertices are fixed)
    Distribution1D m_tri_dist;
    // Sphere emitter.
    Point3f m_center{0.f};
    float m_radius = 0.f;
    bool m_flip = false;
    float m_area = 0.f;
};

/// Every emitting triangle of a scene whose lights are all mesh area lights, as one table, so that
/// next-event estimation picks a triangle and a point on it in one step for a whole packet
/// (integrator/path_kernel.h). Triangle j is picked with probability pmf(light)·area_j/area(light),
/// the density pbrt's two-step choice (a light, then a triangle by area) gives, so the MIS
/// densities of AreaLight::pdf_li hold unchanged.
struct EmitterTable {
    /// Floats per triangle: corners (9), emitting normal (3), error bound of a sampled point (3),
    /// radiance (3), two-sided (1 or 0), pmf(light)/area(light) (the density per unit area).
    static constexpr int kStride = 20;
    std::vector<float> data;
    std::vector<float> cdf;  ///< cdf[j] = Σ_{i<j} probability of i; cdf[m] = 1
    int search_top = 0;      ///< largest power of two below the triangle count (0 for one)
    bool empty() const { return cdf.empty(); }
    int size() const { return int(cdf.size()) - 1; }
};
/// The table of `lights` (pmf[i]: the probability NEE picks light i), or an empty one when a
/// light is not an area light on a mesh.
template <class LightT>
EmitterTable make_emitter_table(const std::vector<LightT>& lights, const std::vector<float>& pmf);

/// A point sampled on an emitter table, as seen from p_ref, in kLaneWidth<F> lanes.
template <class F>
struct EmitterSample {
    MaskT<F> valid;
    V3<F> p, n, err, wi;
    RGB<F> L;
    F pdf;  ///< solid-angle density at p_ref, the triangle's choice included
};

/// Pick a triangle with u_sel (a binary search of fixed length, the same in every lane), a uniform
/// point on it with u (Heitz 2019, square_to_uniform_triangle), and convert its area density to
/// solid angle at p_ref: pdf = pdf_area·dist²/|cos θ_light| (Veach 1997, eq. 8.10).
template <class F>
inline EmitterSample<F> sample_emitter(const EmitterTable& t, const F& u_sel, const V2<F>& u, const V3<F>& p_ref) {
    using I = IntT<F>;
    I j(0);
    const I last(t.size() - 1);
    for (int step = t.search_top; step > 0; step >>= 1) {
        const I c = lane::min(j + I(step), last);
        j = lane::select(lane::int_mask(lane::gather(t.cdf.data(), c) <= u_sel), c, j);
    }
    const I base = j * I(EmitterTable::kStride);
    const float* d = t.data.data();
    auto E = [&](int k) { return lane::gather(d + k, base); };
    const V2<F> b = square_to_uniform_triangle<F>(u);
    const F b0 = F(1.f) - b.x - b.y;
    EmitterSample<F> s;
    s.p = V3<F>(E(0) * b0 + E(3) * b.x + E(6) * b.y, E(1) * b0 + E(4) * b.x + E(7) * b.y,
                E(2) * b0 + E(5) * b.x + E(8) * b.y);
    s.n = V3<F>(E(9), E(10), E(11));
    s.err = V3<F>(E(12), E(13), E(14));
    const V3<F> dp = s.p - p_ref;
    const F dist2 = dot(dp, dp);
    s.wi = dp / lane::sqrt(lane::select(dist2 > F(0.f), dist2, F(1.f)));
    const F cos_w = dot(s.n, s.wi), cos_l = lane::abs(cos_w);
    s.pdf = E(19) * dist2 / lane::select(cos_l > F(0.f), cos_l, F(1.f));
    const auto faces = E(18) > F(0.f) || cos_w < F(0.f);  // emits toward -wi
    s.L = lane::select(faces, RGB<F>(E(15), E(16), E(17)), RGB<F>(F(0.f)));
    s.valid = dist2 > F(0.f) && cos_l > F(0.f) && s.pdf < F(kInfinity) && !is_black(s.L);
    return s;
}
}  // namespace pellucid
