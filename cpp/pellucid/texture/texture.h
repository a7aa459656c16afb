// Textures: the closed list of texture types and their evaluation at a hit with its footprint.
// SPDX-License-Identifier: Apache-2.0
//
// Every texture returns an RGB Spectrum; a float parameter reads the channel average (a grey image
// gives its value). Textures that combine others (scale, mix) refer to them by index into the
// scene's texture list, which the builder fills children-first, so evaluation never loops.
//
// | type         | parameters (JSON)                                                              |
// |--------------|--------------------------------------------------------------------------------|
// | image        | filename, filter (anisotropic*, trilinear, bilinear, nearest), wrap_mode        |
// |              | (repeat*, mirror, clamp, black), color_space (auto*, srgb, linear), to_uv      |
// | checkerboard | color0 (0.4), color1 (0.2), to_uv, filtered (true)                              |
// | noise        | variant (perlin*, fbm), scale (1, frequency in 1/world units), octaves (6),    |
// |              | roughness (0.5, fbm gain), color0 (0), color1 (1), to_world                     |
// | scale        | texture, scale (1)                                                              |
// | mix          | texture0, texture1, amount (0.5)                                                |
// Full tables: docs/scene-format.md § Textures.
#pragma once
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include "pellucid/math/lane_types.h"
#include "pellucid/math/spectrum.h"
#include "pellucid/math/transform.h"
#include "pellucid/math/vec.h"
#include "pellucid/texture/texture_system.h"

namespace pellucid {

/// What a texture sees of a hit: position, uv, and the footprint of one pixel as screen-space
/// derivatives (zero when unknown: then lookups are point samples at the finest level).
struct TextureEvalContext {
    Point3f p{0.f};
    Vec3f dpdx{0.f}, dpdy{0.f};
    Vec2f uv{0.f};
    float dudx = 0.f, dudy = 0.f, dvdx = 0.f, dvdy = 0.f;
};

/// 2D affine map of texture coordinates: uv' = A·uv + b (Mitsuba's `to_uv`).
struct UVTransform {
    float a00 = 1.f, a01 = 0.f, a10 = 0.f, a11 = 1.f, b0 = 0.f, b1 = 0.f;
    Vec2f point(const Vec2f& uv) const { return Vec2f(a00 * uv.x + a01 * uv.y + b0, a10 * uv.x + a11 * uv.y + b1); }
    Vec2f vector(float du, float dv) const { return Vec2f(a00 * du + a01 * dv, a10 * du + a11 * dv); }
    /// The xy part of a 3D transform (a scene's `to_uv` is written with the usual transform ops).
    static UVTransform from(const Transform& t);
};

struct ConstantTexture {
    Spectrum value{0.f};
};

struct ImageTexture {
    ImageTextureHandle handle;
    TextureFilter filter = TextureFilter::Anisotropic;
    TextureWrap wrap = TextureWrap::Repeat;
    UVTransform to_uv;
};

/// Two-colour checkerboard with unit-square cells of size ½ in uv (Mitsuba's pattern: color0 where
/// frac(u) > ½ and frac(v) > ½ agree). `filtered` box-filters it over the footprint in closed form.
struct CheckerboardTexture {
    Spectrum color0{0.4f}, color1{0.2f};
    UVTransform to_uv;
    bool filtered = true;
};

/// Which colour the point-sampled checkerboard (filtered false) shows at (u, v), over a lane type F:
/// 1 for color1, 0 for color0, NaN where st = to_uv(u, v) is not finite (to_uv's entries in a as
/// (a00, a01, b0, a10, a11, b1)). color1 shows where exactly one of frac(s), frac(t) exceeds ½.
/// These are eval_texture's operations: st as UVTransform::point computes it, and the fraction
/// x − ⌊x⌋ of a float is exact in float as in the double wave_coverage takes; eval_texture's
/// coverage is then 0 or 1 and its value color0 or color1 exactly (and NaN where st is not finite).
/// The packet path tracer shades a Lambertian with such a reflectance as its packet form with the
/// parameters of that colour (PathSetup::tex_lanes).
template <class F>
inline F checkerboard_square(const F* a, const F& u, const F& v) {
    const F s = (a[0] * u + a[1] * v) + a[2], t = (a[3] * u + a[4] * v) + a[5];
    const F fs = s - lane::floor(s), ft = t - lane::floor(t);  // NaN where s or t is not finite
    const MaskT<F> os = fs > F(0.5f), ot = ft > F(0.5f);
    const F pick = lane::select((os && !ot) || (!os && ot), F(1.f), F(0.f));
    return lane::select(fs == fs && ft == ft, pick, fs + ft);
}

/// Solid Perlin noise (Perlin 2002, "Improving Noise") on the point to_world⁻¹(p)·scale, or fBm:
/// Σ roughnessⁱ·noise(2ⁱ·x) over `octaves`, the octaves finer than the footprint dropped (they
/// average to zero), as in Musgrave's fBm. Mapped to colour by lerp(color0, color1, ½ + ½·n).
struct NoiseTexture {
    bool fbm = false;
    float scale = 1.f, roughness = 0.5f;
    int octaves = 6;
    Spectrum color0{0.f}, color1{1.f};
    Transform to_local;  ///< world → texture space
};

struct ScaleTexture {
    uint32_t texture = 0;
    Spectrum scale{1.f};
};

struct MixTexture {
    uint32_t texture0 = 0, texture1 = 0, amount = 0;  ///< amount: its channel average is the weight of texture1
};

using Texture = std::variant<ConstantTexture, ImageTexture, CheckerboardTexture, NoiseTexture, ScaleTexture, MixTexture>;
using TextureList = std::vector<Texture>;

/// Evaluate texture `id` of `list` (filtered over the context's footprint).
Spectrum eval_texture(const TextureList& list, uint32_t id, const TextureEvalContext& ctx);

/// Analytic gradient of the texture's channel average with respect to (u, v), where the texture
/// provides one (noise: ∇n·∂p/∂u; constant: 0; scale of such a texture). Returns false otherwise;
/// bump mapping then takes finite differences.
/// `value`, when given, receives eval_texture(list, id, ctx) (bit-identical) from the same
/// evaluation, so that bump mapping evaluates a noise once, not twice.
bool texture_gradient_uv(const TextureList& list, uint32_t id, const TextureEvalContext& ctx, const Vec3f& dpdu,
                         const Vec3f& dpdv, float* dfdu, float* dfdv, Spectrum* value = nullptr);

/// Mitsuba's bump-map gradient (bump_model "mitsuba", Mitsuba 3's bitmap `eval_1_grad`): the exact
/// (u, v) derivative of the bilinear interpolation of the full-resolution image's luminance
/// (Rec. 709 weights), whatever the texture's filter and with no footprint, through `to_uv`. Also
/// for constant textures (0) and scale textures of such textures. Returns false for other textures
/// (bump mapping then uses texture_gradient_uv or finite differences).
bool texture_luminance_gradient_uv(const TextureList& list, uint32_t id, const TextureEvalContext& ctx, float* dfdu,
                                   float* dfdv);

/// Whether texture `id`'s value depends on the context's footprint (dpdx, dpdy, du/dx …): image
/// textures filtered beyond bilinear (trilinear, anisotropic) or looked up through the
/// TextureSystem (too large to keep in memory), filtered checkerboards, fBm noise, and scale and mix
/// textures of such. The others (constant, nearest or bilinear images in memory, point-sampled
/// checkerboards, plain Perlin noise) give the same bits with or without one, and so do
/// texture_luminance_gradient_uv's gradients.
bool texture_reads_footprint(const TextureList& list, uint32_t id);
/// Whether texture_luminance_gradient_uv has a gradient for texture `id` (whatever the context).
bool texture_has_luminance_gradient(const TextureList& list, uint32_t id);

/// Perlin's improved noise in [-1, 1] (roughly) and its gradient.
float perlin_noise(const Vec3f& p, Vec3f* gradient = nullptr);

/// Box-filtered checkerboard mask: the fraction of [u0,u1]×[v0,v1] where the pattern is color1.
float checkerboard_coverage(float u0, float u1, float v0, float v1);

std::string to_string(const Texture& t);
}  // namespace pellucid
