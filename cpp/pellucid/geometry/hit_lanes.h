// The vertex of a hit record — point, error bound, geometric normal and shading frame — written
// once over a lane type F (simd/lane.h) for the analytic sphere, the triangle of a flat-shaded mesh
// (TriangleMesh::flat) and the triangle with interpolated vertex normals. Scene::fill_hit and
// TriangleMesh::flat_triangle build theirs with the float instantiation, and the path kernel builds
// the vertices of a whole packet of hits with the packet's, so both carry the same bits.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include "pellucid/math/constants.h"
#include "pellucid/math/frame.h"
#include "pellucid/math/lane_types.h"

namespace pellucid {

/// What the path tracer shades with at a surface hit.
template <class F>
struct HitVertexT {
    V3<F> p, p_error, ng;
    FrameT<F> shading;
};

/// A 3×3 matrix by its columns.
template <class F>
struct Mat3T {
    V3<F> c0, c1, c2;
    /// M·v, as GLM's mat3 · vec3: (c0·v.x + c1·v.y) + c2·v.z.
    V3<F> mul(const V3<F>& v) const { return c0 * v.x + c1 * v.y + c2 * v.z; }
    /// Mᵀ·v, as GLM's transpose(M) · vec3: the dot products of the columns with v.
    V3<F> mul_transposed(const V3<F>& v) const { return V3<F>(dot(c0, v), dot(c1, v), dot(c2, v)); }
};

/// A hit at barycentrics (b1, b2) of the triangle (p0, p1, p2) of a flat-shaded mesh, whose geometric
/// normal and shading frame are the triangle's constants. The error bound of the interpolated point
/// is pbrt-v4's (§6.8.5, eq. 6.31).
template <class F>
inline HitVertexT<F> flat_triangle_vertex(const V3<F>& p0, const V3<F>& p1, const V3<F>& p2, const F& b1, const F& b2,
                                          const V3<F>& ng, const FrameT<F>& shading) {
    const F b0 = F(1.f) - b1 - b2;
    HitVertexT<F> v;
    v.p = b0 * p0 + b1 * p1 + b2 * p2;
    v.p_error = F(gamma(7)) * (abs(b0 * p0) + abs(b1 * p1) + abs(b2 * p2));
    v.ng = ng;
    v.shading = shading;
    return v;
}

/// A triangle's constants: its unit geometric normal (p₁ − p₀) × (p₂ − p₀), and ∂p/∂u, ∂p/∂v from its
/// uv parameterisation (pbrt-v4 §6.5.3), or, where that is degenerate, the tangents of from_z(ng).
template <class F>
struct TriangleTangentsT {
    V3<F> ng, dpdu, dpdv;
};
template <class F>
inline TriangleTangentsT<F> triangle_tangents(const V3<F>& p0, const V3<F>& p1, const V3<F>& p2, const V2<F>& uv0,
                                              const V2<F>& uv1, const V2<F>& uv2) {
    TriangleTangentsT<F> f;
    f.ng = normalize(cross(p1 - p0, p2 - p0));
    const F du02 = uv0.x - uv2.x, dv02 = uv0.y - uv2.y, du12 = uv1.x - uv2.x, dv12 = uv1.y - uv2.y;
    const V3<F> dp02 = p0 - p2, dp12 = p1 - p2;
    const F det = du02 * dv12 - dv02 * du12;
    const auto regular = !(lane::abs(det) < F(1e-9f));
    const F inv = F(1.f) / lane::select(regular, det, F(1.f));
    f.dpdu = (dv12 * dp02 - dv02 * dp12) * inv;
    f.dpdv = (du02 * dp12 - du12 * dp02) * inv;
    const auto fallback = !regular || length2(cross(f.dpdu, f.dpdv)) == F(0.f);
    if (lane::any(fallback)) {
        const FrameT<F> fr = FrameT<F>::from_z(f.ng);
        f.dpdu = lane::select(fallback, fr.s, f.dpdu);
        f.dpdv = lane::select(fallback, fr.t, f.dpdv);
    }
    return f;
}

/// A hit at barycentrics (b1, b2) of a triangle with vertex normals n₀, n₁, n₂: the shading normal
/// is their interpolation, normalised (the geometric normal turns to its side), and the frame's s is
/// ∂p/∂u made perpendicular to it. Where the interpolated normal vanishes, the geometric normal
/// shades.
template <class F>
inline HitVertexT<F> smooth_triangle_vertex(const V3<F>& p0, const V3<F>& p1, const V3<F>& p2, const F& b1, const F& b2,
                                            const TriangleTangentsT<F>& tri, const V3<F>& n0, const V3<F>& n1,
                                            const V3<F>& n2) {
    const F b0 = F(1.f) - b1 - b2;
    HitVertexT<F> v;
    v.p = b0 * p0 + b1 * p1 + b2 * p2;
    v.p_error = F(gamma(7)) * (abs(b0 * p0) + abs(b1 * p1) + abs(b2 * p2));
    const V3<F> n = b0 * n0 + b1 * n1 + b2 * n2;
    const auto has = length2(n) > F(0.f);
    const V3<F> ns = lane::select(has, normalize(n), tri.ng);
    v.ng = lane::select(has && dot(ns, tri.ng) < F(0.f), -tri.ng, tri.ng);
    v.shading = FrameT<F>::from_xz(tri.dpdu, ns);
    return v;
}

/// The partial derivatives of a sphere hit's position in the sphere's (u, v) parameterisation.
template <class F>
struct SphereTangentsT {
    V3<F> dpdu, dpdv;
    V3<F> local;  ///< the hit's direction from the centre in object space (unit)
};

/// A sphere hit's uv from its `local` direction (SphereTangentsT): (φ/2π, θ/π), φ = atan2(y, x) in
/// [0, 2π), θ = acos z (libm's, one lane at a time; Scene::fill_hit and the path tracer's vertex
/// lanes of textured materials).
Vec2f sphere_uv(const Vec3f& local);

/// A hit at distance t along (o, d) on the sphere of centre c and radius r whose object space
/// maps to world by the orthogonal R (ShapeRecord::rotation), with the normal flipped where `flip`.
/// The point is re-projected onto the surface (its remaining error is a few ulps of |p|, pbrt-v4
/// §6.8.5). The parameterisation is the unit sphere's in object space, (sin θ cos φ, sin θ sin φ,
/// cos θ) with u = φ/2π, v = θ/π, carried to world by R (as Mitsuba 3's sphere); the shading frame's
/// s is ∂p/∂u made perpendicular to the normal, t = n × s (Mitsuba 3's initialize_sh_frame). At a
/// pole, where φ is undefined and ∂p/∂u vanishes, the directions at φ = 0 are taken, with the
/// lengths at the equator.
template <class F>
inline HitVertexT<F> sphere_vertex(const V3<F>& o, const V3<F>& d, const F& t, const V3<F>& c, const F& r,
                                   const Mat3T<F>& R, const MaskT<F>& flip, SphereTangentsT<F>* tangents) {
    const V3<F> hit = o + t * d;
    V3<F> n = hit - c;
    const F len = length(n);
    n = lane::select(len > F(0.f), n / lane::select(len > F(0.f), len, F(1.f)), R.c2);
    HitVertexT<F> v;
    v.p = c + r * n;
    v.p_error = F(gamma(5)) * (abs(v.p) + abs(c)) + V3<F>(F(gamma(5)) * r);
    v.ng = lane::select(flip, -n, n);
    // ∂p/∂u = 2π·r·(−l.y, l.x, 0), ∂p/∂v = π·r·(cos θ cos φ, cos θ sin φ, −sin θ), mapped by R.
    const V3<F> l = R.mul_transposed(n);
    const F st = lane::sqrt(l.x * l.x + l.y * l.y);
    const F k_u = F(2.f * kPi) * r, k_v = F(kPi) * r;
    const auto regular = st > F(1e-6f);
    const F st_safe = lane::select(regular, st, F(1.f));
    const V3<F> dpdu_l = lane::select(regular, k_u * V3<F>(lane::neg(l.y), l.x, F(0.f)), k_u * V3<F>(F(0.f), F(1.f), F(0.f)));
    const V3<F> dpdv_l = lane::select(regular, k_v * V3<F>(l.z * l.x / st_safe, l.z * l.y / st_safe, lane::neg(st)),
                                      k_v * V3<F>(l.z, F(0.f), F(0.f)));
    tangents->dpdu = R.mul(dpdu_l);
    tangents->dpdv = R.mul(dpdv_l);
    tangents->local = l;
    v.shading = FrameT<F>::from_xz(tangents->dpdu, v.ng);
    return v;
}
}  // namespace pellucid
