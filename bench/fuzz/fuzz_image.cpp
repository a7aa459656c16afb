// libFuzzer harness: the image-texture path. The first input byte picks the file extension (so
// OpenImageIO picks the reader) and the colour space; the rest is the file. The image goes through
// open_image_texture (size limit, texel scan, sRGB conversion into the texture cache) and filtered
// lookups. Every input gets a file name of its own: OpenImageIO's cache keys files by name.
// SPDX-License-Identifier: Apache-2.0
#include <OpenImageIO/imageio.h>

#include <filesystem>

#include "fuzz_common.h"
#include "pellucid/texture/texture_system.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const char* kExt[] = {".png", ".exr", ".hdr", ".jpg", ".tif", ".tga", ".bmp", ".pfm"};
    static uint64_t counter = 0;
    if (size < 1) return 0;
    // A file its extension's reader rejects is not offered to every other reader (about 30 of
    // them, some slow to start): the harness targets the reader the extension picks.
    static const bool once = OIIO::attribute("try_all_readers", 0);
    (void)once;
    const uint8_t sel = data[0];
    const std::string name = "img" + std::to_string(counter++) + kExt[sel & 7];
    const std::string path = fuzz::write_file(name, data + 1, size - 1);
    const pellucid::TextureColorSpace cs = (sel >> 3) % 3 == 0   ? pellucid::TextureColorSpace::Auto
                                           : (sel >> 3) % 3 == 1 ? pellucid::TextureColorSpace::SRGB
                                                                 : pellucid::TextureColorSpace::Linear;
    pellucid::ImageTextureInfo info;
    fuzz::expect_only_errors([&] {
        pellucid::ImageTextureHandle h = pellucid::open_image_texture(path, cs, &info);
        using F = pellucid::TextureFilter;
        for (F f : {F::Nearest, F::Bilinear, F::Trilinear, F::Anisotropic}) {
            pellucid::Spectrum v = pellucid::lookup_image_texture(h, f, pellucid::TextureWrap::Repeat, 0.3f, 0.7f,
                                                                  0.01f, 0.f, 0.f, 0.02f);
            for (int c = 0; c < 3; ++c)
                if (!std::isfinite(v[c])) {
                    std::fprintf(stderr, "non-finite texture lookup from an accepted image\n");
                    std::abort();
                }
        }
        pellucid::Spectrum ds, dt;
        pellucid::lookup_image_texture_gradient(h, pellucid::TextureWrap::Clamp, 0.5f, 0.5f, &ds, &dt);
    });
    std::error_code ec;
    std::filesystem::remove(path, ec);
    if (!info.resolved.empty() && info.resolved != path) std::filesystem::remove(info.resolved, ec);
    return 0;
}
