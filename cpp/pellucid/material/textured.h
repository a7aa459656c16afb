// Textured material parameters, bump maps and normal maps: what a material adds to its constant
// parameters when some of them vary over the surface.
// SPDX-License-Identifier: Apache-2.0
//
// Design: a material keeps its `*Params` struct of constants (the values used where no texture is
// bound) and, per textured parameter, a TextureBinding: which texture, which field of the Params
// struct (a byte offset), and how to map the texture value into it (identity, r → α = r², clamp).
// At a hit, get_textured_bxdf() copies the Params, writes the evaluated textures into the bound
// fields and builds the BxDF from the copy, through the same constructor the builder used: one
// generic path for every material, and materials without textures keep their prebuilt BxDF (no
// per-hit work). A material's Params must be standard layout for the offsets to be meaningful
// (checked by static_assert next to each binding site in builders.cpp).
#pragma once
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "pellucid/geometry/interaction.h"
#include "pellucid/material/material.h"
#include "pellucid/texture/texture.h"

namespace pellucid {

struct TextureBinding {
    enum class Kind : uint8_t { Spectrum, Float };
    enum class Op : uint8_t { Identity, Square };  ///< Square: perceptual roughness r → α = r²
    uint32_t texture = 0;
    uint16_t offset = 0;  ///< byte offset of the target field in the material's Params struct
    Kind kind = Kind::Spectrum;
    Op op = Op::Identity;
    float lo = 0.f, hi = 1.f;  ///< the parameter's valid range; texture values are clamped into it
};

/// Everything textured about one material (fixed size: no heap, copied with the scene).
struct MaterialTextures {
    static constexpr int kMaxBindings = 16;
    TextureBinding bindings[kMaxBindings];
    int count = 0;
    int32_t bump = -1;        ///< height texture B (world units × bump_scale), or -1
    float bump_scale = 1.f;
    float bump_step_scale = 1.f;  ///< multiplies the footprint step Δu (for studies; 1 = one footprint)
    int32_t normal_map = -1;  ///< tangent-space normal map, or -1
    bool normal_map_directx = false;  ///< DirectX convention (green = −bitangent)
    /// Soften the shadow terminator of perturbed normals (Chiang et al. 2019); on by default.
    bool terminator_softening = true;

    bool has_bindings() const { return count > 0; }
    bool perturbs_normal() const { return bump >= 0 || normal_map >= 0; }
};

/// The BxDF of material `m` at a hit whose parameters come from `mt`'s textures.
BxDF get_textured_bxdf(const Material& m, const MaterialTextures& mt, const TextureList& textures,
                       const TextureEvalContext& ctx, const SurfaceInteraction& si);

/// Shading frame with a bump map (F' = F + B·n, finite differences over one pixel footprint, see
/// the .cpp) or a tangent-space normal map applied. Returns the new shading frame.
Frame perturbed_shading_frame(const MaterialTextures& mt, const TextureList& textures, const TextureEvalContext& ctx,
                              const SurfaceInteraction& si);

/// The bump-mapped shading normal about the unbumped normal n (si supplies ∂p/∂u, ∂p/∂v, ∂n/∂u,
/// ∂n/∂v), from explicit steps Δu, Δv (exposed for the convergence tests).
Normal3f bump_normal(const TextureList& textures, uint32_t height, float scale, const TextureEvalContext& ctx,
                     const SurfaceInteraction& si, const Normal3f& n, float du, float dv, bool allow_analytic);

/// The finite-difference steps bump mapping uses: half the pixel footprint in u and v
/// (½(|∂u/∂x| + |∂u/∂y|)), and 5e-4 (in uv units) where the hit has no footprint.
Vec2f bump_steps(const TextureEvalContext& ctx);
constexpr float kBumpFallbackStep = 5e-4f;
}  // namespace pellucid
