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

namespace {
/// Header attributes into `spec` (integers that fit 32 bits as int, larger ones as strings).
void add_attributes(OIIO::ImageSpec& spec, const std::vector<ImageAttribute>& attributes) {
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
}

/// The alpha channel of an 8-bit image of c channels (grey + alpha, RGBA), or -1.
int alpha_of(int c) { return c == 4 ? 3 : c == 2 ? 1 : -1; }
}  // namespace

void write_image_file(const std::string& path, const Image& img, const std::vector<ImageAttribute>& attributes) {
    if (img.width <= 0 || img.height <= 0) throw Error(path + ": cannot write an empty image");
    if (img.channels < 1) throw Error(path + ": cannot write an image with no channels");
    std::string ext = extension(path);
    check_image_output(path);
    auto out = OIIO::ImageOutput::create(path);
    if (!out) throw Error(path + ": unsupported image format '" + ext + "': " + OIIO::geterror());
    if (img.channels > 4 && !out->supports("nchannels"))
        throw Error(path + ": the " + ext + " format holds 1 to 4 channels, the image has " +
                    std::to_string(img.channels) + " (write .exr for more)");
    bool is_float = is_float_format(ext);
    OIIO::ImageSpec spec(img.width, img.height, img.channels, is_float ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
    if (img.channels == 1) spec.channelnames = {"Y"};
    if (img.channels == 2) spec.channelnames = {"Y", "A"};
    spec.alpha_channel = alpha_of(img.channels);
    // Channel values are written as given: no (un)premultiplication by alpha.
    if (spec.alpha_channel >= 0) spec.attribute("oiio:UnassociatedAlpha", 1);
    add_attributes(spec, attributes);
    if (!out->open(path, spec)) throw Error(path + ": cannot open for writing: " + out->geterror());
    bool ok;
    if (is_float) {
        ok = out->write_image(OIIO::TypeDesc::FLOAT, img.data.data());
    } else {
        std::vector<unsigned char> px(img.data.size());
        const int alpha = alpha_of(img.channels);
        for (size_t i = 0; i < px.size(); ++i) {
            const float v = img.data[i];
            const float e = int(i % size_t(img.channels)) == alpha ? (v > 0.f ? std::min(v, 1.f) : 0.f) : linear_to_srgb(v);
            px[i] = (unsigned char)std::lround(255.f * e);
        }
        ok = out->write_image(OIIO::TypeDesc::UINT8, px.data());
    }
    if (!ok) throw Error(path + ": write failed: " + out->geterror());
    out->close();
}

namespace {
/// OpenImageIO's readers can throw (a BMP whose RLE header claims 4 × 10⁹ pixels throws
/// std::length_error from ImageInput::open): such an exception becomes an Error naming the file.
template <class Fn>
auto naming_the_file(const std::string& path, Fn&& fn) -> decltype(fn()) {
    try {
        return fn();
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        throw Error(path + ": cannot read image (corrupt file; the reader failed: " + e.what() + ")");
    }
}
/// Every channel of the file, linear float (8-bit files decoded from sRGB, alpha excepted);
/// `spec_out` receives the file's spec. With `as_stored`, colour channels are not multiplied by
/// alpha (OpenImageIO's default for PNG and other unassociated-alpha formats does that).
Image decode_all(const std::string& path, OIIO::ImageSpec* spec_out = nullptr, bool as_stored = true) {
    if (!std::filesystem::exists(path)) throw Error(path + ": image file not found");
    OIIO::ImageSpec config;
    if (as_stored) config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(path, &config);
    if (!in) throw Error(path + ": cannot read image (unsupported or corrupt): " + OIIO::geterror());
    const OIIO::ImageSpec spec = in->spec();
    int w = spec.width, h = spec.height, c = spec.nchannels;
    if (w <= 0 || h <= 0 || c <= 0) throw Error(path + ": image has no pixels");
    if (std::string e = texture_size_error(w, h); !e.empty()) throw Error(path + ": " + e);  // before decoding
    Image img(w, h, c);
    if (!in->read_image(0, 0, 0, c, OIIO::TypeDesc::FLOAT, img.data.data()))
        throw Error(path + ": cannot decode image: " + in->geterror());
    in->close();
    // 8/16-bit integer files are display-encoded unless they say otherwise; alpha is linear.
    std::string cs = spec.get_string_attribute("oiio:ColorSpace", "");
    bool srgb = spec.format.is_floating_point() ? false : (cs.empty() || cs == "sRGB");
    if (srgb)
        for (size_t i = 0; i < img.data.size(); ++i) {
            if (int(i % size_t(c)) == spec.alpha_channel) continue;
            float& v = img.data[i];
            v = v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
        }
    if (spec_out) *spec_out = spec;
    return img;
}

/// The header attribute that keeps the written order of a multi-layer file's channels.
constexpr const char* kChannelOrder = "pellucid:channels";

/// Where channel `name` goes among its layer's channels: R, G, B, A / X, Y, Z, W / U, V in that
/// order, others after them in the file's order.
int channel_rank(const std::string& name) {
    static const char* kOrder[] = {"R", "G", "B", "A", "X", "Y", "Z", "W", "U", "V"};
    for (int i = 0; i < 10; ++i)
        if (name == kOrder[i]) return i;
    return 10;
}
}  // namespace

Image read_image_channels(const std::string& path) {
    return naming_the_file(path, [&] { return decode_all(path); });
}

void write_layers_file(const std::string& path, const std::vector<ImageLayer>& layers,
                       const std::vector<ImageAttribute>& attributes) {
    if (extension(path) != ".exr")
        throw Error(path + ": layers (AOVs) are written to one multi-layer OpenEXR file: use a .exr path");
    if (layers.empty()) throw Error(path + ": no layers to write");
    const int w = layers.front().image.width, h = layers.front().image.height;
    if (w <= 0 || h <= 0) throw Error(path + ": cannot write an empty image");
    std::vector<std::string> names;
    for (const ImageLayer& l : layers) {
        const std::string what = l.name.empty() ? std::string("the unnamed layer") : "layer '" + l.name + "'";
        if (l.image.width != w || l.image.height != h)
            throw Error(path + ": " + what + " is " + std::to_string(l.image.width) + "x" + std::to_string(l.image.height) +
                        ", the first layer " + std::to_string(w) + "x" + std::to_string(h));
        if (int(l.channels.size()) != l.image.channels)
            throw Error(path + ": " + what + " has " + std::to_string(l.image.channels) + " channels but " +
                        std::to_string(l.channels.size()) + " channel names");
        if (l.name.find('.') != std::string::npos) throw Error(path + ": layer name '" + l.name + "' contains a '.'");
        for (const std::string& c : l.channels) {
            if (c.empty() || c.find('.') != std::string::npos)
                throw Error(path + ": " + what + ": bad channel name '" + c + "'");
            names.push_back(l.name.empty() ? c : l.name + "." + c);
            if (std::count(names.begin(), names.end(), names.back()) > 1)
                throw Error(path + ": channel '" + names.back() + "' appears twice");
        }
    }
    check_image_output(path);
    auto out = OIIO::ImageOutput::create(path);
    if (!out) throw Error(path + ": cannot create an OpenEXR writer: " + OIIO::geterror());
    OIIO::ImageSpec spec(w, h, int(names.size()), OIIO::TypeDesc::FLOAT);
    spec.channelnames = names;
    spec.alpha_channel = -1;
    spec.z_channel = -1;
    for (size_t i = 0; i < names.size(); ++i)
        if (names[i] == "A") spec.alpha_channel = int(i);
    add_attributes(spec, attributes);
    // OpenEXR stores channels sorted by name: the order of layers and channels goes in the header.
    std::string order;
    for (const std::string& c : names) order += (order.empty() ? "" : ",") + c;
    spec.attribute(kChannelOrder, order);
    const size_t nc = names.size(), n = size_t(w) * size_t(h);
    std::vector<float> px(n * nc);
    size_t c0 = 0;
    for (const ImageLayer& l : layers) {
        const size_t lc = size_t(l.image.channels);
        for (size_t p = 0; p < n; ++p)
            for (size_t k = 0; k < lc; ++k) px[p * nc + c0 + k] = l.image.data[p * lc + k];
        c0 += lc;
    }
    if (!out->open(path, spec)) throw Error(path + ": cannot open for writing: " + out->geterror());
    if (!out->write_image(OIIO::TypeDesc::FLOAT, px.data())) throw Error(path + ": write failed: " + out->geterror());
    out->close();
}

std::vector<ImageLayer> read_layers_file(const std::string& path) {
    return naming_the_file(path, [&] {
        OIIO::ImageSpec spec;
        const Image all = decode_all(path, &spec);
        struct Entry {
            std::string layer, channel;
            int index;
        };
        // The channels in the order they were written (kChannelOrder), when the header has it and it
        // names exactly the file's channels; else the file's order.
        std::vector<int> file_order(size_t(all.channels));
        for (int i = 0; i < all.channels; ++i) file_order[size_t(i)] = i;
        const std::string written = spec.get_string_attribute(kChannelOrder, "");
        bool known_order = false;
        if (!written.empty()) {
            std::vector<int> idx;
            size_t start = 0;
            while (start <= written.size()) {
                size_t end = written.find(',', start);
                if (end == std::string::npos) end = written.size();
                const std::string c = written.substr(start, end - start);
                auto it = std::find(spec.channelnames.begin(), spec.channelnames.end(), c);
                if (it == spec.channelnames.end() || std::count(idx.begin(), idx.end(), int(it - spec.channelnames.begin())))
                    break;
                idx.push_back(int(it - spec.channelnames.begin()));
                start = end + 1;
            }
            if (int(idx.size()) == all.channels) file_order = idx, known_order = true;
        }
        std::vector<std::string> order;  // layer names, unnamed first, then as they appear
        std::vector<Entry> entries;
        for (int i : file_order) {
            const std::string full = i < int(spec.channelnames.size()) ? spec.channelnames[size_t(i)] : "";
            const size_t dot = full.rfind('.');
            Entry e{dot == std::string::npos ? "" : full.substr(0, dot), dot == std::string::npos ? full : full.substr(dot + 1), i};
            if (std::find(order.begin(), order.end(), e.layer) == order.end()) order.push_back(e.layer);
            entries.push_back(e);
        }
        std::stable_partition(order.begin(), order.end(), [](const std::string& s) { return s.empty(); });
        std::vector<ImageLayer> out;
        const size_t n = size_t(all.width) * size_t(all.height), nc = size_t(all.channels);
        for (const std::string& name : order) {
            std::vector<Entry> mine;
            for (const Entry& e : entries)
                if (e.layer == name) mine.push_back(e);
            if (!known_order)
                std::stable_sort(mine.begin(), mine.end(), [](const Entry& a, const Entry& b) {
                    return channel_rank(a.channel) < channel_rank(b.channel);
                });
            ImageLayer l{name, {}, Image(all.width, all.height, int(mine.size()))};
            for (size_t k = 0; k < mine.size(); ++k) {
                l.channels.push_back(mine[k].channel);
                for (size_t p = 0; p < n; ++p) l.image.data[p * mine.size() + k] = all.data[p * nc + size_t(mine[k].index)];
            }
            out.push_back(std::move(l));
        }
        return out;
    });
}

Image read_image_file(const std::string& path) {
    return naming_the_file(path, [&] {
        const Image all = decode_all(path, nullptr, false);
        const int c = all.channels;
        Image img(all.width, all.height, 3);
        for (size_t p = 0; p < size_t(all.width) * size_t(all.height); ++p)
            for (int k = 0; k < 3; ++k) img.data[p * 3 + size_t(k)] = all.data[p * size_t(c) + size_t(c >= 3 ? k : 0)];
        return img;
    });
}

std::vector<ImageAttribute> read_image_attributes(const std::string& path) {
    return naming_the_file(path, [&] {
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
    });
}
}  // namespace pellucid
