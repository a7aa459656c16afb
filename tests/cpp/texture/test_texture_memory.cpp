// Image textures' in-memory full-resolution level (Nearest, Bilinear and the bilinear gradient in
// our own code) against OpenImageIO's TextureSystem, which reads the same handle when its texels
// pointer is null.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "pellucid/sampling/rng.h"
#include "pellucid/texture/texture_system.h"
#include "support/temp_dir.h"

using namespace pellucid;

namespace {

struct Case {
    const char* name;
    int width, height, channels, bits;
    TextureColorSpace cs;
};

// Odd, non-square and power-of-two sizes (OIIO wraps power-of-two sizes with a mask); 8-bit PNGs
// decoded from sRGB (read from the linear half-float copy), an 8-bit PNG read as linear, float EXRs;
// 1, 3 and 4 (alpha ignored) channels.
const Case kCases[] = {
    {"srgb_rgb.png", 7, 5, 3, 8, TextureColorSpace::Auto},   {"srgb_gray.png", 5, 9, 1, 8, TextureColorSpace::Auto},
    {"linear_rgb.png", 6, 3, 3, 8, TextureColorSpace::Linear}, {"float_rgb.exr", 11, 6, 3, 32, TextureColorSpace::Linear},
    {"float_gray.exr", 13, 4, 1, 32, TextureColorSpace::Linear}, {"float_rgba.exr", 8, 4, 4, 32, TextureColorSpace::Linear},
    {"one_texel.exr", 1, 1, 3, 32, TextureColorSpace::Linear},
};

const TextureWrap kWraps[] = {TextureWrap::Repeat, TextureWrap::Mirror, TextureWrap::Clamp, TextureWrap::Black};
const char* wrap_name(TextureWrap w) {
    return w == TextureWrap::Repeat ? "repeat" : w == TextureWrap::Mirror ? "mirror" : w == TextureWrap::Clamp ? "clamp" : "black";
}

/// Lookup points: fixed-seed random (s, t) in [−2.5, 3.5]², exact texel centres and texel edges
/// (inside, on and beyond the image's borders), and the image's corners.
std::vector<std::pair<float, float>> lookup_points(int w, int h) {
    std::vector<std::pair<float, float>> p;
    PCG32 rng(0x5eedull, 17);
    for (int k = 0; k < 2000; ++k) p.emplace_back(-2.5f + 6.f * rng.next_float(), -2.5f + 6.f * rng.next_float());
    for (int j = -2; j <= h + 1; ++j)
        for (int i = -2; i <= w + 1; ++i) {
            p.emplace_back((float(i) + 0.5f) / float(w), (float(j) + 0.5f) / float(h));  // centres
            p.emplace_back(float(i) / float(w), float(j) / float(h));                    // edges
            p.emplace_back(float(i) / float(w), (float(j) + 0.5f) / float(h));
        }
    for (float s : {0.f, 1.f, -1.f, 2.f})
        for (float t : {0.f, 1.f, -1.f, 2.f}) p.emplace_back(s, t);
    return p;
}

std::vector<float> test_pixels(int w, int h, int nc, uint64_t seed) {
    PCG32 rng(seed, 3);
    std::vector<float> px(size_t(w) * size_t(h) * size_t(nc));
    for (float& v : px) v = rng.next_float();
    return px;
}

float ulp_of(float range) { return range * std::numeric_limits<float>::epsilon(); }

}  // namespace

// Values: our lookups and OIIO's read the same texels (level 0 of the file, or of the linear
// half-float copy of an sRGB file) and interpolate with the same operations in the same order, so
// they agree to 2 float ulps of the texels' range (observed: bit-identical). Gradients are width (or
// height) × a blend of texel differences: 2 ulps of range × the resolution.
TEST(ImageTextureMemory, LookupsMatchTheTextureSystem) {
    const test::TempDir tmp("pellucid_texmem_");
    uint64_t seed = 1;
    for (const Case& c : kCases) {
        const std::string path = tmp.file(c.name);
        std::vector<float> px = test_pixels(c.width, c.height, c.channels, seed++);
        write_test_image(path, c.width, c.height, c.channels, c.bits, px.data());
        ImageTextureInfo info;
        const ImageTextureHandle mem = open_image_texture(path, c.cs, &info);
        ASSERT_NE(mem.texels, nullptr) << c.name;
        EXPECT_EQ(mem.width, c.width);
        EXPECT_EQ(mem.height, c.height);
        ImageTextureHandle oiio = mem;
        oiio.texels = nullptr;  // the TextureSystem's path
        float range = 0.f;
        for (int k = 0; k < 3; ++k) range = std::max({range, std::fabs(info.lo[k]), std::fabs(info.hi[k])});
        const float tol = 2.f * ulp_of(range);
        const float tol_grad = tol * float(std::max(c.width, c.height));
        const auto points = lookup_points(c.width, c.height);
        double worst = 0.0, worst_grad = 0.0;
        int mismatches = 0;
        for (TextureWrap wrap : kWraps) {
            for (const auto& [s, t] : points) {
                for (TextureFilter f : {TextureFilter::Nearest, TextureFilter::Bilinear}) {
                    const Spectrum a = lookup_image_texture(mem, f, wrap, s, t, 0.f, 0.f, 0.f, 0.f);
                    const Spectrum b = lookup_image_texture(oiio, f, wrap, s, t, 0.f, 0.f, 0.f, 0.f);
                    for (int k = 0; k < 3; ++k) {
                        const double d = std::fabs(double(a[k]) - double(b[k]));
                        worst = std::max(worst, d);
                        if (d > tol && ++mismatches <= 5)
                            ADD_FAILURE() << c.name << " " << wrap_name(wrap)
                                          << (f == TextureFilter::Nearest ? " nearest" : " bilinear") << " at (" << s
                                          << ", " << t << ") channel " << k << ": " << a[k] << " vs OIIO " << b[k];
                    }
                }
                Spectrum ads, adt, bds, bdt;
                const Spectrum a = lookup_image_texture_gradient(mem, wrap, s, t, &ads, &adt);
                const Spectrum b = lookup_image_texture_gradient(oiio, wrap, s, t, &bds, &bdt);
                for (int k = 0; k < 3; ++k) {
                    const double dv = std::fabs(double(a[k]) - double(b[k]));
                    const double dg = std::max(std::fabs(double(ads[k]) - double(bds[k])),
                                               std::fabs(double(adt[k]) - double(bdt[k])));
                    worst = std::max(worst, dv);
                    worst_grad = std::max(worst_grad, dg);
                    if ((dv > tol || dg > tol_grad) && ++mismatches <= 5)
                        ADD_FAILURE() << c.name << " " << wrap_name(wrap) << " gradient at (" << s << ", " << t
                                      << ") channel " << k << ": value " << a[k] << " vs " << b[k] << ", d/ds "
                                      << ads[k] << " vs " << bds[k] << ", d/dt " << adt[k] << " vs " << bdt[k];
                }
            }
        }
        EXPECT_EQ(mismatches, 0) << c.name;
        std::printf("%-16s largest difference: values %.3g, gradients %.3g (tolerances %.3g, %.3g)\n", c.name, worst,
                    worst_grad, double(tol), double(tol_grad));
    }
}

// The in-memory level is what the TextureSystem reads: a one-channel image replicates to RGB, a
// lookup at a texel centre returns that texel, and the gradient between two texels is
// width × their difference.
TEST(ImageTextureMemory, TexelCentresAndGradientAreExact) {
    const test::TempDir tmp("pellucid_texmem_");
    const std::string path = tmp.file("ramp.exr");
    const std::vector<float> px = {0.f, 0.25f, 1.f, 0.5f, 0.75f, 2.f};  // 3 x 2, one channel
    write_test_image(path, 3, 2, 1, 32, px.data());
    const ImageTextureHandle h = open_image_texture(path, TextureColorSpace::Linear, nullptr);
    ASSERT_NE(h.texels, nullptr);
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 3; ++i) {
            const Spectrum v = lookup_image_texture(h, TextureFilter::Bilinear, TextureWrap::Clamp, (i + 0.5f) / 3.f,
                                                    (j + 0.5f) / 2.f, 0, 0, 0, 0);
            EXPECT_EQ(v.r, px[size_t(j * 3 + i)]);
            EXPECT_EQ(v.g, v.r);
            EXPECT_EQ(v.b, v.r);
        }
    Spectrum ds, dt;
    // Halfway between texels (0,0) and (1,0) on the top row's centre line.
    const Spectrum v = lookup_image_texture_gradient(h, TextureWrap::Clamp, 1.f / 3.f, 0.25f, &ds, &dt);
    EXPECT_EQ(v.r, 0.125f);
    EXPECT_EQ(ds.r, 3.f * 0.25f);
    EXPECT_EQ(dt.r, 2.f * (0.5f * 0.5f + 0.5f * 0.5f));  // blend of (0.5 − 0) and (0.75 − 0.25)
}

// A file rewritten under the same name is read again, in memory too, once forgotten (until then a
// linear file's old texels stay, as the TextureSystem's tiles do: its cache keys files by name; an
// sRGB file's linear copy is keyed by the file's size and time as well).
TEST(ImageTextureMemory, ForgetRereadsTheInMemoryLevel) {
    const test::TempDir tmp("pellucid_texmem_");
    struct File {
        const char* name;
        int bits;
        TextureColorSpace cs;
    };
    for (const File& f : {File{"same.exr", 32, TextureColorSpace::Linear}, File{"same.png", 8, TextureColorSpace::Linear},
                          File{"same_srgb.png", 8, TextureColorSpace::SRGB}}) {
        const std::string path = tmp.file(f.name);
        const bool srgb = f.cs == TextureColorSpace::SRGB;
        auto write = [&](float v) {
            std::vector<float> px(5 * 3 * 3, v);
            px[0] = 1.f - v;  // not a constant image
            write_test_image(path, 5, 3, 3, f.bits, px.data());
        };
        auto read = [&] {
            const ImageTextureHandle h = open_image_texture(path, f.cs, nullptr);
            EXPECT_NE(h.texels, nullptr);
            return lookup_image_texture(h, TextureFilter::Nearest, TextureWrap::Repeat, 0.5f, 0.5f, 0, 0, 0, 0).r;
        };
        // 8-bit sRGB 0.2 and 0.8 decode to about 0.033 and 0.604.
        write(0.2f);
        const float first = read();
        EXPECT_NEAR(first, srgb ? 0.0331f : 0.2f, 3e-3f) << f.name;
        write(0.8f);
        if (!srgb) {
            EXPECT_EQ(read(), first) << f.name << ": the cache keys files by name until forgotten";
        }
        forget_image_texture(path);
        EXPECT_NEAR(read(), srgb ? 0.6038f : 0.8f, 3e-3f) << f.name;
        forget_image_texture(path);
    }
}

// An image above kInMemoryTextureTexels is not held in memory: every lookup goes through the
// TextureSystem (here a 4097 x 4096 one-channel PNG, one texel past the cap by a column).
TEST(ImageTextureMemory, LargeImagesStayOnTheTextureSystem) {
    const test::TempDir tmp("pellucid_texmem_");
    const std::string path = tmp.file("large.png");
    const int w = 4097, h = 4096;
    ASSERT_GT(int64_t(w) * h, kInMemoryTextureTexels);
    std::vector<float> px(size_t(w) * size_t(h), 0.f);
    px[size_t(7) * size_t(w) + 5] = 1.f;  // texel (5, 7)
    write_test_image(path, w, h, 1, 8, px.data());
    const ImageTextureHandle handle = open_image_texture(path, TextureColorSpace::Linear, nullptr);
    EXPECT_EQ(handle.texels, nullptr);
    const Spectrum v = lookup_image_texture(handle, TextureFilter::Nearest, TextureWrap::Clamp, 5.5f / float(w),
                                            7.5f / float(h), 0, 0, 0, 0);
    EXPECT_EQ(v.r, 1.f);
    forget_image_texture(path);
}
