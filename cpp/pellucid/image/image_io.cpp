// Image files through OpenImageIO.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/image/image_io.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>

#include "pellucid/util/error.h"
#include "pellucid/util/limits.h"

namespace pellucid {
namespace {
std::string extension(const std::string& path) {
    std::string e = std::filesystem::path(path).extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return e;
}
bool is_float_format(const std::string& ext) { return ext == ".exr" || ext == ".hdr" || ext == ".pfm"; }

// sRGB transfer function (IEC 61966-2-1).
float linear_to_srgb(float v) {
    if (!(v > 0.f)) return 0.f;
    if (v >= 1.f) return 1.f;
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.f / 2.4f) - 0.055f;
}
}  // namespace

void write_image_file(const std::string& path, const Image& img) {
    if (img.width <= 0 || img.height <= 0) throw Error(path + ": cannot write an empty image");
    std::string ext = extension(path);
    auto parent = std::filesystem::path(path).parent_path();
    if (!parent.empty() && !std::filesystem::exists(parent))
        throw Error(path + ": directory '" + parent.string() + "' does not exist");
    auto out = OIIO::ImageOutput::create(path);
    if (!out) throw Error(path + ": unsupported image format '" + ext + "': " + OIIO::geterror());
    bool is_float = is_float_format(ext);
    OIIO::ImageSpec spec(img.width, img.height, img.channels, is_float ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
    if (!out->open(path, spec)) throw Error(path + ": cannot open for writing: " + out->geterror());
    bool ok;
    if (is_float) {
        ok = out->write_image(OIIO::TypeDesc::FLOAT, img.data.data());
    } else {
        std::vector<unsigned char> px(img.data.size());
        for (size_t i = 0; i < px.size(); ++i)
            px[i] = (unsigned char)std::lround(255.f * linear_to_srgb(img.data[i]));
        ok = out->write_image(OIIO::TypeDesc::UINT8, px.data());
    }
    if (!ok) throw Error(path + ": write failed: " + out->geterror());
    out->close();
}

Image read_image_file(const std::string& path) {
    if (!std::filesystem::exists(path)) throw Error(path + ": image file not found");
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw Error(path + ": cannot read image (unsupported or corrupt): " + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    int w = spec.width, h = spec.height, c = spec.nchannels;
    if (w <= 0 || h <= 0 || c <= 0) throw Error(path + ": image has no pixels");
    if (std::string e = texture_size_error(w, h); !e.empty()) throw Error(path + ": " + e);  // before decoding
    std::vector<float> raw(size_t(w) * h * c);
    if (!in->read_image(0, 0, 0, c, OIIO::TypeDesc::FLOAT, raw.data()))
        throw Error(path + ": cannot decode image: " + in->geterror());
    // 8/16-bit integer files are display-encoded unless they say otherwise.
    std::string cs = spec.get_string_attribute("oiio:ColorSpace", "");
    bool srgb = spec.format.is_floating_point() ? false : (cs.empty() || cs == "sRGB");
    in->close();
    Image img(w, h, 3);
    for (size_t p = 0; p < size_t(w) * h; ++p)
        for (int k = 0; k < 3; ++k) {
            float v = raw[p * c + std::min(k, c == 2 ? 0 : c - 1)];
            if (c >= 3) v = raw[p * c + k];
            if (srgb) v = v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
            img.data[p * 3 + k] = v;
        }
    return img;
}
}  // namespace pellucid
