// Image files through OpenImageIO.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/image/image_io.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>

#include <unistd.h>

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

void check_image_output(const std::string& path) {
    namespace fs = std::filesystem;
    const std::string ext = extension(path);
    if (ext.empty()) throw Error(path + ": output has no extension (use .exr, .png, .hdr, .jpg, ...)");
    auto out = OIIO::ImageOutput::create(path);
    if (!out) throw Error(path + ": unsupported image format '" + ext + "' (use .exr, .png, .hdr, .jpg, ...)");
    fs::path parent = fs::path(path).parent_path();
    if (parent.empty()) parent = ".";
    std::error_code ec;
    if (!fs::exists(parent, ec)) {
        fs::create_directories(parent, ec);
        if (ec) throw Error(path + ": cannot create directory '" + parent.string() + "': " + ec.message());
    }
    if (!fs::is_directory(parent, ec)) throw Error(path + ": '" + parent.string() + "' is not a directory");
    if (::access(parent.c_str(), W_OK) != 0) throw Error(path + ": directory '" + parent.string() + "' is not writable");
    if (fs::is_directory(path, ec)) throw Error(path + ": is a directory");
}

void write_image_file(const std::string& path, const Image& img, const std::vector<ImageAttribute>& attributes) {
    if (img.width <= 0 || img.height <= 0) throw Error(path + ": cannot write an empty image");
    std::string ext = extension(path);
    check_image_output(path);
    auto out = OIIO::ImageOutput::create(path);
    if (!out) throw Error(path + ": unsupported image format '" + ext + "': " + OIIO::geterror());
    bool is_float = is_float_format(ext);
    OIIO::ImageSpec spec(img.width, img.height, img.channels, is_float ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
    for (const ImageAttribute& a : attributes) {
        if (const auto* i = std::get_if<int64_t>(&a.value)) {
            if (*i >= INT32_MIN && *i <= INT32_MAX) spec.attribute(a.name, int(*i));
            else spec.attribute(a.name, std::to_string(*i));
        } else if (const auto* d = std::get_if<double>(&a.value)) {
            spec.attribute(a.name, OIIO::TypeDesc::DOUBLE, d);
        } else {
            spec.attribute(a.name, std::get<std::string>(a.value));
        }
    }
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

std::vector<ImageAttribute> read_image_attributes(const std::string& path) {
    if (!std::filesystem::exists(path)) throw Error(path + ": image file not found");
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw Error(path + ": cannot read image (unsupported or corrupt): " + OIIO::geterror());
    std::vector<ImageAttribute> out;
    for (const OIIO::ParamValue& p : in->spec().extra_attribs) {
        const OIIO::TypeDesc t = p.type();
        if (t.aggregate != OIIO::TypeDesc::SCALAR || t.arraylen != 0) {
            out.push_back({p.name().string(), p.get_string()});
        } else if (t.basetype == OIIO::TypeDesc::FLOAT || t.basetype == OIIO::TypeDesc::DOUBLE ||
                   t.basetype == OIIO::TypeDesc::HALF) {
            out.push_back({p.name().string(), double(p.get_float())});
            if (t.basetype == OIIO::TypeDesc::DOUBLE) out.back().value = *static_cast<const double*>(p.data());
        } else if (t.basetype == OIIO::TypeDesc::STRING) {
            out.push_back({p.name().string(), p.get_string()});
        } else if (t.basetype == OIIO::TypeDesc::UINT64) {
            out.push_back({p.name().string(), int64_t(*static_cast<const uint64_t*>(p.data()))});
        } else if (t.basetype == OIIO::TypeDesc::INT64) {
            out.push_back({p.name().string(), *static_cast<const int64_t*>(p.data())});
        } else {
            out.push_back({p.name().string(), int64_t(p.get_int())});
        }
    }
    in->close();
    return out;
}
}  // namespace pellucid
