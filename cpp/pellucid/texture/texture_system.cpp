// OpenImageIO TextureSystem wrapper: loading (with sRGB → linear conversion into a cached MIP-mapped
// file) and filtered lookups.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/texture/texture_system.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imagecache.h>
#include <OpenImageIO/imageio.h>
#include <OpenImageIO/texture.h>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <vector>

#include "pellucid/util/error.h"
#include "pellucid/util/limits.h"

namespace pellucid {
namespace fs = std::filesystem;
namespace {

/// OpenImageIO's process-wide image cache, which ImageBuf reads go through.
OIIO::ImageCache* shared_image_cache() {
    static OIIO::ImageCache* ic = OIIO::ImageCache::create(/*shared=*/true);
    return ic;
}

OIIO::TextureSystem* texture_system() {
    static OIIO::TextureSystem* ts = [] {
        OIIO::TextureSystem* t = OIIO::TextureSystem::create(/*shared=*/false);
        t->attribute("automip", 1);           // MIP-map untiled/unmipped files in memory
        t->attribute("autotile", 64);         // and read them in tiles
        t->attribute("max_memory_MB", float(texture_cache_mb()));  // util/limits.h
        t->attribute("accept_untiled", 1);
        t->attribute("accept_unmipped", 1);
        return t;
    }();
    return ts;
}

std::string cache_dir() {
    if (const char* env = std::getenv("PELLUCID_TEXTURE_CACHE"); env && *env) return env;
    std::error_code ec;
    fs::path tmp = fs::temp_directory_path(ec);
    if (ec) tmp = "/tmp";
    return (tmp / "pellucid-texture-cache").string();
}

// FNV-1a, 64 bit: a cache key, not a security boundary.
uint64_t fnv1a(const std::string& s) {
    uint64_t h = 1469598103934665603ull;
    for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
    return h;
}

std::string hex(uint64_t v) {
    static const char* d = "0123456789abcdef";
    std::string s(16, '0');
    for (int i = 15; i >= 0; --i, v >>= 4) s[size_t(i)] = d[v & 15];
    return s;
}

float srgb_to_linear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }

/// Every texel of every MIP level of subimage 0, read a band of scanlines at a time (a few MB): the
/// range of the channels lookups return, and the first NaN or infinite texel, which is an error.
void scan_texels(const std::string& path, OIIO::ImageInput& in, bool srgb, ImageTextureInfo& info) {
    const int lookup_channels = info.channels >= 3 ? 3 : 1;  // as lookup_image_texture
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    std::vector<float> band;
    for (int level = 0; in.seek_subimage(0, level); ++level) {
        const OIIO::ImageSpec spec = in.spec();  // a copy: seek_subimage replaces it
        const int w = spec.width, h = spec.height, nc = spec.nchannels;
        if (w < 1 || h < 1 || nc < 1 || spec.depth > 1 || spec.deep) break;
        if (std::string e = texture_size_error(w, h); !e.empty())
            throw Error(path + ": MIP level " + std::to_string(level) + ": " + e);
        // Bands of about 1M values; whole rows of tiles for a tiled file.
        const int unit = spec.tile_width > 0 ? std::max(1, spec.tile_height) : 1;
        const int rows = unit * int(std::max<int64_t>(1, (int64_t(1) << 20) / (int64_t(w) * nc * unit)));
        for (int y0 = spec.y; y0 < spec.y + h; y0 += rows) {
            const int y1 = std::min(spec.y + h, y0 + rows);
            band.resize(size_t(y1 - y0) * size_t(w) * size_t(nc));
            const bool ok = spec.tile_width > 0
                                ? in.read_tiles(0, level, spec.x, spec.x + w, y0, y1, spec.z, spec.z + std::max(1, spec.depth),
                                                0, nc, OIIO::TypeDesc::FLOAT, band.data())
                                : in.read_scanlines(0, level, y0, y1, spec.z, 0, nc, OIIO::TypeDesc::FLOAT, band.data());
            if (!ok) throw Error(path + ": cannot decode texture: " + in.geterror());
            for (size_t i = 0; i < band.size(); ++i) {
                const float v = band[i];
                const int c = int(i % size_t(nc));
                if (!std::isfinite(v)) {
                    const size_t texel = i / size_t(nc);
                    throw Error(path + ": texel (" + std::to_string(texel % size_t(w)) + ", " +
                                std::to_string(size_t(y0 - spec.y) + texel / size_t(w)) + ") channel " +
                                std::to_string(c) + (level ? " of MIP level " + std::to_string(level) : "") +
                                " is " + (std::isnan(v) ? "NaN" : "infinite") +
                                "; textures must hold finite values");
                }
                if (c < lookup_channels) {
                    lo[c] = std::min(lo[c], v);
                    hi[c] = std::max(hi[c], v);
                }
            }
        }
    }
    if (lookup_channels == 1) lo[1] = lo[2] = lo[0], hi[1] = hi[2] = hi[0];
    for (int c = 0; c < 3; ++c) {
        // sRGB decoding is increasing, so it maps the extremes to the extremes.
        info.lo[c] = srgb ? srgb_to_linear(lo[c]) : lo[c];
        info.hi[c] = srgb ? srgb_to_linear(hi[c]) : hi[c];
    }
}

// Convert an sRGB-encoded file once into a linear half-float tiled MIP map (maketx's job).
std::string linear_copy(const std::string& path) {
    std::error_code ec;
    fs::path abs = fs::absolute(path, ec);
    auto size = fs::file_size(abs, ec);
    auto mtime = fs::last_write_time(abs, ec).time_since_epoch().count();
    std::string key = hex(fnv1a(abs.string() + "|" + std::to_string(size) + "|" + std::to_string(mtime) + "|srgb-v1"));
    fs::path dir = cache_dir();
    fs::path out = dir / (abs.stem().string() + "-" + key + ".exr");
    if (fs::exists(out, ec)) return out.string();
    fs::create_directories(dir, ec);
    if (ec) throw Error(path + ": cannot create the texture cache directory " + dir.string() + ": " + ec.message());
    // Write to a unique temporary name and rename: concurrent processes never see half a file.
    static std::atomic<unsigned> counter{0};
    fs::path tmp = dir / (out.stem().string() + ".tmp" + std::to_string(::getpid()) + "-" +
                          std::to_string(counter++) + ".exr");
    // Decode sRGB → linear ourselves (IEC 61966-2-1; OIIO's own conversion needs an OCIO config),
    // then let make_texture build the tiled MIP pyramid from linear floats. A failure leaves no
    // temporary file behind.
    struct RemoveOnFailure {
        fs::path file;
        bool done = false;
        ~RemoveOnFailure() {
            std::error_code ignored;
            if (!done) fs::remove(file, ignored);
        }
    } cleanup{tmp};
    OIIO::ImageBuf src(path);
    if (!src.read(0, 0, true, OIIO::TypeDesc::FLOAT))
        throw Error(path + ": cannot read texture: " + src.geterror());
    const OIIO::ImageSpec& spec = src.spec();
    std::vector<float> px(size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels));
    src.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, px.data());
    int colour_channels = spec.alpha_channel >= 0 ? std::min(spec.nchannels, 3) : spec.nchannels;
    for (size_t i = 0; i < px.size(); ++i) {
        if (int(i % size_t(spec.nchannels)) >= colour_channels) continue;  // alpha stays linear
        float c = px[i];
        px[i] = srgb_to_linear(c);
    }
    OIIO::ImageSpec lin_spec(spec.width, spec.height, spec.nchannels, OIIO::TypeDesc::FLOAT);
    lin_spec.channelnames = spec.channelnames;
    lin_spec.alpha_channel = spec.alpha_channel;
    OIIO::ImageBuf lin(lin_spec);
    lin.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, px.data());
    OIIO::ImageSpec config;
    config.format = OIIO::TypeDesc::HALF;
    config.tile_width = config.tile_height = 64;
    config.attribute("maketx:filtername", "box");
    if (!OIIO::ImageBufAlgo::make_texture(OIIO::ImageBufAlgo::MakeTxTexture, lin, tmp.string(), config))
        throw Error(path + ": cannot convert the texture to linear MIP-mapped form: " + OIIO::geterror());
    fs::rename(tmp, out, ec);
    if (ec) throw Error(path + ": cannot write the texture cache entry " + out.string() + ": " + ec.message());
    cleanup.done = true;
    // ImageBuf registered the source in OpenImageIO's shared image cache; the texture system reads
    // the converted copy, so the source's record (header, tiles) is of no further use.
    shared_image_cache()->invalidate(OIIO::ustring(path), /*force=*/true);
    return out.string();
}

OIIO::TextureOpt::Wrap to_oiio(TextureWrap w) {
    switch (w) {
        case TextureWrap::Repeat: return OIIO::TextureOpt::WrapPeriodic;
        case TextureWrap::Mirror: return OIIO::TextureOpt::WrapMirror;
        case TextureWrap::Clamp: return OIIO::TextureOpt::WrapClamp;
        case TextureWrap::Black: return OIIO::TextureOpt::WrapBlack;
    }
    return OIIO::TextureOpt::WrapPeriodic;
}
}  // namespace

static ImageTextureHandle open_image_texture_unchecked(const std::string& path, TextureColorSpace cs,
                                                       ImageTextureInfo* info);

ImageTextureHandle open_image_texture(const std::string& path, TextureColorSpace cs, ImageTextureInfo* info) {
    // OpenImageIO's readers can throw (a BMP whose RLE header claims 4 x 10^9 pixels throws
    // std::length_error from ImageInput::open): such an exception becomes an Error naming the file.
    try {
        return open_image_texture_unchecked(path, cs, info);
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        throw Error(path + ": cannot read texture (corrupt file; the reader failed: " + e.what() + ")");
    }
}

static ImageTextureHandle open_image_texture_unchecked(const std::string& path, TextureColorSpace cs,
                                                       ImageTextureInfo* info) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) throw Error(path + ": texture file not found");
    ImageTextureInfo found;
    {
        auto in = OIIO::ImageInput::open(path);
        if (!in) throw Error(path + ": cannot read texture (unsupported or corrupt image): " + OIIO::geterror());
        const OIIO::ImageSpec& spec = in->spec();
        found.width = spec.width;
        found.height = spec.height;
        found.channels = spec.nchannels;
        const bool integer_format =
            spec.format.basetype == OIIO::TypeDesc::UINT8 || spec.format.basetype == OIIO::TypeDesc::UINT16 ||
            spec.format.basetype == OIIO::TypeDesc::INT8 || spec.format.basetype == OIIO::TypeDesc::INT16;
        if (found.width < 1 || found.height < 1 || found.channels < 1) throw Error(path + ": texture has no pixels");
        if (spec.depth > 1 || spec.deep)
            throw Error(path + ": " + (spec.deep ? "deep" : "volume (3D)") + " images are not textures");
        // From the header, before a pixel is decoded: a small file can claim a huge image.
        if (std::string e = texture_size_error(spec.width, spec.height); !e.empty()) throw Error(path + ": " + e);
        // The display window must be the data window: the texture system sizes its MIP levels by
        // the display window and fills it from the data, so a 4x3 EXR claiming a display window of
        // 1501953x37377 (or 1x7601509) ran for minutes.
        if (spec.full_width != spec.width || spec.full_height != spec.height || spec.full_x != spec.x ||
            spec.full_y != spec.y)
            throw Error(path + ": the display window (" + std::to_string(spec.full_width) + "x" +
                        std::to_string(spec.full_height) + " at " + std::to_string(spec.full_x) + "," +
                        std::to_string(spec.full_y) + ") differs from the data window (" + std::to_string(spec.width) +
                        "x" + std::to_string(spec.height) + " at " + std::to_string(spec.x) + "," +
                        std::to_string(spec.y) + "); a texture must be a whole image: crop it to its data window");
        // OpenImageIO reads whole tiles: a header may claim tiles far larger than the image.
        if (spec.tile_width > 0 && int64_t(spec.tile_width) * std::max(1, spec.tile_height) > (int64_t(1) << 20))
            throw Error(path + ": tiles of " + std::to_string(spec.tile_width) + "x" + std::to_string(spec.tile_height) +
                        " pixels, more than the 1048576 pixels a tile may have");
        found.srgb = cs == TextureColorSpace::SRGB || (cs == TextureColorSpace::Auto && integer_format);
        scan_texels(path, *in, found.srgb, found);
        in->close();
    }
    found.resolved = found.srgb ? linear_copy(path) : path;
    const std::string& resolved = found.resolved;
    const int channels = found.channels;

    OIIO::TextureSystem* ts = texture_system();
    static std::mutex mutex;  // handle creation is cheap and rare; keep error reporting per call
    std::lock_guard<std::mutex> lock(mutex);
    OIIO::TextureSystem::TextureHandle* h = ts->get_texture_handle(OIIO::ustring(resolved));
    if (!h || !ts->good(h)) throw Error(path + ": cannot open texture: " + ts->geterror());
    if (info) *info = found;
    return ImageTextureHandle{h, channels};
}

void forget_image_texture(const std::string& path) {
    texture_system()->invalidate(OIIO::ustring(path), /*force=*/true);
    shared_image_cache()->invalidate(OIIO::ustring(path), /*force=*/true);
}

Spectrum lookup_image_texture(const ImageTextureHandle& h, TextureFilter filter, TextureWrap wrap, float s,
                              float t, float dsdx, float dtdx, float dsdy, float dtdy) {
    OIIO::TextureSystem* ts = texture_system();
    OIIO::TextureOpt opt;
    opt.swrap = opt.twrap = to_oiio(wrap);
    switch (filter) {
        case TextureFilter::Nearest:
            opt.mipmode = OIIO::TextureOpt::MipModeNoMIP;
            opt.interpmode = OIIO::TextureOpt::InterpClosest;
            break;
        case TextureFilter::Bilinear:
            opt.mipmode = OIIO::TextureOpt::MipModeNoMIP;
            opt.interpmode = OIIO::TextureOpt::InterpBilinear;
            break;
        case TextureFilter::Trilinear:
            opt.mipmode = OIIO::TextureOpt::MipModeTrilinear;
            opt.interpmode = OIIO::TextureOpt::InterpBilinear;
            break;
        case TextureFilter::Anisotropic:
            opt.mipmode = OIIO::TextureOpt::MipModeAniso;
            opt.interpmode = OIIO::TextureOpt::InterpBilinear;
            break;
    }
    float r[3] = {0.f, 0.f, 0.f};
    auto* handle = static_cast<OIIO::TextureSystem::TextureHandle*>(h.handle);
    int n = h.channels >= 3 ? 3 : 1;
    // OIIO's per-thread state, fetched once per thread (get_perthread_info is a virtual call and
    // a thread-specific-storage lookup; the pointer stays valid for the thread's lifetime).
    thread_local OIIO::TextureSystem::Perthread* thread_info = ts->get_perthread_info();
    ts->texture(handle, thread_info, opt, s, t, dsdx, dtdx, dsdy, dtdy, n, r);
    if (n == 1) return Spectrum(r[0]);
    return Spectrum(r[0], r[1], r[2]);
}

Spectrum lookup_image_texture_gradient(const ImageTextureHandle& h, TextureWrap wrap, float s, float t,
                                       Spectrum* dvalue_ds, Spectrum* dvalue_dt) {
    OIIO::TextureSystem* ts = texture_system();
    OIIO::TextureOpt opt;
    opt.swrap = opt.twrap = to_oiio(wrap);
    opt.mipmode = OIIO::TextureOpt::MipModeNoMIP;
    opt.interpmode = OIIO::TextureOpt::InterpBilinear;
    float r[3] = {0.f, 0.f, 0.f}, ds[3] = {0.f, 0.f, 0.f}, dt[3] = {0.f, 0.f, 0.f};
    auto* handle = static_cast<OIIO::TextureSystem::TextureHandle*>(h.handle);
    int n = h.channels >= 3 ? 3 : 1;
    thread_local OIIO::TextureSystem::Perthread* thread_info = ts->get_perthread_info();
    // OIIO differentiates its bilinear interpolation exactly when asked for dresultds/dresultdt.
    ts->texture(handle, thread_info, opt, s, t, 0.f, 0.f, 0.f, 0.f, n, r, ds, dt);
    if (n == 1) {
        *dvalue_ds = Spectrum(ds[0]);
        *dvalue_dt = Spectrum(dt[0]);
        return Spectrum(r[0]);
    }
    *dvalue_ds = Spectrum(ds[0], ds[1], ds[2]);
    *dvalue_dt = Spectrum(dt[0], dt[1], dt[2]);
    return Spectrum(r[0], r[1], r[2]);
}

int write_level_index_mipmap(const std::string& path, int size) {
    auto out = OIIO::ImageOutput::create(path);
    if (!out || !out->supports("mipmap")) throw Error(path + ": cannot write a MIP-mapped file");
    int levels = 0;
    for (int s = size; s >= 1; s /= 2) ++levels;
    for (int k = 0, s = size; k < levels; ++k, s /= 2) {
        OIIO::ImageSpec spec(s, s, 1, OIIO::TypeDesc::FLOAT);
        spec.tile_width = spec.tile_height = 16;
        spec.attribute("openexr:levelmode", 1);  // MIPMAP_LEVELS
        spec.attribute("textureformat", "Plain Texture");
        std::vector<float> px(size_t(s) * size_t(s), float(k));
        bool ok = k == 0 ? out->open(path, spec) : out->open(path, spec, OIIO::ImageOutput::AppendMIPLevel);
        if (!ok || !out->write_image(OIIO::TypeDesc::FLOAT, px.data()))
            throw Error(path + ": cannot write MIP level " + std::to_string(k) + ": " + out->geterror());
    }
    out->close();
    return levels;
}

void write_test_image(const std::string& path, int width, int height, int channels, int bits, const float* data) {
    auto out = OIIO::ImageOutput::create(path);
    if (!out) throw Error(path + ": cannot create image writer: " + OIIO::geterror());
    OIIO::TypeDesc fmt = bits == 8 ? OIIO::TypeDesc::UINT8 : bits == 16 ? OIIO::TypeDesc::UINT16 : OIIO::TypeDesc::FLOAT;
    OIIO::ImageSpec spec(width, height, channels, fmt);
    if (!out->open(path, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, data))
        throw Error(path + ": cannot write: " + out->geterror());
    out->close();
}
}  // namespace pellucid
