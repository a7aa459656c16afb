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
#include <memory>
#include <mutex>
#include <vector>

#include "pellucid/texture/texture_lanes.h"
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
/// When level0 is given, it receives the full-resolution level's lookup channels as read (before
/// any sRGB decoding), rows from the top.
void scan_texels(const std::string& path, OIIO::ImageInput& in, bool srgb, ImageTextureInfo& info,
                 std::vector<float>* level0) {
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
            if (level == 0 && level0) {
                if (y0 == spec.y) level0->resize(size_t(w) * size_t(h) * size_t(lookup_channels));
                float* dst = level0->data() + size_t(y0 - spec.y) * size_t(w) * size_t(lookup_channels);
                const size_t texels = band.size() / size_t(nc);
                for (size_t k = 0; k < texels; ++k)
                    for (int c = 0; c < lookup_channels; ++c)
                        dst[k * size_t(lookup_channels) + size_t(c)] = band[k * size_t(nc) + size_t(c)];
            }
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

/// The full-resolution levels kept in memory (ImageTextureHandle::texels), keyed by the file the
/// TextureSystem reads, as its cache is. Blocks live until forget_image_texture of their file; the
/// registry itself is never destroyed, so handles stay valid through static destruction.
struct TexelBlock {
    std::string source;  ///< the path open_image_texture was given
    int width = 0, height = 0;
    std::vector<float> texels;
};
struct TexelRegistry {
    std::mutex mutex;
    std::vector<std::unique_ptr<TexelBlock>> blocks;  // few textures per scene: a linear search
    std::vector<std::string> keys;
};
TexelRegistry& texel_registry() {
    static TexelRegistry* r = new TexelRegistry;
    return *r;
}

const TexelBlock* find_texel_block(const std::string& key) {
    TexelRegistry& r = texel_registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    for (size_t i = 0; i < r.keys.size(); ++i)
        if (r.keys[i] == key) return r.blocks[i].get();
    return nullptr;
}

/// Registers block under key unless another thread did first; returns the registered one.
const TexelBlock* add_texel_block(const std::string& key, std::unique_ptr<TexelBlock> block) {
    TexelRegistry& r = texel_registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    for (size_t i = 0; i < r.keys.size(); ++i)
        if (r.keys[i] == key) return r.blocks[i].get();
    r.keys.push_back(key);
    r.blocks.push_back(std::move(block));
    return r.blocks.back().get();
}

void forget_texel_blocks(const std::string& path) {
    TexelRegistry& r = texel_registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    for (size_t i = r.keys.size(); i-- > 0;) {
        if (r.keys[i] != path && r.blocks[i]->source != path) continue;
        r.keys.erase(r.keys.begin() + std::ptrdiff_t(i));
        r.blocks.erase(r.blocks.begin() + std::ptrdiff_t(i));
    }
}

/// Level 0 of a file, its first `channels` channels as floats (OpenImageIO's conversion, the one its
/// tile cache applies: integer values × 1/max, half values exactly).
std::vector<float> read_level0(const std::string& path, const std::string& file, int channels, int width,
                               int height) {
    auto in = OIIO::ImageInput::open(file);
    if (!in) throw Error(path + ": cannot read texture " + file + ": " + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width != width || spec.height != height || spec.nchannels < channels)
        throw Error(path + ": the texture cache entry " + file + " does not match the source's size");
    std::vector<float> px(size_t(width) * size_t(height) * size_t(channels));
    if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, px.data()))
        throw Error(path + ": cannot decode texture " + file + ": " + in->geterror());
    return px;
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
    bool keep_in_memory = false, capture = false;
    std::vector<float> level0;
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
        // A linear file's level 0 as scanned is what the TextureSystem reads: keep it, unless the
        // registry holds it already or the image is too large to keep.
        keep_in_memory = int64_t(found.width) * found.height <= kInMemoryTextureTexels;
        capture = keep_in_memory && !found.srgb && !find_texel_block(path);
        scan_texels(path, *in, found.srgb, found, capture ? &level0 : nullptr);
        in->close();
    }
    found.resolved = found.srgb ? linear_copy(path) : path;
    const std::string& resolved = found.resolved;
    const int channels = found.channels;
    const TexelBlock* block = nullptr;
    if (keep_in_memory) {
        block = find_texel_block(resolved);
        if (!block) {
            auto b = std::make_unique<TexelBlock>();
            b->source = path;
            b->width = found.width;
            b->height = found.height;
            // An sRGB file: the linear half-float copy the TextureSystem reads.
            b->texels = capture ? std::move(level0)
                                : read_level0(path, resolved, channels >= 3 ? 3 : 1, found.width, found.height);
            block = add_texel_block(resolved, std::move(b));
        }
    }

    OIIO::TextureSystem* ts = texture_system();
    static std::mutex mutex;  // handle creation is cheap and rare; keep error reporting per call
    std::lock_guard<std::mutex> lock(mutex);
    OIIO::TextureSystem::TextureHandle* h = ts->get_texture_handle(OIIO::ustring(resolved));
    if (!h || !ts->good(h)) throw Error(path + ": cannot open texture: " + ts->geterror());
    if (info) *info = found;
    ImageTextureHandle handle;
    handle.handle = h;
    handle.channels = channels;
    if (block) {
        handle.texels = block->texels.data();
        handle.width = block->width;
        handle.height = block->height;
    }
    return handle;
}

void forget_image_texture(const std::string& path) {
    forget_texel_blocks(path);
    texture_system()->invalidate(OIIO::ustring(path), /*force=*/true);
    shared_image_cache()->invalidate(OIIO::ustring(path), /*force=*/true);
}

namespace {
// Lookups on the in-memory full-resolution level, with the TextureSystem's conventions (its
// sample_closest / sample_bilinear with no MIP map, written anew): texel i's centre is at
// s = (i + ½)/width, t = 0 is the top row, and out-of-range texel indices wrap per axis.

/// Texel coordinate x = s·n − ½ split into floor and fraction. Coordinates beyond ±2^29 texels (and
/// NaN) are pinned there so that the integer index and its neighbour stay representable.
inline int texel_floor(float st, int n, float* frac) {
    float x = st * float(n) - 0.5f;  // as OIIO: s·width + (origin − ½), origin 0
    if (!(std::fabs(x) < 536870912.f)) x = x > 0.f ? 536870912.f : -536870912.f;
    const float f = std::floor(x);
    *frac = x - f;
    return int(f);
}

/// Wrap texel index i of a row (or column) of n texels; false: the texel is outside and black.
inline bool wrap_texel(TextureWrap wrap, int& i, int n) {
    if (uint32_t(i) < uint32_t(n)) return true;  // inside: every mode leaves it
    switch (wrap) {
        case TextureWrap::Repeat:
            i %= n;
            if (i < 0) i += n;
            return true;
        case TextureWrap::Mirror: {
            // Period 2n, reflected about the edges: texel −1 reads texel 0, texel n reads n − 1.
            if (i < 0) i = -1 - i;
            const int k = i / n;
            i -= k * n;
            if (k & 1) i = n - 1 - i;
            return true;
        }
        case TextureWrap::Clamp:
            i = i < 0 ? 0 : n - 1;
            return true;
        case TextureWrap::Black: return false;
    }
    return false;
}

/// The four texels around (s, t) (invalid ones read as zero) and the fractions between them.
template <int N>
struct Quad {
    float v[2][2][N];  // [row: t0, t1][column: s0, s1][channel]
    float sf, tf;
};

template <int N>
inline void gather_quad(const ImageTextureHandle& h, TextureWrap wrap, float s, float t, Quad<N>& q) {
    const int w = h.width, hh = h.height;
    int s0 = texel_floor(s, w, &q.sf), t0 = texel_floor(t, hh, &q.tf);
    int s1 = s0 + 1, t1 = t0 + 1;
    bool vs0, vs1, vt0, vt1;
    if (wrap == TextureWrap::Repeat) {  // one division per axis: the neighbour of a wrapped index
        vs0 = vs1 = vt0 = vt1 = wrap_texel(wrap, s0, w) && wrap_texel(wrap, t0, hh);
        s1 = s0 + 1 == w ? 0 : s0 + 1;
        t1 = t0 + 1 == hh ? 0 : t0 + 1;
    } else {
        vs0 = wrap_texel(wrap, s0, w), vs1 = wrap_texel(wrap, s1, w);
        vt0 = wrap_texel(wrap, t0, hh), vt1 = wrap_texel(wrap, t1, hh);
    }
    const int ss[2] = {s0, s1}, tt[2] = {t0, t1};
    const bool vss[2] = {vs0, vs1}, vtt[2] = {vt0, vt1};
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            if (!(vtt[j] && vss[i])) {
                for (int c = 0; c < N; ++c) q.v[j][i][c] = 0.f;
                continue;
            }
            const float* p = h.texels + (size_t(tt[j]) * size_t(w) + size_t(ss[i])) * N;
            for (int c = 0; c < N; ++c) q.v[j][i][c] = p[c];
        }
}

inline Spectrum to_spectrum(const float* r, int n) { return n == 1 ? Spectrum(r[0]) : Spectrum(r[0], r[1], r[2]); }

template <int N>
Spectrum memory_nearest(const ImageTextureHandle& h, TextureWrap wrap, float s, float t) {
    float sf, tf;
    int i = texel_floor(s, h.width, &sf), j = texel_floor(t, h.height, &tf);
    if (sf > 0.5f) ++i;  // exactly halfway: the lower texel, as OIIO
    if (tf > 0.5f) ++j;
    float r[3] = {0.f, 0.f, 0.f};
    if (wrap_texel(wrap, i, h.width) && wrap_texel(wrap, j, h.height)) {
        const float* p = h.texels + (size_t(j) * size_t(h.width) + size_t(i)) * N;
        for (int c = 0; c < N; ++c) r[c] = p[c];
    }
    return to_spectrum(r, N);
}

// The interpolation is written as OIIO's (same operations in the same order, no contraction), so
// results agree with the TextureSystem's to the last bit or nearly.
template <int N>
Spectrum memory_bilinear(const ImageTextureHandle& h, TextureWrap wrap, float s, float t, Spectrum* dvalue_ds,
                         Spectrum* dvalue_dt) {
    Quad<N> q;
    gather_quad<N>(h, wrap, s, t, q);
    float r[3] = {0.f, 0.f, 0.f};
    for (int c = 0; c < N; ++c) r[c] = bilinear_mix<float>(q.v[0][0][c], q.v[0][1][c], q.v[1][0][c], q.v[1][1][c], q.sf, q.tf);
    if (dvalue_ds) {
        float ds[3] = {0.f, 0.f, 0.f}, dt[3] = {0.f, 0.f, 0.f};
        for (int c = 0; c < N; ++c)
            bilinear_derivatives<float>(q.v[0][0][c], q.v[0][1][c], q.v[1][0][c], q.v[1][1][c], q.sf, q.tf, float(h.width),
                                        float(h.height), &ds[c], &dt[c]);
        *dvalue_ds = to_spectrum(ds, N);
        *dvalue_dt = to_spectrum(dt, N);
    }
    return to_spectrum(r, N);
}
}  // namespace

Spectrum lookup_image_texture(const ImageTextureHandle& h, TextureFilter filter, TextureWrap wrap, float s,
                              float t, float dsdx, float dtdx, float dsdy, float dtdy) {
    if (h.texels && filter <= TextureFilter::Bilinear) {
        const bool rgb = h.channels >= 3;
        if (filter == TextureFilter::Nearest)
            return rgb ? memory_nearest<3>(h, wrap, s, t) : memory_nearest<1>(h, wrap, s, t);
        return rgb ? memory_bilinear<3>(h, wrap, s, t, nullptr, nullptr)
                   : memory_bilinear<1>(h, wrap, s, t, nullptr, nullptr);
    }
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
    if (h.texels)
        return h.channels >= 3 ? memory_bilinear<3>(h, wrap, s, t, dvalue_ds, dvalue_dt)
                               : memory_bilinear<1>(h, wrap, s, t, dvalue_ds, dvalue_dt);
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
