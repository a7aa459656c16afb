// Hand-built hit records for the texture and bump tests.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include "pellucid/geometry/interaction.h"
#include "pellucid/texture/texture.h"

namespace pellucid::test {

/// A hit on the plane z = 0 with the parameterisation p = (u, v, 0), the viewer along the normal.
inline SurfaceInteraction plane_hit(const Vec2f& uv = Vec2f(0.f)) {
    SurfaceInteraction si;
    si.p = Point3f(uv.x, uv.y, 0.f);
    si.uv = uv;
    si.ng = Normal3f(0.f, 0.f, 1.f);
    si.dpdu = Vec3f(1, 0, 0);
    si.dpdv = Vec3f(0, 1, 0);
    si.shading = Frame::from_xz(si.dpdu, si.ng);
    si.wo = si.ng;
    return si;
}
/// The texture lookup context of a hit, without a footprint.
inline TextureEvalContext ctx_of(const SurfaceInteraction& si) {
    TextureEvalContext c;
    c.p = si.p;
    c.uv = si.uv;
    return c;
}
}  // namespace pellucid::test
