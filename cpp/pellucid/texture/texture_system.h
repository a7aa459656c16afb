// Filtered image lookups through OpenImageIO's TextureSystem (the only TextureSystem user; plain
// image files go through image/image_io.cpp).
// SPDX-License-Identifier: Apache-2.0
//
// One process-wide, thread-safe texture cache. Images are MIP-mapped on first use (OIIO "automip"
// for linear float files; 8- and 16-bit files whose values are sRGB-encoded are converted once to a
// linear, tiled, MIP-mapped half-float file in the texture cache directory, as maketx does, so that
// every filter averages linear values: averaging encoded values darkens high-contrast texture at a
// distance, e.g. a black/white checker would filter to 0.21 instead of 0.5).
//
// Cache directory: $PELLUCID_TEXTURE_CACHE, else <temp dir>/pellucid-texture-cache. Entries are keyed
// by the source's absolute path, size and modification time; stale entries are simply not reused.
#pragma once
#include <cstdint>
#include <string>

#include "pellucid/math/spectrum.h"
#include "pellucid/math/vec.h"

namespace pellucid {

enum class TextureWrap : uint8_t { Repeat, Mirror, Clamp, Black };
/// Filtering: Nearest and Bilinear read the full-resolution level only (no MIP map); Trilinear
/// blends two MIP levels chosen by the larger footprint axis; Anisotropic (OIIO's elliptical
/// multi-probe filter) follows the footprint's shape.
enum class TextureFilter : uint8_t { Nearest, Bilinear, Trilinear, Anisotropic };
enum class TextureColorSpace : uint8_t { Auto, SRGB, Linear };

struct ImageTextureInfo {
    int width = 0, height = 0, channels = 0;
    bool srgb = false;         ///< values were decoded from sRGB at load
    std::string resolved;      ///< the file the TextureSystem reads (the cached linear copy if any)
    /// Smallest and largest value of each channel lookups return (one channel replicated to RGB),
    /// over every texel of every MIP level of the file, after sRGB decoding. Filtered lookups
    /// average texels with non-negative weights, so they stay within [lo, hi].
    Spectrum lo{0.f}, hi{0.f};
};

/// Largest image (width × height texels) whose full-resolution level open_image_texture keeps in
/// memory as linear floats for the Nearest and Bilinear filters and the gradient lookup: 16 M texels
/// (4096 × 4096; 192 MB as RGB). Larger images are read through the TextureSystem's tile cache.
constexpr int64_t kInMemoryTextureTexels = int64_t(1) << 24;

/// A loaded texture: an opaque handle into the shared TextureSystem plus, for an image of at most
/// kInMemoryTextureTexels texels, its full-resolution level in memory (no heap, trivially copyable).
struct ImageTextureHandle {
    void* handle = nullptr;  ///< OIIO::TextureSystem::TextureHandle*
    /// The full-resolution level as lookups return it: width × height texels, rows from the top,
    /// 1 float per texel when channels < 3, else 3 (RGB). Owned by a process-wide registry until
    /// forget_image_texture of the file. Null: every lookup goes through the TextureSystem.
    const float* texels = nullptr;
    int width = 0, height = 0;
    int channels = 3;  ///< the file's channel count
};

/// Open (and if needed convert) an image for filtered lookups. Throws pellucid::Error naming the
/// path for a missing file, an unreadable or unsupported format, an image larger than the texture
/// limit (util/limits.h; checked from the header, before decoding), and a NaN or infinite texel
/// (its position named). Every texel is read once here to find them and the value range.
ImageTextureHandle open_image_texture(const std::string& path, TextureColorSpace cs, ImageTextureInfo* info);

/// Forget what the texture cache holds of the file at path (its header, decoded tiles and in-memory
/// level), so that the next open_image_texture of that path reads the file again; handles to it must
/// not be used after this. For a file rewritten under the same name.
void forget_image_texture(const std::string& path);

/// Filtered lookup at texture coordinates (s, t) ∈ [0,1]² (t = 0 is the image's top row) with the
/// screen-space derivatives of (s, t): the footprint. Zero derivatives give a point lookup at the
/// finest level. One channel is replicated to RGB; alpha is ignored. Nearest and Bilinear read the
/// handle's in-memory level when it has one (the TextureSystem's conventions, in our own code, with
/// no lock and no allocation); Trilinear and Anisotropic always go through the TextureSystem.
Spectrum lookup_image_texture(const ImageTextureHandle& h, TextureFilter filter, TextureWrap wrap, float s,
                              float t, float dsdx, float dtdx, float dsdy, float dtdy);

/// Bilinear lookup at the full-resolution level (no MIP map, no footprint) at (s, t), with the exact
/// derivatives of that bilinear interpolation with respect to s and t (texel centres at
/// (i + ½)/width, so ∂/∂s = width × the difference of neighbouring texels, blended in t). The
/// bump gradient of Mitsuba's bitmap texture is this derivative (bump_model "mitsuba"). Reads the
/// in-memory level when the handle has one.
Spectrum lookup_image_texture_gradient(const ImageTextureHandle& h, TextureWrap wrap, float s, float t,
                                       Spectrum* dvalue_ds, Spectrum* dvalue_dt);

/// Testing aid: write a tiled, MIP-mapped float image whose level k holds the constant value k, to
/// check which level a lookup reads. Returns the level count.
int write_level_index_mipmap(const std::string& path, int size);
/// Testing aid: write an image with `bits` per channel (8 or 16: integer PNG/TIFF; 32: float) from
/// linear-float pixel values in [0, 1] (integer files store them as-is, no transfer curve).
void write_test_image(const std::string& path, int width, int height, int channels, int bits, const float* data);
}  // namespace pellucid
