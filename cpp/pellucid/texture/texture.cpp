// Texture evaluation: image lookups, the box-filtered checkerboard, Perlin noise and fBm.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/texture/texture.h"

#include <array>
#include <cmath>

#include "pellucid/material/params.h"
#include "pellucid/math/constants.h"
#include "pellucid/sampling/rng.h"

namespace pellucid {

UVTransform UVTransform::from(const Transform& t) {
    const Mat4f& m = t.matrix();  // column-major: m[col][row]
    UVTransform u;
    u.a00 = m[0][0];
    u.a01 = m[1][0];
    u.b0 = m[3][0];
    u.a10 = m[0][1];
    u.a11 = m[1][1];
    u.b1 = m[3][1];
    return u;
}

namespace {
// ∫₀ˣ [frac(t) > ½] dt: the running integral of the 1D square wave that builds the checkerboard.
double square_wave_integral(double x) {
    double fl = std::floor(x);
    return 0.5 * fl + std::max(0.0, (x - fl) - 0.5);
}
// Fraction of [x0, x1] where frac(x) > ½ (the point value for an empty interval).
double wave_coverage(double x0, double x1) {
    if (x1 - x0 < 1e-7) {
        double c = 0.5 * (x0 + x1);
        return (c - std::floor(c)) > 0.5 ? 1.0 : 0.0;
    }
    return (square_wave_integral(x1) - square_wave_integral(x0)) / (x1 - x0);
}

// Perlin 2002: a fixed permutation of 0..255 (ours, shuffled by PCG32 with a fixed seed), doubled.
const std::array<uint8_t, 512>& permutation() {
    static const std::array<uint8_t, 512> perm = [] {
        std::array<uint8_t, 256> p{};
        for (int i = 0; i < 256; ++i) p[size_t(i)] = uint8_t(i);
        PCG32 rng(0x9e3779b97f4a7c15ull, 54u);
        for (int i = 255; i > 0; --i) std::swap(p[size_t(i)], p[size_t(rng.next_u32() % uint32_t(i + 1))]);
        std::array<uint8_t, 512> out{};
        for (int i = 0; i < 512; ++i) out[size_t(i)] = p[size_t(i & 255)];
        return out;
    }();
    return perm;
}
// The twelve cube-edge gradient directions of Perlin 2002 (§3), picked by the low hash bits.
Vec3f gradient_dir(int hash) {
    switch (hash & 15) {
        case 0: case 12: return {1, 1, 0};
        case 1: case 13: return {-1, 1, 0};
        case 2: return {1, -1, 0};
        case 3: return {-1, -1, 0};
        case 4: return {1, 0, 1};
        case 5: return {-1, 0, 1};
        case 6: return {1, 0, -1};
        case 7: return {-1, 0, -1};
        case 8: return {0, 1, 1};
        case 9: case 14: return {0, -1, 1};
        case 10: return {0, 1, -1};
        default: return {0, -1, -1};
    }
}
// Perlin 2002's quintic fade 6t⁵ − 15t⁴ + 10t³ and its derivative.
float fade(float t) { return t * t * t * (t * (t * 6.f - 15.f) + 10.f); }
float dfade(float t) { return 30.f * t * t * (t * (t - 2.f) + 1.f); }

// Footprint width of a solid texture in its own space.
float footprint(const Vec3f& dx, const Vec3f& dy) { return std::max(length(dx), length(dy)); }

float fbm(const Vec3f& q, float width, const NoiseTexture& t, Vec3f* grad) {
    // Octave i has frequency 2ⁱ; keep octaves whose period exceeds about two footprints (finer ones
    // average to zero over the pixel), the last one faded in by its fractional part.
    float n_oct = float(t.octaves);
    if (width > 0.f) n_oct = clamp(-1.f - std::log2(width), 0.f, float(t.octaves));
    int full = int(n_oct);
    float sum = 0.f, amp = 1.f, freq = 1.f;
    Vec3f g_sum(0.f), g;
    for (int i = 0; i <= full && i < t.octaves; ++i) {
        float w = i < full ? 1.f : n_oct - float(full);
        if (w <= 0.f) break;
        sum += w * amp * perlin_noise(q * freq, grad ? &g : nullptr);
        if (grad) g_sum += (w * amp * freq) * g;
        amp *= t.roughness;
        freq *= 2.f;
    }
    if (grad) *grad = g_sum;
    return sum;
}

float noise_value(const NoiseTexture& t, const TextureEvalContext& ctx, Vec3f* grad_q) {
    Vec3f q = t.to_local.point(ctx.p) * t.scale;
    if (!t.fbm) return perlin_noise(q, grad_q);
    float width = footprint(t.to_local.vector(ctx.dpdx), t.to_local.vector(ctx.dpdy)) * t.scale;
    return fbm(q, width, t, grad_q);
}
}  // namespace

float perlin_noise(const Vec3f& p, Vec3f* gradient) {
    const auto& perm = permutation();
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
        if (gradient) *gradient = Vec3f(0.f);
        return 0.f;
    }
    Vec3f fl(std::floor(p.x), std::floor(p.y), std::floor(p.z));
    Vec3f f = p - fl;
    // The lattice index modulo 256; beyond the int range (a large `scale` or far geometry) the
    // conversion to int would be undefined, so reduce it first (the period is 256).
    auto lattice = [](float x) {
        if (std::fabs(x) < 2147483648.f) return int(x) & 255;
        float m = std::fmod(x, 256.f);
        return int(m < 0.f ? m + 256.f : m) & 255;
    };
    int ix = lattice(fl.x), iy = lattice(fl.y), iz = lattice(fl.z);
    float w[3][2], dw[3][2];
    for (int a = 0; a < 3; ++a) {
        float s = fade(f[a]), ds = dfade(f[a]);
        w[a][0] = 1.f - s;
        w[a][1] = s;
        dw[a][0] = -ds;
        dw[a][1] = ds;
    }
    float n = 0.f;
    Vec3f grad(0.f);
    for (int c = 0; c < 8; ++c) {
        int bx = c & 1, by = (c >> 1) & 1, bz = (c >> 2) & 1;
        int h = perm[size_t(perm[size_t(perm[size_t(ix + bx)] + iy + by)] + iz + bz)];
        Vec3f g = gradient_dir(h);
        Vec3f d = f - Vec3f(float(bx), float(by), float(bz));
        float dotgd = dot(g, d);
        float wx = w[0][bx], wy = w[1][by], wz = w[2][bz];
        n += wx * wy * wz * dotgd;
        if (gradient)
            grad += Vec3f(dw[0][bx] * wy * wz, wx * dw[1][by] * wz, wx * wy * dw[2][bz]) * dotgd + (wx * wy * wz) * g;
    }
    if (gradient) *gradient = grad;
    return n;
}

float checkerboard_coverage(float u0, float u1, float v0, float v1) {
    double fx = wave_coverage(u0, u1), fy = wave_coverage(v0, v1);
    return float(fx * (1.0 - fy) + fy * (1.0 - fx));
}

Spectrum eval_texture(const TextureList& list, uint32_t id, const TextureEvalContext& ctx) {
    return std::visit([&](const auto& t) -> Spectrum {
        using T = std::decay_t<decltype(t)>;
        if constexpr (std::is_same_v<T, ConstantTexture>) {
            return t.value;
        } else if constexpr (std::is_same_v<T, ImageTexture>) {
            Vec2f st = t.to_uv.point(ctx.uv);
            Vec2f dx = t.to_uv.vector(ctx.dudx, ctx.dvdx), dy = t.to_uv.vector(ctx.dudy, ctx.dvdy);
            return lookup_image_texture(t.handle, t.filter, t.wrap, st.x, st.y, dx.x, dx.y, dy.x, dy.y);
        } else if constexpr (std::is_same_v<T, CheckerboardTexture>) {
            Vec2f st = t.to_uv.point(ctx.uv);
            float du = 0.f, dv = 0.f;
            if (t.filtered) {
                Vec2f dx = t.to_uv.vector(ctx.dudx, ctx.dvdx), dy = t.to_uv.vector(ctx.dudy, ctx.dvdy);
                du = std::max(std::fabs(dx.x), std::fabs(dy.x));
                dv = std::max(std::fabs(dx.y), std::fabs(dy.y));
            }
            float c1 = checkerboard_coverage(st.x - du, st.x + du, st.y - dv, st.y + dv);
            return t.color0 * (1.f - c1) + t.color1 * c1;
        } else if constexpr (std::is_same_v<T, NoiseTexture>) {
            float n = noise_value(t, ctx, nullptr);
            float a = clamp(0.5f + 0.5f * n, 0.f, 1.f);
            return t.color0 * (1.f - a) + t.color1 * a;
        } else if constexpr (std::is_same_v<T, ScaleTexture>) {
            return eval_texture(list, t.texture, ctx) * t.scale;
        } else {
            float a = eval_texture(list, t.amount, ctx).average();
            return eval_texture(list, t.texture0, ctx) * (1.f - a) + eval_texture(list, t.texture1, ctx) * a;
        }
    }, list[id]);
}

bool texture_gradient_uv(const TextureList& list, uint32_t id, const TextureEvalContext& ctx, const Vec3f& dpdu,
                         const Vec3f& dpdv, float* dfdu, float* dfdv, Spectrum* value) {
    return std::visit([&](const auto& t) -> bool {
        using T = std::decay_t<decltype(t)>;
        if constexpr (std::is_same_v<T, ConstantTexture>) {
            *dfdu = *dfdv = 0.f;
            if (value) *value = t.value;
            return true;
        } else if constexpr (std::is_same_v<T, NoiseTexture>) {
            Vec3f g;
            float n = noise_value(t, ctx, &g);  // the same n as without the gradient
            if (value) {
                float a = clamp(0.5f + 0.5f * n, 0.f, 1.f);  // as eval_texture
                *value = t.color0 * (1.f - a) + t.color1 * a;
            }
            float k = 0.5f * (t.color1 - t.color0).average();
            if (std::fabs(n) > 1.f) k = 0.f;  // the colour mapping clamps there: flat
            Vec3f qu = t.to_local.vector(dpdu) * t.scale, qv = t.to_local.vector(dpdv) * t.scale;
            *dfdu = k * dot(g, qu);
            *dfdv = k * dot(g, qv);
            return true;
        } else if constexpr (std::is_same_v<T, ScaleTexture>) {
            if (!texture_gradient_uv(list, t.texture, ctx, dpdu, dpdv, dfdu, dfdv, value)) return false;
            if (value) *value = *value * t.scale;
            float s = t.scale.average();
            *dfdu *= s;
            *dfdv *= s;
            return true;
        } else {
            return false;
        }
    }, list[id]);
}

namespace {
// Per-channel (u, v) gradients of the full-resolution bilinear interpolation (see
// texture_luminance_gradient_uv).
bool bilinear_gradient_uv(const TextureList& list, uint32_t id, const TextureEvalContext& ctx, Spectrum* du,
                          Spectrum* dv) {
    return std::visit([&](const auto& t) -> bool {
        using T = std::decay_t<decltype(t)>;
        if constexpr (std::is_same_v<T, ConstantTexture>) {
            *du = *dv = Spectrum(0.f);
            return true;
        } else if constexpr (std::is_same_v<T, ImageTexture>) {
            Vec2f st = t.to_uv.point(ctx.uv);
            Spectrum ds, dt;
            lookup_image_texture_gradient(t.handle, t.wrap, st.x, st.y, &ds, &dt);
            // Chain rule through st = A·uv + b: ∂f/∂u = a00·∂f/∂s + a10·∂f/∂t, ∂f/∂v = a01·∂f/∂s + a11·∂f/∂t.
            *du = ds * t.to_uv.a00 + dt * t.to_uv.a10;
            *dv = ds * t.to_uv.a01 + dt * t.to_uv.a11;
            return true;
        } else if constexpr (std::is_same_v<T, ScaleTexture>) {
            if (!bilinear_gradient_uv(list, t.texture, ctx, du, dv)) return false;
            *du = *du * t.scale;
            *dv = *dv * t.scale;
            return true;
        } else {
            return false;
        }
    }, list[id]);
}
}  // namespace

bool texture_reads_footprint(const TextureList& list, uint32_t id) {
    return std::visit([&](const auto& t) -> bool {
        using T = std::decay_t<decltype(t)>;
        if constexpr (std::is_same_v<T, ConstantTexture>) return false;
        else if constexpr (std::is_same_v<T, ImageTexture>)
            // Nearest and bilinear lookups of an image kept in memory read no MIP level; the
            // TextureSystem's lookups are taken as reading the footprint whatever the filter.
            return t.filter > TextureFilter::Bilinear || !t.handle.texels;
        else if constexpr (std::is_same_v<T, CheckerboardTexture>) return t.filtered;
        else if constexpr (std::is_same_v<T, NoiseTexture>) return t.fbm;  // the octaves finer than the footprint drop
        else if constexpr (std::is_same_v<T, ScaleTexture>) return texture_reads_footprint(list, t.texture);
        else
            return texture_reads_footprint(list, t.texture0) || texture_reads_footprint(list, t.texture1) ||
                   texture_reads_footprint(list, t.amount);
    }, list[id]);
}

bool texture_luminance_gradient_uv(const TextureList& list, uint32_t id, const TextureEvalContext& ctx, float* dfdu,
                                   float* dfdv) {
    Spectrum du, dv;
    if (!bilinear_gradient_uv(list, id, ctx, &du, &dv)) return false;
    *dfdu = du.luminance();
    *dfdv = dv.luminance();
    return true;
}

bool texture_has_luminance_gradient(const TextureList& list, uint32_t id) {
    // Whether bilinear_gradient_uv answers depends on the texture's type only, not on the context.
    float du, dv;
    return texture_luminance_gradient_uv(list, id, TextureEvalContext{}, &du, &dv);
}

std::string to_string(const Texture& tex) {
    return std::visit([](const auto& t) -> std::string {
        using T = std::decay_t<decltype(t)>;
        if constexpr (std::is_same_v<T, ConstantTexture>) return "ConstantTexture[" + format_spectrum(t.value) + "]";
        else if constexpr (std::is_same_v<T, ImageTexture>) return "ImageTexture[channels=" + std::to_string(t.handle.channels) + "]";
        else if constexpr (std::is_same_v<T, CheckerboardTexture>)
            return "CheckerboardTexture[color0=" + format_spectrum(t.color0) + ", color1=" + format_spectrum(t.color1) + "]";
        else if constexpr (std::is_same_v<T, NoiseTexture>)
            return std::string("NoiseTexture[variant=") + (t.fbm ? "fbm" : "perlin") + ", scale=" + format_float(t.scale) + "]";
        else if constexpr (std::is_same_v<T, ScaleTexture>) return "ScaleTexture[" + format_spectrum(t.scale) + "]";
        else return "MixTexture";
    }, tex);
}
}  // namespace pellucid
