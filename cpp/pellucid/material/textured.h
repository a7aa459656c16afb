// Textured material parameters, bump maps and normal maps: what a material adds to its constant
// parameters when some of them vary over the surface.
// SPDX-License-Identifier: Apache-2.0
//
// Design: a material's Params struct holds each parameter as a Tex (material/tex.h), a constant or
// a texture of the scene; the builders bind a Tex to a texture and list the texture in the
// material's MaterialTextures. At a hit, the model's make_bxdf (material/material.h) reads its
// parameters through a TexEval over the scene's textures and the hit's lookup context: one function
// per model, with no per-hit copying of Params. It reuses the constants derived from the constant
// parameters at load (Fresnel averages) unless the fields they depend on, the IOR, are textured:
// then they are computed at every hit (one 32-point quadrature; three for a conductor's η, k).
// Materials without textures use Scene::material_bxdfs (no per-hit work).
#pragma once
#include <cstdint>

#include "pellucid/bxdf/bsdf.h"
#include "pellucid/geometry/interaction.h"
#include "pellucid/texture/texture.h"

namespace pellucid {

/// How a bump map turns heights into a shading normal (key `bump_model`).
///  - Footprint (default): the bumped surface F' = F + B·n with its B·∂n/∂u term, ∂B/∂u from the
///    texture's analytic gradient or a finite difference of its channel mean over one pixel
///    footprint (filtered lookups); frame s from ∂p/∂u.
///  - Mitsuba (Mitsuba 3's bumpmap): ∂B/∂u the exact derivative of the bilinear interpolation of the
///    full-resolution image's luminance (texture_luminance_gradient_uv); tangents projected onto
///    the plane of n before adding g·n, no B·∂n/∂u term; n' flipped to the side of ng; frame s the
///    unperturbed shading s Gram–Schmidt-ed against n'.
enum class BumpModel : uint8_t { Footprint, Mitsuba };
/// What is done to a perturbed normal that puts the viewer below its horizon (key `invalid_normals`).
///  - Bend (default): remove just enough of n's component along wo that wo sits slightly above it
///    (cos 0.02 before renormalising).
///  - Mirror (Mitsuba's flip_invalid_normals, after Schüssler et al. 2017): negate n's tangential
///    part in the unperturbed shading frame.
///  - Keep: leave it (such a viewer sees black).
enum class InvalidNormals : uint8_t { Bend, Mirror, Keep };

/// Everything textured about one material (fixed size: no heap, copied with the scene).
struct MaterialTextures {
    static constexpr int kMaxTextured = 16;
    uint32_t bound[kMaxTextured] = {};  ///< the textures bound to the material's Tex parameters
    int count = 0;
    int32_t bump = -1;        ///< height texture B (world units × bump_scale), or -1
    float bump_scale = 1.f;
    float bump_step_scale = 1.f;  ///< multiplies the footprint step Δu (for studies; 1 = one footprint)
    int32_t normal_map = -1;  ///< tangent-space normal map, or -1
    bool normal_map_directx = false;  ///< DirectX convention (green = −bitangent)
    BumpModel bump_model = BumpModel::Footprint;
    InvalidNormals invalid_normals = InvalidNormals::Bend;
    /// Soften the shadow terminator of perturbed normals; on by default, with Chiang et al. 2019's
    /// term unless terminator_model says Estevez (bxdf/bsdf.h).
    bool terminator_softening = true;
    TerminatorModel terminator_model = TerminatorModel::Chiang;
    /// Key `two_sided`: false makes a hit seen from the back of its shading normal
    /// (dot(wo, shading n) ≤ 0) scatter nothing (Scene::bsdf), as Mitsuba 3's one-sided BSDFs.
    bool two_sided = true;

    bool has_textured_params() const { return count > 0; }
    bool perturbs_normal() const { return bump >= 0 || normal_map >= 0; }
};

/// Whether a material with these textures reads its hits' pixel footprints: a bound or normal-map
/// texture that does (texture_reads_footprint), or a bump map whose steps or gradient do (the
/// footprint model always; Mitsuba's where its texture has no bilinear luminance gradient). Scenes
/// without such a material skip the footprints and ray differentials (Scene::needs_footprints).
bool material_reads_footprint(const MaterialTextures& mt, const TextureList& textures);

/// The texture lookup context of a hit: its position, uv and pixel footprint.
TextureEvalContext texture_eval_context(const SurfaceInteraction& si);

/// Shading frame with a bump map (by mt.bump_model, see the .cpp) or a tangent-space normal map
/// applied, and invalid normals treated by mt.invalid_normals. Returns the new shading frame.
Frame perturbed_shading_frame(const MaterialTextures& mt, const TextureList& textures, const TextureEvalContext& ctx,
                              const SurfaceInteraction& si);

/// The bump-mapped shading normal about the unbumped normal n (si supplies ∂p/∂u, ∂p/∂v, ∂n/∂u,
/// ∂n/∂v), from explicit steps Δu, Δv (exposed for the convergence tests).
Normal3f bump_normal(const TextureList& textures, uint32_t height, float scale, const TextureEvalContext& ctx,
                     const SurfaceInteraction& si, const Normal3f& n, float du, float dv, bool allow_analytic);

/// The bumped normal of BumpModel::Mitsuba about n (before any invalid-normal treatment): tangents
/// ∂p/∂u − n(n·∂p/∂u) + g_u·n (likewise v), g = scale·∇B in uv, n' = their normalised cross
/// product on the side of si.ng. `grad` is g/scale; exposed for the frame tests.
Normal3f bump_normal_mitsuba(const SurfaceInteraction& si, const Normal3f& n, float scale, const Vec2f& grad);

/// bump_normal_mitsuba over a lane type F (its float instantiation is that function's arithmetic):
/// the hit's ∂p/∂u, ∂p/∂v and geometric normal ng, the normal n, and the gradient (gu, gv) before
/// `scale`. Where the cross product has no finite, non-zero length, n itself.
template <class F>
inline V3<F> bump_normal_mitsuba_lanes(const V3<F>& dpdu, const V3<F>& dpdv, const V3<F>& ng, const V3<F>& n,
                                       const F& scale, const F& gu, const F& gv) {
    // Mitsuba 3's bumpmap: the tangents are first projected onto the plane of n (they need not be
    // tangent to it: a mesh's interpolated normal), then tilted by the scaled height gradient:
    //   ∂p'/∂u = ∂p/∂u − n(n·∂p/∂u) + g_u·n,   n' = normalize(∂p'/∂u × ∂p'/∂v).
    // There is no B·∂n/∂u term, so a constant height changes nothing.
    const V3<F> tu = dpdu + n * (scale * gu - dot(n, dpdu));
    const V3<F> tv = dpdv + n * (scale * gv - dot(n, dpdv));
    const V3<F> np = cross(tu, tv);
    const F len = length(np);
    const auto ok = (len > F(0.f)) && (len < F(kInfinity));
    const V3<F> unit = np / lane::select(ok, len, F(1.f));
    return lane::select(ok, lane::select(dot(unit, ng) < F(0.f), -unit, unit), n);  // the side of ng
}

/// InvalidNormals::Mirror over a lane type F: where the viewer wo is on different sides of n and of
/// the unperturbed shading frame's normal, n's tangential part in that frame negated.
template <class F>
inline V3<F> mirror_invalid_normal(const FrameT<F>& shading, const V3<F>& wo, const V3<F>& n) {
    // Schüssler et al. 2017 (§ "flipping" of invalid normals), as Mitsuba 3 does it: with n0 the
    // unperturbed normal, wo·n' = 2(wo·n0)(n·n0) − wo·n, which has the sign of wo·n0.
    const V3<F> nl = shading.to_local(n), wl = shading.to_local(wo);
    const V3<F> flipped = shading.to_world(V3<F>(lane::neg(nl.x), lane::neg(nl.y), nl.z));
    return lane::select(wl.z * dot(wl, nl) <= F(0.f), flipped, n);
}

/// The finite-difference steps bump mapping uses: half the pixel footprint in u and v
/// (½(|∂u/∂x| + |∂u/∂y|)), and 5e-4 (in uv units) where the hit has no footprint.
Vec2f bump_steps(const TextureEvalContext& ctx);
constexpr float kBumpFallbackStep = 5e-4f;
}  // namespace pellucid
