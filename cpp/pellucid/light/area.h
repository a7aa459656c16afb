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
#include "pellucid/math/frame.h"
#include "pellucid/math/ray.h"
#include "pellucid/sampling/distribution_1d.h"
#include "pellucid/sampling/warp.h"

namespace pellucid {

/// The cone of directions a sphere of squared radius r2 subtends from a point at squared distance
/// d2 > r2 from its centre: sin²θmax = r2/d2, and 1 − cos θmax, from the series 1 − cos θ ≈
/// sin²θ/2 where the cone is narrower than 1.5° (there 1 − √(1 − sin²θ) would lose its digits).
/// The density of a uniform direction in the cone is 1/(2π(1 − cos θmax)).
constexpr float kSphereNarrowSin2 = 0.00068523f;  ///< sin² 1.5°
template <class F>
inline void sphere_cone(const F& d2, const F& r2, F* sin2_max, F* one_minus_cos_max) {
    *sin2_max = r2 / d2;
    const F cos_max = lane::sqrt(lane::max(F(0.f), F(1.f) - *sin2_max));
    *one_minus_cos_max = lane::select(*sin2_max < F(kSphereNarrowSin2), *sin2_max * F(0.5f), F(1.f) - cos_max);
}
/// Whether p_ref at squared distance d2 from the centre of a sphere of squared radius r2 is outside
/// it (with a margin: from points on or inside it the sphere is sampled by area).
template <class F>
inline MaskT<F> sphere_outside(const F& d2, const F& r2) { return d2 > r2 * F(1.0001f); }

/// A point on a sphere light sampled as seen from p_ref, in kLaneWidth<F> lanes: its position, its
/// emitting normal (inward where flip), its error bound, the unit direction toward it and the
/// solid-angle density at p_ref. valid is false where no sample exists (the emitter's radiance and
/// sides are the caller's).
template <class F>
struct SphereSample {
    MaskT<F> valid;
    V3<F> p, n, err, wi;
    F pdf;
};
/// From outside, a uniform direction in the cone the sphere subtends (Shirley & Wang 1996; pbrt-v4
/// §6.2.4): cos θ uniform on [cos θmax, 1], and the point where that direction first meets the
/// sphere found by the law of cosines in the triangle (p_ref, centre, point), whose angle α at the
/// centre has cos α = sin²θ/sin θmax + cos θ √(1 − sin²θ/sin²θmax), in float without a ray–sphere
/// intersection. From inside, a uniform point on the sphere, its area density converted to solid
/// angle (dist²/(|cos θ_light| area), Veach 1997 eq. 8.10). Only sqrt and warp.h's sincos are used,
/// so every lane type gives the same bits.
template <class F>
inline SphereSample<F> sample_sphere(const V3<F>& c, const F& r, const MaskT<F>& flip, const V3<F>& p_ref, const V2<F>& u) {
    using M = MaskT<F>;
    const F r2 = r * r;
    const V3<F> to_c = c - p_ref;
    const F d2 = dot(to_c, to_c);
    const M outside = sphere_outside<F>(d2, r2);
    F cphi, sphi;
    detail::sincos_two_pi<F>(u.y, &cphi, &sphi);
    SphereSample<F> s;
    V3<F> n;  // unit, outward
    F pdf_cone;
    {
        F sin2_max, omc;
        sphere_cone<F>(d2, r2, &sin2_max, &omc);
        const M narrow = sin2_max < F(kSphereNarrowSin2);
        // cos θ = 1 − u·(1 − cos θmax), and sin²θ = u sin²θmax in a narrow cone (its first-order form).
        const F cos_t_wide = F(1.f) - u.x * omc;
        const F sin2_t = lane::select(narrow, sin2_max * u.x, F(1.f) - cos_t_wide * cos_t_wide);
        const F cos_t = lane::select(narrow, lane::sqrt(lane::max(F(0.f), F(1.f) - sin2_t)), cos_t_wide);
        const F sin_max = lane::sqrt(sin2_max);
        const F safe_sin_max = lane::select(sin_max > F(0.f), sin_max, F(1.f));
        const F safe_sin2_max = lane::select(sin2_max > F(0.f), sin2_max, F(1.f));
        const F cos_a = sin2_t / safe_sin_max + cos_t * lane::sqrt(lane::max(F(0.f), F(1.f) - sin2_t / safe_sin2_max));
        const F sin_a = lane::sqrt(lane::max(F(0.f), F(1.f) - cos_a * cos_a));
        const F d = lane::sqrt(lane::select(outside, d2, F(1.f)));
        const V3<F> wc = to_c / d;
        V3<F> sx, sy;
        coordinate_system<F>(wc, sx, sy);
        // The point's direction from the centre: α away from −wc, at azimuth φ.
        n = -(sx * (sin_a * cphi) + sy * (sin_a * sphi) + wc * cos_a);
        pdf_cone = F(1.f) / (F(2.f * kPi) * omc);
    }
    const M inside = !outside;
    if (lane::any(inside)) {
        n = lane::select(inside, square_to_uniform_sphere_lanes<F>(u), n);
    }
    s.p = c + n * r;
    s.n = lane::select(flip, -n, n);
    s.err = (abs(s.p) + abs(c)) * F(gamma(5)) + V3<F>(F(gamma(5)) * r);
    const V3<F> dp = s.p - p_ref;
    const F dist2 = dot(dp, dp);
    s.wi = dp / lane::sqrt(lane::select(dist2 > F(0.f), dist2, F(1.f)));
    const F cos_l = lane::abs(dot(s.n, s.wi));
    const F pdf_area = dist2 / (lane::select(cos_l > F(0.f), cos_l, F(1.f)) * (F(4.f * kPi) * r2));
    s.pdf = lane::select(outside, pdf_cone, pdf_area);
    s.valid = dist2 > F(0.f) && s.pdf > F(0.f) && s.pdf < F(kInfinity) && (outside || cos_l > F(0.f));
    return s;
}

/// A mesh emitter as sample_mesh_light reads it: per triangle kMeshLightStride floats (corners 9,
/// the unit normal of the side that emits 3, the error bound of a sampled point 3, then 0), and
/// the running sums of the triangles' areas over the light's area in float (count + 1 entries, 0
/// first, the last 1). Triangles of zero area are left out.
constexpr int kMeshLightStride = 16;

template <class F>
struct MeshLightSample {
    MaskT<F> valid;
    V3<F> p, n, err, wi;
    F pdf;  ///< solid-angle density at p_ref
};

/// A point on a mesh emitter as seen from p_ref, with u: a triangle by its share of the area from
/// u.x (the largest j < count with cdf[j] ≤ u.x, by a binary search of fixed length from `top`,
/// the largest power of two below the most triangles of any lane's light), the remainder of u.x in
/// its interval reused for the point (as Distribution1D::sample_discrete remaps it), a uniform
/// point on the triangle (Heitz 2019, square_to_uniform_triangle), and its area density 1/area
/// converted to solid angle: dist²/(|cos θ_light|·area) (Veach 1997, eq. 8.10). Per lane: the
/// light's first triangle in `tris` (rows of kMeshLightStride), its CDF's offset in `cdf`, its
/// triangle count and its area. AreaLight::sample_li of a mesh is the float instantiation; the
/// light table (light_table.h) runs it on packets.
template <class F>
inline MeshLightSample<F> sample_mesh_light(const float* tris, const float* cdf, const IntT<F>& first,
                                            const IntT<F>& cdf_at, const IntT<F>& count, int top, const F& area,
                                            const V3<F>& p_ref, const V2<F>& u) {
    using I = IntT<F>;
    I j(0);
    const I last = count - I(1);
    for (int step = top; step > 0; step >>= 1) {
        const I c = lane::min(j + I(step), last);
        j = lane::select(lane::int_mask(lane::gather(cdf, cdf_at + c) <= u.x), c, j);
    }
    const F c0 = lane::gather(cdf, cdf_at + j), width = lane::gather(cdf, cdf_at + j + I(1)) - c0;
    const F u_rem = lane::min((u.x - c0) / lane::select(width > F(0.f), width, F(1.f)), F(0x1.fffffep-1f));
    F row[kMeshLightStride];
    lane::gather_rows<kMeshLightStride>(tris, (first + j) * I(kMeshLightStride), row);
    const V2<F> b = square_to_uniform_triangle<F>(V2<F>{u_rem, u.y});
    const F b0 = F(1.f) - b.x - b.y;
    MeshLightSample<F> s;
    s.p = V3<F>(row[0] * b0 + row[3] * b.x + row[6] * b.y, row[1] * b0 + row[4] * b.x + row[7] * b.y,
                row[2] * b0 + row[5] * b.x + row[8] * b.y);
    s.n = V3<F>(row[9], row[10], row[11]);
    s.err = V3<F>(row[12], row[13], row[14]);
    const V3<F> d = s.p - p_ref;
    const F dist2 = dot(d, d);
    s.wi = d / lane::sqrt(lane::select(dist2 > F(0.f), dist2, F(1.f)));
    const F cos_l = lane::abs(dot(s.n, s.wi));
    s.pdf = dist2 / (lane::select(cos_l > F(0.f), cos_l, F(1.f)) * area);
    s.valid = dist2 > F(0.f) && cos_l > F(0.f) && s.pdf < F(kInfinity);
    return s;
}

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
    /// Sphere emitter: its centre, radius and whether its normals point inward.
    const Point3f& center() const { return m_center; }
    float radius() const { return m_radius; }
    bool flipped() const { return m_flip; }
    /// Mesh emitter: its triangles' corners (3 per triangle), unit normals (the side that emits)
    /// and sampled-point error bounds, as sample_li uses them.
    const std::vector<Point3f>& triangles() const { return m_tri; }
    const std::vector<Normal3f>& triangle_normals() const { return m_tri_n; }
    const std::vector<Vec3f>& triangle_errors() const { return m_tri_err; }
    /// Mesh emitter as sample_mesh_light reads it: its triangles of nonzero area as rows, their
    /// area CDF, and the largest power of two below their count (0 for one).
    const std::vector<float>& sampling_rows() const { return m_rows; }
    const std::vector<float>& sampling_cdf() const { return m_cdf; }
    int sampling_top() const { return m_top; }
    std::string to_string() const;

private:
    Spectrum m_radiance;
    bool m_two_sided;
    bool m_is_sphere;
    // Mesh emitter: triangle corners (3 per triangle) and face normals, area distribution.
    std::vector<Point3f> m_tri;
    std::vector<Normal3f> m_tri_n;
    std::vector<Vec3f> m_tri_err;  ///< error bound of a sampled point, per triangle (its vertices are fixed)
    std::vector<float> m_rows;     ///< sample_mesh_light's rows (kMeshLightStride per triangle of nonzero area)
    std::vector<float> m_cdf;      ///< and the running sums of their areas over the light's
    int m_top = 0;
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
    static constexpr int kPad = 4;  ///< zeros after the last row: a row is read as 24 floats (sample_emitter)
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
    // Each lane's row as two row reads (16 and 8 floats; the table is padded past its last row),
    // transposed into packets (lane::gather_rows), not a gather per entry.
    F row[24];
    lane::gather_rows<16>(t.data.data(), base, row);
    lane::gather_rows<8>(t.data.data(), base + I(16), row + 16);
    auto E = [&](int k) { return row[k]; };
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
