// Orthonormal frames: the local shading frame has z = normal. Written over a lane type F
// (math/lane_types.h): Frame is FrameT<float>; the packet kernel uses FrameT of its packet.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cmath>

#include "pellucid/math/lane_types.h"

namespace pellucid {

/// Build two unit tangents t, b with (t, b, n) right-handed, for a unit n, without a branch.
/// Duff et al. 2017, "Building an Orthonormal Basis, Revisited", JCGT 6(1), Listing 3.
template <class F>
inline void coordinate_system(const V3<F>& n, V3<F>& t, V3<F>& b) {
    const F sign = lane::copysign(F(1.f), n.z);
    const F a = F(-1.f) / (sign + n.z);
    const F bb = n.x * n.y * a;
    t = V3<F>(F(1.f) + sign * n.x * n.x * a, sign * bb, lane::neg(sign) * n.x);
    b = V3<F>(bb, sign + n.y * n.y * a, lane::neg(n.y));
}

/// An orthonormal basis (s, t, n). to_local maps world vectors into the frame, to_world back.
template <class F>
struct FrameT {
    V3<F> s{F(1.f), F(0.f), F(0.f)}, t{F(0.f), F(1.f), F(0.f)}, n{F(0.f), F(0.f), F(1.f)};

    FrameT() = default;
    FrameT(const V3<F>& s_, const V3<F>& t_, const V3<F>& n_) : s(s_), t(t_), n(n_) {}
    static FrameT from_z(const V3<F>& n) {
        FrameT f;
        f.n = n;
        coordinate_system<F>(n, f.s, f.t);
        return f;
    }
    /// Frame with z = n and x as close to `x` as possible (Gram–Schmidt); from_z where x is
    /// (nearly) parallel to n.
    static FrameT from_xz(const V3<F>& x, const V3<F>& n) {
        V3<F> s = x - n * dot(n, x);
        const F l2 = length2(s);
        const auto ok = l2 > F(1e-12f);
        if (lane::none(ok)) return from_z(n);
        s = s / lane::sqrt(lane::select(ok, l2, F(1.f)));
        FrameT f(s, cross(n, s), n);
        if (lane::all(ok)) return f;
        const FrameT z = from_z(n);
        return FrameT(lane::select(ok, f.s, z.s), lane::select(ok, f.t, z.t), n);
    }
    V3<F> to_local(const V3<F>& v) const { return V3<F>(dot(v, s), dot(v, t), dot(v, n)); }
    V3<F> to_world(const V3<F>& v) const { return s * v.x + t * v.y + n * v.z; }
};
using Frame = FrameT<float>;
}  // namespace pellucid
