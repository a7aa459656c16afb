// Textured parameters, bump mapping (as the seeds define it) and normal mapping.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/material/textured.h"

#include <cmath>

namespace pellucid {
namespace {

// Height B (already scaled) at the hit shifted by (du, dv) in uv, and by the matching first-order
// move of the position for solid textures.
float height_at(const TextureList& textures, uint32_t id, float scale, TextureEvalContext ctx,
                const SurfaceInteraction& si, float du, float dv) {
    ctx.uv += Vec2f(du, dv);
    ctx.p += du * si.dpdu + dv * si.dpdv;
    return scale * eval_texture(textures, id, ctx).average();
}
}  // namespace

TextureEvalContext texture_eval_context(const SurfaceInteraction& si) {
    TextureEvalContext ctx;
    ctx.p = si.p;
    ctx.dpdx = si.dpdx;
    ctx.dpdy = si.dpdy;
    ctx.uv = si.uv;
    ctx.dudx = si.dudx;
    ctx.dudy = si.dudy;
    ctx.dvdx = si.dvdx;
    ctx.dvdy = si.dvdy;
    return ctx;
}

bool material_reads_footprint(const MaterialTextures& mt, const TextureList& textures) {
    for (int i = 0; i < mt.count; ++i)
        if (texture_reads_footprint(textures, mt.bound[i])) return true;
    if (mt.normal_map >= 0 && texture_reads_footprint(textures, uint32_t(mt.normal_map))) return true;
    if (mt.bump >= 0) {
        // Mitsuba's model takes the bilinear luminance gradient, which reads no footprint; without
        // one it falls back to an analytic gradient or to differences over footprint steps.
        if (mt.bump_model != BumpModel::Mitsuba || !texture_has_luminance_gradient(textures, uint32_t(mt.bump))) return true;
    }
    return false;
}

Vec2f bump_steps(const TextureEvalContext& ctx) {
    // One pixel footprint in u and in v: the mean extent of the footprint's two screen axes
    // (pbrt-v4 §10.5.1 uses the same measure). Without ray differentials there is no footprint,
    // and a fixed 5e-4 in uv (about one texel of a 2k map) is used instead.
    float du = 0.5f * (std::fabs(ctx.dudx) + std::fabs(ctx.dudy));
    float dv = 0.5f * (std::fabs(ctx.dvdx) + std::fabs(ctx.dvdy));
    if (!(du > 0.f) || !std::isfinite(du)) du = kBumpFallbackStep;
    if (!(dv > 0.f) || !std::isfinite(dv)) dv = kBumpFallbackStep;
    return Vec2f(du, dv);
}

Normal3f bump_normal(const TextureList& textures, uint32_t height, float scale, const TextureEvalContext& ctx,
                     const SurfaceInteraction& si, const Normal3f& n, float du, float dv, bool allow_analytic) {
    // The bumped surface F' = F + B·n has tangents
    //   ∂F'/∂u = ∂F/∂u + (∂B/∂u)·n + B·∂n/∂u   (and likewise in v),
    // and normal n' = normalize(∂F'/∂u × ∂F'/∂v) (Blinn 1978, eq. 4; the seeds' definition).
    // ∂B/∂u: the texture's analytic gradient where it has one, else a forward difference of step
    // Δu (first order: error O(Δu)).
    float B, dBdu, dBdv;
    Spectrum value;
    if (allow_analytic && texture_gradient_uv(textures, height, ctx, si.dpdu, si.dpdv, &dBdu, &dBdv, &value)) {
        B = scale * value.average();  // the value from the same evaluation as the gradient
        dBdu *= scale;
        dBdv *= scale;
    } else {
        B = height_at(textures, height, scale, ctx, si, 0.f, 0.f);
        dBdu = (height_at(textures, height, scale, ctx, si, du, 0.f) - B) / du;
        dBdv = (height_at(textures, height, scale, ctx, si, 0.f, dv) - B) / dv;
    }
    Vec3f dpdu = si.dpdu + dBdu * n + B * si.dndu;
    Vec3f dpdv = si.dpdv + dBdv * n + B * si.dndv;
    Vec3f np = cross(dpdu, dpdv);
    float len = length(np);
    if (!(len > 0.f) || !std::isfinite(len)) return n;
    np /= len;
    return dot(np, n) < 0.f ? -np : np;  // keep the side of the unbumped shading normal
}

Normal3f bump_normal_mitsuba(const SurfaceInteraction& si, const Normal3f& n, float scale, const Vec2f& grad) {
    return bump_normal_mitsuba_lanes<float>(si.dpdu, si.dpdv, si.ng, n, scale, grad.x, grad.y);
}

namespace {
// The height gradient for BumpModel::Mitsuba, before `scale`: Mitsuba's bilinear luminance
// gradient where the texture has one; otherwise the texture's analytic gradient, else a forward
// difference over the footprint steps (Mitsuba refuses such textures; we fall back).
Vec2f mitsuba_height_gradient(const MaterialTextures& mt, const TextureList& textures, const TextureEvalContext& ctx,
                              const SurfaceInteraction& si) {
    const uint32_t id = uint32_t(mt.bump);
    float gu, gv;
    if (texture_luminance_gradient_uv(textures, id, ctx, &gu, &gv)) return Vec2f(gu, gv);
    if (texture_gradient_uv(textures, id, ctx, si.dpdu, si.dpdv, &gu, &gv)) return Vec2f(gu, gv);
    Vec2f d = bump_steps(ctx) * mt.bump_step_scale;
    float b = height_at(textures, id, 1.f, ctx, si, 0.f, 0.f);
    return Vec2f((height_at(textures, id, 1.f, ctx, si, d.x, 0.f) - b) / d.x,
                 (height_at(textures, id, 1.f, ctx, si, 0.f, d.y) - b) / d.y);
}
}  // namespace

Frame perturbed_shading_frame(const MaterialTextures& mt, const TextureList& textures, const TextureEvalContext& ctx,
                              const SurfaceInteraction& si) {
    Normal3f n = si.shading.n;
    if (mt.normal_map >= 0) {
        // Tangent-space normal map: rgb ∈ [0,1]³ → n_ts = 2·rgb − 1 in the frame (s ∥ ∂p/∂u,
        // t = n × s, n) — the OpenGL convention (Mitsuba's too); DirectX stores −t in green.
        Spectrum c = eval_texture(textures, uint32_t(mt.normal_map), ctx);
        Vec3f nt(2.f * c.r - 1.f, 2.f * c.g - 1.f, 2.f * c.b - 1.f);
        // 8-bit maps cannot store ½: the flat code 128 decodes to 1/255. Tilts within one 8-bit step
        // of zero are taken as zero, so a flat map, (128, 128, 255) or (0.5, 0.5, 1), changes nothing.
        for (int i = 0; i < 2; ++i)
            if (std::fabs(nt[i]) <= 1.f / 255.f + 1e-6f) nt[i] = 0.f;
        if (mt.normal_map_directx) nt.y = -nt.y;
        Vec3f w = si.shading.to_world(nt);
        float len = length(w);
        if (len > 0.f && std::isfinite(len)) n = w / len;
    }
    const bool mitsuba = mt.bump_model == BumpModel::Mitsuba;
    if (mt.bump >= 0) {
        if (mitsuba) {
            n = bump_normal_mitsuba(si, n, mt.bump_scale, mitsuba_height_gradient(mt, textures, ctx, si));
        } else {
            Vec2f d = bump_steps(ctx) * mt.bump_step_scale;
            n = bump_normal(textures, uint32_t(mt.bump), mt.bump_scale, ctx, si, n, d.x, d.y, true);
        }
    }
    if (mt.invalid_normals == InvalidNormals::Bend) {
        // A perturbed normal can put the viewer below the shading hemisphere while it is above the
        // geometric one: then no light could ever be reflected (black pixels along silhouettes).
        // Remove just enough of n's component along wo that wo sits slightly above it (a minimal
        // change).
        float side = dot(si.wo, si.ng) >= 0.f ? 1.f : -1.f;
        constexpr float kMinCos = 0.02f;
        if (side * dot(si.wo, n) < kMinCos) {
            Vec3f fixed = n - si.wo * (dot(si.wo, n) - side * kMinCos);
            float len = length(fixed);
            if (len > 0.f) n = fixed / len;
        }
    } else if (mt.invalid_normals == InvalidNormals::Mirror) {
        n = mirror_invalid_normal<float>(si.shading, si.wo, n);
    }
    return mitsuba ? Frame::from_xz(si.shading.s, n) : Frame::from_xz(si.dpdu, n);
}
}  // namespace pellucid
