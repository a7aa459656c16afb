// The vertex of a hit record — point, error bound, geometric normal and shading frame — written
// once over a lane type F (simd/lane.h) for the two shapes whose vertex needs no per-hit solve: the
// analytic sphere and the triangle of a flat-shaded mesh (TriangleMesh::flat). Scene::fill_hit
// builds every such record with the float instantiation, and the path kernel builds the vertices of
// a whole packet of hits with the packet's, so both carry the same bits.
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

/// The partial derivatives of a sphere hit's position in the sphere's (u, v) parameterisation.
template <class F>
struct SphereTangentsT {
    V3<F> dpdu, dpdv;
    V3<F> local;  ///< the hit's direction from the centre in object space (unit)
};

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
