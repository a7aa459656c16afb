// Orthonormal frames: the local shading frame has z = normal.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cmath>

#include "pellucid/math/vec.h"

namespace pellucid {

/// Build two unit tangents t, b with (t, b, n) right-handed, for a unit n.
/// Duff et al. 2017, "Building an Orthonormal Basis, Revisited", JCGT 6(1), Listing 3.
inline void coordinate_system(const Vec3f& n, Vec3f& t, Vec3f& b) {
    float sign = std::copysign(1.f, n.z);
    float a = -1.f / (sign + n.z);
    float bb = n.x * n.y * a;
    t = Vec3f(1.f + sign * n.x * n.x * a, sign * bb, -sign * n.x);
    b = Vec3f(bb, sign + n.y * n.y * a, -n.y);
}

/// An orthonormal basis (s, t, n). to_local maps world vectors into the frame, to_world back.
struct Frame {
    Vec3f s{1, 0, 0}, t{0, 1, 0}, n{0, 0, 1};

    Frame() = default;
    Frame(const Vec3f& s_, const Vec3f& t_, const Vec3f& n_) : s(s_), t(t_), n(n_) {}
    static Frame from_z(const Vec3f& n) {
        Frame f;
        f.n = n;
        coordinate_system(n, f.s, f.t);
        return f;
    }
    /// Frame with z = n and x as close to `x` as possible (Gram–Schmidt); falls back to from_z.
    static Frame from_xz(const Vec3f& x, const Vec3f& n) {
        Vec3f s = x - n * dot(n, x);
        float l2 = length2(s);
        if (!(l2 > 1e-12f)) return from_z(n);
        s /= std::sqrt(l2);
        return Frame(s, cross(n, s), n);
    }
    Vec3f to_local(const Vec3f& v) const { return Vec3f(dot(v, s), dot(v, t), dot(v, n)); }
    Vec3f to_world(const Vec3f& v) const { return s * v.x + t * v.y + n * v.z; }
};
}  // namespace pellucid
