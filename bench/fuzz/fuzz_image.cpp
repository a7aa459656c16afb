// libFuzzer harness: the image-texture path. The first input byte picks the file extension (so
// OpenImageIO picks the reader) and the colour space; the rest is the file. The image goes through
// open_image_texture (size limit, texel scan, sRGB conversion into the texture cache) and filtered
// lookups. OpenImageIO's cache keys files by name: every input gets a file name of its own (reusing
// one name with forget_image_texture in between made OpenEXR corrupt its heap under ASan on
// malformed inputs), and the cache forgets the file and its converted copy once the input is done,
// so its tiles and headers do not pile up over millions of inputs.
// SPDX-License-Identifier: Apache-2.0
#include <OpenImageIO/imageio.h>

#include <filesystem>

#include "fuzz_common.h"
#include "pellucid/texture/texture_system.h"

namespace {
/// An OpenEXR header with an attribute whose declared size exceeds the bytes left in the file.
/// OpenEXR allocates and clears the declared size before reading it (a 1.4 KB file makes it take
/// 1.8 GB and 6 s, inside ImageInput::open, before pellucid sees the header): a known behaviour of
/// the library (bench/fuzz/README.md), which would otherwise take most of the harness's time.
/// Only the first header is walked; anything unusual ends the walk with "no".
bool exr_attribute_past_end(const uint8_t* p, size_t n) {
    if (n < 8 || p[0] != 0x76 || p[1] != 0x2f || p[2] != 0x31 || p[3] != 0x01) return false;
    size_t i = 8;
    for (int attr = 0; attr < 1000 && i < n && p[i] != 0; ++attr) {
        for (int field = 0; field < 2; ++field) {  // name, then type: NUL-terminated strings
            while (i < n && p[i] != 0) ++i;
            if (++i > n) return false;
        }
        if (i + 4 > n) return false;
        const uint32_t len = uint32_t(p[i]) | uint32_t(p[i + 1]) << 8 | uint32_t(p[i + 2]) << 16 | uint32_t(p[i + 3]) << 24;
        i += 4;
        if (len > n - i) return true;
        i += len;
    }
    return false;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const char* kExt[] = {".png", ".exr", ".hdr", ".jpg", ".tif", ".tga", ".bmp", ".pfm"};
    if (size < 1) return 0;
    // A file its extension's reader rejects is not offered to every other reader (about 30 of
    // them, some slow to start): the harness targets the reader the extension picks.
    static const bool once = OIIO::attribute("try_all_readers", 0);
    (void)once;
    const uint8_t sel = data[0];
    if (exr_attribute_past_end(data + 1, size - 1)) return -1;  // not kept in the corpus
    static uint64_t counter = 0;
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
    pellucid::forget_image_texture(path);
    std::filesystem::remove(path, ec);
    if (!info.resolved.empty() && info.resolved != path) {
        pellucid::forget_image_texture(info.resolved);
        std::filesystem::remove(info.resolved, ec);
    }
    return 0;
}
