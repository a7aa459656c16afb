// Documented input limits, each with the way to raise it (docs/scene-format.md, "Limits").
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <string>

namespace pellucid {

/// Deepest nesting of objects and arrays a scene description may have (JSON files, dicts passed to
/// load_dict). Real scenes nest fewer than ten levels; the limit keeps a malformed or
/// self-referencing input from exhausting the stack. Raised with the environment variable
/// PELLUCID_MAX_SCENE_DEPTH (read once per process).
constexpr int kDefaultMaxSceneDepth = 256;
int max_scene_depth();

/// Largest image a scene reads (image textures, environment maps), in pixels (width x height),
/// checked from the file's header before any pixel is decoded: a small compressed file can claim a
/// huge image (a "decompression bomb"). The default, 2^26 pixels (8192 x 8192), needs about 4.5 GB
/// while an 8-bit RGBA file is converted to its linear MIP-mapped form (67 bytes per pixel,
/// measured; docs/scene-format.md, "Limits and numbers"). Raised with the environment variable
/// PELLUCID_MAX_TEXTURE_PIXELS.
constexpr int64_t kDefaultMaxTexturePixels = int64_t(1) << 26;
int64_t max_texture_pixels();
/// "" when a width x height image is within the texture limit, else the message (naming the limit
/// and how to raise it) to report with the file's name.
std::string texture_size_error(int64_t width, int64_t height);

/// Memory the image-texture cache may hold for all textures together, in MB (tiles of decoded
/// texels; least recently used tiles are dropped past it). Changed with the environment variable
/// PELLUCID_TEXTURE_CACHE_MB (64 to 1048576).
constexpr int64_t kDefaultTextureCacheMB = 2048;
int64_t texture_cache_mb();

/// Largest element count (vertices, faces) a mesh file may declare: PLY headers and OBJ files. The
/// default, 2^28, keeps a mesh under about 11 GB (vertices with normals and uv: 32 bytes each;
/// triangles: 12 bytes). Raised with PELLUCID_MAX_MESH_ELEMENTS (at most 2^32 - 1: indices are
/// 32-bit).
constexpr int64_t kDefaultMaxMeshElements = int64_t(1) << 28;
int64_t max_mesh_elements();

/// Largest film, in pixels. The default, 2^25 pixels (for example 8192 x 4096, or 8K UHD
/// 7680 x 4320), needs about 2.3 GB (filter sampling) or 4.7 GB (splatting) of film and output
/// image. Raised with PELLUCID_MAX_FILM_PIXELS (up to 2^28, since each side is at most 16384).
constexpr int64_t kDefaultMaxFilmPixels = int64_t(1) << 25;
int64_t max_film_pixels();
/// "" when a width x height film is within the limit, else the message to report with the key.
std::string film_size_error(int width, int height);

/// True when a parameter given in double precision survives conversion to the 32-bit float it is
/// stored in: finite, and no larger in magnitude than FLT_MAX (1e39 is finite as a double, infinite
/// as a float).
/// Largest coordinate magnitude of scene geometry, the camera and positional lights, in scene
/// units. Embree rejects (and asserts on) ray origins of magnitude 1.844e18 or more; rays leave
/// surfaces and lights, so positions stay below 1e18. Not configurable: past it float spacing
/// exceeds 1e11 units and nothing can be rendered meaningfully.
constexpr float kMaxCoordinate = 1e18f;
inline bool within_coordinate_limit(float x, float y, float z) {
    return std::fabs(x) <= kMaxCoordinate && std::fabs(y) <= kMaxCoordinate && std::fabs(z) <= kMaxCoordinate;
}

/// "[x, y, z]" with 6 significant digits, for messages about coordinates.
std::string point_text(float x, float y, float z);

inline bool fits_float(double v) { return std::isfinite(v) && std::fabs(v) <= double(FLT_MAX); }
}  // namespace pellucid
