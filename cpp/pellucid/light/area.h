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
#include "pellucid/sampling/distribution_1d.h"

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
}  // namespace pellucid
