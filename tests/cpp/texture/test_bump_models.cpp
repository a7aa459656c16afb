// Mitsuba's bump and normal map model (bump_model "mitsuba", invalid_normals, terminator_model
// "estevez"): the bilinear luminance gradient, the perturbed frame, the invalid-normal treatments
// and the Estevez shadowing term. All checks are deterministic; each states its tolerance and why.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "pellucid/bxdf/bsdf.h"
#include "pellucid/bxdf/lambertian.h"
#include "pellucid/material/textured.h"
#include "pellucid/sampling/rng.h"
#include "pellucid/texture/texture.h"
#include "support/surface_util.h"
#include "support/temp_dir.h"

namespace pellucid::test {
namespace {

float srgb_to_linear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }

// An image's texels (row 0 = the top row = t near 0) and the closed-form derivative of their
// bilinear interpolation (texel centres at (i + ½)/W), with periodic wrap, written independently
// of the texture system: Mitsuba 3's bitmap eval_1_grad defines the same quantity.
struct Texels {
    int w, h;
    std::vector<float> lum;  // luminance per texel
    float at(int x, int y) const { return lum[size_t(((y % h + h) % h) * w + ((x % w + w) % w))]; }
    Vec2f grad_st(float s, float t) const {
        float x = s * w - 0.5f, y = t * h - 0.5f;
        int i = int(std::floor(x)), j = int(std::floor(y));
        float fx = x - i, fy = y - j;
        float ds = (1.f - fy) * (at(i + 1, j) - at(i, j)) + fy * (at(i + 1, j + 1) - at(i, j + 1));
        float dt = (1.f - fx) * (at(i, j + 1) - at(i, j)) + fx * (at(i + 1, j + 1) - at(i + 1, j));
        return Vec2f(ds * w, dt * h);
    }
    // Distance of (s, t) to the nearest line through texel centres, in texels (the gradient jumps
    // across those lines, so finite differences are only exact away from them).
    float margin(float s, float t) const {
        float x = s * w - 0.5f, y = t * h - 0.5f;
        auto d = [](float v) { float f = v - std::floor(v); return std::min(f, 1.f - f); };
        return std::min(d(x), d(y));
    }
};

// A random W×H RGB image written as `bits` per channel; returns its texels as the texture
// system will hold them (8-bit files are sRGB-decoded).
Texels write_random_image(const std::string& path, int w, int h, int bits, uint64_t seed) {
    PCG32 rng(seed, 1);
    std::vector<float> px(size_t(w) * h * 3);
    for (float& v : px) v = bits == 8 ? std::round(rng.next_float() * 255.f) / 255.f : rng.next_float();
    write_test_image(path, w, h, 3, bits, px.data());
    Texels t{w, h, std::vector<float>(size_t(w) * h)};
    for (size_t i = 0; i < t.lum.size(); ++i) {
        Spectrum c(px[3 * i], px[3 * i + 1], px[3 * i + 2]);
        if (bits == 8) c = Spectrum(srgb_to_linear(c.r), srgb_to_linear(c.g), srgb_to_linear(c.b));
        t.lum[i] = c.luminance();
    }
    return t;
}

ImageTexture image_texture(const std::string& path, TextureColorSpace cs, const UVTransform& to_uv) {
    ImageTexture tex;
    tex.handle = open_image_texture(path, cs, nullptr);
    tex.filter = TextureFilter::Bilinear;
    tex.to_uv = to_uv;
    return tex;
}

UVTransform skewed_uv() {
    UVTransform a;
    a.a00 = 1.3f, a.a01 = 0.2f, a.a10 = -0.4f, a.a11 = 0.9f, a.b0 = 0.1f, a.b1 = 0.3f;
    return a;
}

// The gradient equals the closed form of the bilinear interpolation's derivative, chained through
// to_uv (∂/∂u = a00·∂/∂s + a10·∂/∂t), and central differences of the bilinear lookup itself. A
// float image keeps its values exactly; the closed form and the texture system then differ only by
// float rounding: 1e-3 relative to the gradient scale (max |texel difference|·W ≈ 6).
TEST(BilinearLuminanceGradient, MatchesClosedFormAndFiniteDifferences) {
    const TempDir tmp("pellucid_bumpgrad_");
    const UVTransform to_uv = skewed_uv();
    Texels tx = write_random_image(tmp.file("rand.exr"), 7, 5, 32, 11);
    TextureList list{image_texture(tmp.file("rand.exr"), TextureColorSpace::Linear, to_uv)};
    PCG32 rng(3, 1);
    int fd_checked = 0;
    for (int k = 0; k < 200; ++k) {
        SurfaceInteraction si = plane_hit(Vec2f(rng.next_float() * 2.f - 0.5f, rng.next_float() * 2.f - 0.5f));
        TextureEvalContext ctx = ctx_of(si);
        float gu, gv;
        ASSERT_TRUE(texture_luminance_gradient_uv(list, 0, ctx, &gu, &gv));
        Vec2f st = to_uv.point(si.uv);
        st.x -= std::floor(st.x);
        st.y -= std::floor(st.y);
        Vec2f g = tx.grad_st(st.x, st.y);
        float eu = to_uv.a00 * g.x + to_uv.a10 * g.y, ev = to_uv.a01 * g.x + to_uv.a11 * g.y;
        EXPECT_NEAR(gu, eu, 6e-3f) << "uv " << si.uv.x << ", " << si.uv.y;
        EXPECT_NEAR(gv, ev, 6e-3f) << "uv " << si.uv.x << ", " << si.uv.y;
        // Central differences with step h in u (and v): the lookup is a quadratic along such a
        // line inside one texel cell, so the central difference is exact there; only points whose
        // ±h steps stay in the cell are compared (a step moves at most h·1.5·7 ≈ 0.011 texels).
        // Rounding: 1e-7/h ≈ 1e-4, times the gradient scale.
        const float h = 1e-3f;
        if (tx.margin(st.x, st.y) < 0.03f) continue;
        auto lum_at = [&](float du, float dv) {
            TextureEvalContext c = ctx;
            c.uv += Vec2f(du, dv);
            return eval_texture(list, 0, c).luminance();
        };
        EXPECT_NEAR(gu, (lum_at(h, 0.f) - lum_at(-h, 0.f)) / (2.f * h), 2e-2f);
        EXPECT_NEAR(gv, (lum_at(0.f, h) - lum_at(0.f, -h)) / (2.f * h), 2e-2f);
        ++fd_checked;
    }
    EXPECT_GT(fd_checked, 50);
}

// 8-bit images are sRGB-decoded before differencing (Mitsuba decodes bitmaps at load unless raw),
// and a scale texture scales the gradient. The decoded copy is stored as half floats: relative
// error 2⁻¹¹ per texel, so 3e-3·W on the gradient.
TEST(BilinearLuminanceGradient, SrgbImagesAreDecodedFirstAndScaleTexturesScale) {
    const TempDir tmp("pellucid_bumpgrad_");
    Texels tx = write_random_image(tmp.file("rand.png"), 8, 8, 8, 5);
    TextureList list{image_texture(tmp.file("rand.png"), TextureColorSpace::SRGB, UVTransform{}),
                     ScaleTexture{0, Spectrum(2.f, 2.f, 2.f)}};
    PCG32 rng(9, 1);
    for (int k = 0; k < 100; ++k) {
        SurfaceInteraction si = plane_hit(Vec2f(rng.next_float(), rng.next_float()));
        float gu, gv, su, sv;
        ASSERT_TRUE(texture_luminance_gradient_uv(list, 0, ctx_of(si), &gu, &gv));
        ASSERT_TRUE(texture_luminance_gradient_uv(list, 1, ctx_of(si), &su, &sv));
        Vec2f g = tx.grad_st(si.uv.x, si.uv.y);
        EXPECT_NEAR(gu, g.x, 0.025f);
        EXPECT_NEAR(gv, g.y, 0.025f);
        EXPECT_FLOAT_EQ(su, 2.f * gu);
        EXPECT_FLOAT_EQ(sv, 2.f * gv);
    }
    // Textures without the bilinear gradient report so (bump mapping then falls back).
    TextureList noise{NoiseTexture{}};
    float gu, gv;
    EXPECT_FALSE(texture_luminance_gradient_uv(noise, 0, ctx_of(plane_hit()), &gu, &gv));
}

// The frame on a plane p = (2u, 3v, 0): ∂p'/∂u = (2, 0, k·g_u), ∂p'/∂v = (0, 3, k·g_v), so
// n' ∝ (−3k·g_u, −2k·g_v, 6). Tangents with a normal component (a mesh's interpolated normal)
// are projected first, so they give the same n'; a left-handed parameterisation is flipped to ng's
// side. Tolerance: float rounding.
TEST(MitsubaBump, FrameOnAPlane) {
    SurfaceInteraction si = plane_hit(Vec2f(0.3f, 0.4f));
    si.dpdu = Vec3f(2.f, 0.f, 0.f);
    si.dpdv = Vec3f(0.f, 3.f, 0.f);
    si.dndu = Vec3f(5.f, 0.f, 0.f);  // ignored by this model (no B·∂n/∂u term)
    const float k = 0.7f;
    const Vec2f g(0.9f, -1.6f);
    Vec3f expect = normalize(Vec3f(-3.f * k * g.x, -2.f * k * g.y, 6.f));
    auto near = [](const Vec3f& a, const Vec3f& b) { return length(a - b) < 1e-5f; };
    Normal3f n = bump_normal_mitsuba(si, si.shading.n, k, g);
    EXPECT_TRUE(near(n, expect)) << n.x << " " << n.y << " " << n.z;
    SurfaceInteraction tilted = si;
    tilted.dpdu = Vec3f(2.f, 0.f, 0.8f);
    tilted.dpdv = Vec3f(0.f, 3.f, -0.4f);
    EXPECT_TRUE(near(bump_normal_mitsuba(tilted, si.shading.n, k, g), expect));
    SurfaceInteraction flipped = si;
    flipped.dpdv = Vec3f(0.f, -3.f, 0.f);  // cross(∂p/∂u, ∂p/∂v) = −z: flipped back to ng = +z
    Vec3f nf = bump_normal_mitsuba(flipped, si.shading.n, k, g);
    EXPECT_GT(nf.z, 0.f);
    EXPECT_TRUE(near(nf, normalize(Vec3f(-3.f * k * g.x, 2.f * k * g.y, 6.f))));

    // Through perturbed_shading_frame with a ramp image (height = s along u): n' as above with
    // the image's gradient, s the unperturbed s Gram–Schmidt-ed against n' (orthonormal frame).
    const TempDir tmp("pellucid_bumpgrad_");
    float ramp[4 * 2];
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 4; ++x) ramp[y * 4 + x] = 0.25f * x;
    write_test_image(tmp.file("ramp.exr"), 4, 2, 1, 32, ramp);
    TextureList list{image_texture(tmp.file("ramp.exr"), TextureColorSpace::Linear, UVTransform{})};
    MaterialTextures mt;
    mt.bump = 0;
    mt.bump_scale = k;
    mt.bump_model = BumpModel::Mitsuba;
    si.uv = Vec2f(0.5f, 0.5f);  // inside the ramp: ∂h/∂s = 0.25·4 = 1, ∂h/∂t = 0
    Frame f = perturbed_shading_frame(mt, list, ctx_of(si), si);
    EXPECT_TRUE(near(f.n, normalize(Vec3f(-3.f * k, 0.f, 6.f)))) << f.n.x << " " << f.n.y << " " << f.n.z;
    EXPECT_NEAR(dot(f.s, f.n), 0.f, 1e-6f);
    EXPECT_NEAR(length(f.s), 1.f, 1e-6f);
    EXPECT_NEAR(f.s.y, 0.f, 1e-6f);  // in the plane of the unperturbed s = x and n'
    EXPECT_GT(f.s.x, 0.f);
    // The footprint model on the same hit differs (its B·∂n/∂u term): the option is live.
    mt.bump_model = BumpModel::Footprint;
    Frame ff = perturbed_shading_frame(mt, list, ctx_of(si), si);
    EXPECT_GT(length(ff.n - f.n), 1e-2f);
}

// The three treatments of a normal that puts the viewer below its horizon: a normal map tilted
// 60° toward +x seen from the −x side at 50° from the normal.
TEST(InvalidNormals, BendMirrorKeep) {
    Vec3f nt(std::sin(1.0472f), 0.f, std::cos(1.0472f));
    TextureList list{ConstantTexture{Spectrum(0.5f + 0.5f * nt.x, 0.5f + 0.5f * nt.y, 0.5f + 0.5f * nt.z)}};
    SurfaceInteraction si = plane_hit(Vec2f(0.2f, 0.2f));
    si.wo = Vec3f(-std::sin(0.8727f), 0.f, std::cos(0.8727f));
    ASSERT_LT(dot(si.wo, normalize(nt)), 0.f);
    MaterialTextures mt;
    mt.normal_map = 0;
    mt.invalid_normals = InvalidNormals::Keep;
    Frame keep = perturbed_shading_frame(mt, list, ctx_of(si), si);
    EXPECT_LT(length(keep.n - nt), 1e-5f);
    mt.invalid_normals = InvalidNormals::Mirror;
    Frame mirror = perturbed_shading_frame(mt, list, ctx_of(si), si);
    EXPECT_LT(length(mirror.n - Vec3f(-nt.x, -nt.y, nt.z)), 1e-5f);
    EXPECT_GT(dot(si.wo, mirror.n), 0.f);
    mt.invalid_normals = InvalidNormals::Bend;
    Frame bend = perturbed_shading_frame(mt, list, ctx_of(si), si);
    // 0.02 before renormalising the bent normal, a little more after.
    EXPECT_GE(dot(si.wo, bend.n), 0.02f);
    EXPECT_LT(dot(si.wo, bend.n), 0.03f);
    // A valid normal is left alone by all three.
    si.wo = Vec3f(0.f, 0.f, 1.f);
    for (InvalidNormals m : {InvalidNormals::Keep, InvalidNormals::Mirror, InvalidNormals::Bend}) {
        mt.invalid_normals = m;
        EXPECT_LT(length(perturbed_shading_frame(mt, list, ctx_of(si), si).n - nt), 1e-5f);
    }
}

// The Estevez term: eval with softening over eval without is 2/(1 + √(1 + α²·tan²θ_l)),
// α² = min(tan²θ_d/8, 1), θ_l the light's angle to n0 and θ_d the tilt; it depends on the light
// direction only (wi under radiance transport, wo under importance) and is 1 on an untilted frame.
// Tolerance: float rounding.
TEST(EstevezTerminator, MatchesClosedFormOnTheLightDirection) {
    const Normal3f n0(0.f, 0.f, 1.f);
    BxDF lambert = Lambertian(Spectrum(0.5f));
    for (float tilt_deg : {0.f, 20.f, 60.f, 80.f}) {
        float td = tilt_deg * kPi / 180.f;
        Frame f = Frame::from_xz(Vec3f(1, 0, 0), Vec3f(std::sin(td), 0.f, std::cos(td)));
        BSDF plain(lambert, f, n0), soft(lambert, f, n0);
        soft.soften_terminator(n0, TerminatorModel::Estevez);
        float tan_d = std::tan(td), alpha2 = std::min(0.125f * tan_d * tan_d, 1.f);
        for (float light_deg : {5.f, 40.f, 75.f, 88.f})
            for (float view_deg : {10.f, 50.f}) {
                float tl = light_deg * kPi / 180.f, tv = view_deg * kPi / 180.f;
                Vec3f light(std::sin(tl) * 0.6f, std::sin(tl) * 0.8f, std::cos(tl));
                Vec3f view(-std::sin(tv), 0.f, std::cos(tv));
                float tan_l = std::tan(tl);
                float expect = 2.f / (1.f + std::sqrt(1.f + alpha2 * tan_l * tan_l));
                Spectrum a = plain.eval(view, light), b = soft.eval(view, light);
                if (a.r > 0.f) {
                    EXPECT_NEAR(b.r / a.r, expect, 1e-5f) << tilt_deg << " " << light_deg;
                }
                // Importance transport: the light is wo.
                Spectrum ai = plain.eval(light, view, TransportMode::Importance),
                         bi = soft.eval(light, view, TransportMode::Importance);
                if (ai.r > 0.f) {
                    EXPECT_NEAR(bi.r / ai.r, expect, 1e-5f) << tilt_deg << " " << light_deg;
                }
            }
    }
}
// Where the perturbed normal equals n0, dot(n0, n0)² can round above 1, so that 1 − cos²θ_d is a
// tiny negative number; with light grazing n0, α²·tan²θ_l then fell below −1 and the square root
// gave NaN (a textured_bump render dropped about one sample in a million as NaN). The factor must be
// finite and in [0, 1] for such normals, and at every light angle down to the tangent plane (the
// float instantiation of the template that the packet kernel instantiates on its packets).
TEST(EstevezTerminator, FiniteWhereTheNormalIsUnperturbedAndTheLightGrazes) {
    PCG32 rng(3, 7);
    int rounding_above_one = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        const Vec3f n0 = normalize(Vec3f(rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f));
        const float c_n = dot(n0, n0);
        rounding_above_one += c_n * c_n > 1.f;
        // A light direction at angle 90° − ε to n0, ε from 0.1 down to 1e-30 and exactly 0.
        const Frame f = Frame::from_z(n0);
        for (float eps : {1e-1f, 1e-3f, 1e-5f, 1e-7f, 1e-12f, 1e-20f, 1e-30f, 0.f}) {
            const Vec3f light_w = normalize(f.s + n0 * eps);
            const Vec3f light = f.to_local(light_w), other(0.f, 0.f, 1.f);
            const float g = terminator_factor<float>(true, other, light, light_w, n0, n0);
            ASSERT_TRUE(std::isfinite(g) && g >= 0.f && g <= 1.f) << "trial " << trial << " eps " << eps << ": " << g;
        }
    }
    EXPECT_GT(rounding_above_one, 100);  // the case the test is about does occur
}
}  // namespace
}  // namespace pellucid::test
