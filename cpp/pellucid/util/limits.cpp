// Input limits.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/util/limits.h"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "pellucid/util/error.h"

namespace pellucid {

namespace {
/// The integer in environment variable `name`, `def` when unset or empty; an error outside [lo, hi].
int64_t env_limit(const char* name, int64_t def, int64_t lo, int64_t hi) {
    const char* s = std::getenv(name);
    if (!s || !*s) return def;
    char* end = nullptr;
    errno = 0;
    long long v = std::strtoll(s, &end, 10);
    if (*end != '\0' || errno == ERANGE || v < lo || v > hi)
        throw Error("environment variable " + std::string(name) + ": expected an integer in [" + std::to_string(lo) +
                    ", " + std::to_string(hi) + "], got '" + std::string(s) + "'");
    return int64_t(v);
}
}  // namespace

int max_scene_depth() {
    static const int depth = int(env_limit("PELLUCID_MAX_SCENE_DEPTH", kDefaultMaxSceneDepth, 1, 100000));
    return depth;
}

int64_t max_texture_pixels() {
    static const int64_t n = env_limit("PELLUCID_MAX_TEXTURE_PIXELS", kDefaultMaxTexturePixels, 1, int64_t(1) << 40);
    return n;
}

std::string texture_size_error(int64_t width, int64_t height) {
    const int64_t limit = max_texture_pixels();
    if (width <= limit && height <= limit && width * height <= limit) return "";
    return "the image is " + std::to_string(width) + "x" + std::to_string(height) + " pixels, more than the limit of " +
           std::to_string(limit) + " pixels for images read by a scene (raise it with PELLUCID_MAX_TEXTURE_PIXELS)";
}

int64_t texture_cache_mb() {
    static const int64_t n = env_limit("PELLUCID_TEXTURE_CACHE_MB", kDefaultTextureCacheMB, 64, int64_t(1) << 20);
    return n;
}

int64_t max_mesh_elements() {
    static const int64_t n = env_limit("PELLUCID_MAX_MESH_ELEMENTS", kDefaultMaxMeshElements, 1, 0xffffffffll);
    return n;
}

int64_t max_film_pixels() {
    static const int64_t n = env_limit("PELLUCID_MAX_FILM_PIXELS", kDefaultMaxFilmPixels, 1, int64_t(1) << 28);
    return n;
}

std::string film_size_error(int width, int height) {
    const int64_t limit = max_film_pixels();
    if (int64_t(width) * height <= limit) return "";
    return "resolution " + std::to_string(width) + "x" + std::to_string(height) + " is more than the limit of " +
           std::to_string(limit) + " pixels (raise it with PELLUCID_MAX_FILM_PIXELS)";
}
std::string point_text(float x, float y, float z) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "[%g, %g, %g]", double(x), double(y), double(z));
    return buf;
}
}  // namespace pellucid
