// Inputs that crashed, aborted or exhausted memory (found by the fuzzers in bench/fuzz or reported
// in the robustness issue), each kept in tests/data/fuzz/: every one now gets a pellucid::Error
// naming the file, the key or the limit.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "pellucid/geometry/mesh_io.h"
#include "pellucid/scene/mitsuba_xml.h"
#include "pellucid/texture/texture.h"
#include "pellucid/texture/texture_system.h"
#include "pellucid/util/limits.h"
#include "support/error_of.h"
#include "support/temp_dir.h"

using namespace pellucid;
using test::error_of_call;

namespace {
const std::string kData = std::string(PELLUCID_SOURCE_DIR) + "/tests/data/fuzz/";

std::string read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}
bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

/// Point the texture cache at `dir` for the lifetime of the object.
struct CacheDir {
    explicit CacheDir(const std::string& dir) { setenv("PELLUCID_TEXTURE_CACHE", dir.c_str(), 1); }
    ~CacheDir() { unsetenv("PELLUCID_TEXTURE_CACHE"); }
};
}  // namespace

TEST(FuzzRegressions, DeepJsonNesting) {
    std::string e = test::json_scene_error(read_text(kData + "deep_nesting.json"));
    EXPECT_TRUE(contains(e, "scene.json: objects and arrays nested deeper than 256 levels")) << e;
}

TEST(FuzzRegressions, DeepTwosidedNestingInMitsubaXml) {
    // 300 levels in the file; 10,000 (the size that overflowed the stack) built here.
    std::string e = error_of_call([] { parse_mitsuba_xml(read_text(kData + "deep_twosided.xml"), "deep.xml", ".", false); });
    EXPECT_TRUE(contains(e, "deep.xml:2: bsdfs nested deeper than 256 levels")) << e;
    EXPECT_TRUE(contains(e, "PELLUCID_MAX_SCENE_DEPTH")) << e;
    std::string deep;
    for (int i = 0; i < 10000; ++i) deep += "<bsdf type=\"twosided\">";
    deep += "<bsdf type=\"diffuse\"/>";
    for (int i = 0; i < 10000; ++i) deep += "</bsdf>";
    e = error_of_call([&] {
        parse_mitsuba_xml("<scene version=\"3.0.0\"><shape type=\"sphere\">" + deep + "</shape></scene>", "d.xml", ".",
                          true);
    });
    EXPECT_TRUE(contains(e, "bsdfs nested deeper than 256 levels")) << e;
    // Nesting within the limit still imports.
    std::string ok = "<bsdf type=\"twosided\"><bsdf type=\"twosided\"><bsdf type=\"diffuse\"/></bsdf></bsdf>";
    EXPECT_EQ(error_of_call([&] {
                  parse_mitsuba_xml("<scene version=\"3.0.0\"><shape type=\"sphere\">" + ok + "</shape></scene>", "ok.xml",
                                    ".", false);
              }),
              "");
}

TEST(FuzzRegressions, DecompressionBombPngIsRejectedFromItsHeader) {
    // 33 KB on disk, 16384 x 16384 pixels: 3 GB as float RGB. Rejected before decoding, and the
    // texture cache stays empty.
    test::TempDir dir("pellucid-bomb-");
    CacheDir cache(dir.file("cache"));
    const std::string png = kData + "bomb.png";
    std::string e = error_of_call([&] { open_image_texture(png, TextureColorSpace::Auto, nullptr); });
    EXPECT_EQ(e, png + ": the image is 16384x16384 pixels, more than the limit of 67108864 pixels for images "
                       "read by a scene (raise it with PELLUCID_MAX_TEXTURE_PIXELS)");
    EXPECT_FALSE(std::filesystem::exists(dir.file("cache")) && !std::filesystem::is_empty(dir.file("cache")));
    // The scene-level error names the key path as well.
    std::string s = test::json_scene_error(R"({"materials": {"m": {"type": "lambertian", "reflectance":
        {"type": "image", "filename": ")" + png + R"("}}}})");
    EXPECT_TRUE(contains(s, "scene.json: materials.m.reflectance.filename: " + png + ": the image is 16384x16384")) << s;
}

TEST(FuzzRegressions, CorruptTextureLeavesNoCacheFiles) {
    test::TempDir dir("pellucid-corrupt-");
    CacheDir cache(dir.file("cache"));
    // A valid PNG header with its image data cut off.
    std::string bytes = read_text(kData + "bomb.png").substr(0, 200);
    std::ofstream(dir.file("cut.png"), std::ios::binary) << bytes;
    std::string e = error_of_call([&] { open_image_texture(dir.file("cut.png"), TextureColorSpace::SRGB, nullptr); });
    EXPECT_TRUE(contains(e, dir.file("cut.png") + ": ")) << e;
    if (std::filesystem::exists(dir.file("cache")))
        EXPECT_TRUE(std::filesystem::is_empty(dir.file("cache")));
}

TEST(FuzzRegressions, NanTexelIsRejectedWithTheFileAndTexel) {
    const std::string pfm = kData + "nan_texel.pfm";
    std::string e = error_of_call([&] { open_image_texture(pfm, TextureColorSpace::Linear, nullptr); });
    // PFM rows are stored bottom-up; OpenImageIO returns them top-down, so the second stored texel
    // (x 1 of the bottom row) is texel (1, 1).
    EXPECT_EQ(e, pfm + ": texel (1, 1) channel 1 is NaN; textures must hold finite values");
}

TEST(FuzzRegressions, HugePlyCountsNameTheFileAndTheLimit) {
    const std::string huge = kData + "huge_count.ply";
    EXPECT_EQ(error_of_call([&] { load_ply(huge); }),
              huge + ":3: element 'vertex' has 4294967296 items, more than the limit of 268435456 (the mesh element "
                     "limit; raise it with PELLUCID_MAX_MESH_ELEMENTS)");
    const std::string cut = kData + "truncated_count.ply";
    EXPECT_EQ(error_of_call([&] { load_ply(cut); }),
              cut + ": the header declares 100000000 vertices and 100000000 faces, more than the 12 bytes of data can "
                    "hold (truncated file?)");
}

TEST(FuzzRegressions, DirectoryAsMeshOrSceneFileIsAnError) {
    // Reading a directory threw std::ios_base::failure from inside the standard library.
    test::TempDir dir("pellucid-dirfile-");
    EXPECT_EQ(error_of_call([&] { load_ply(dir.dir()); }), dir.dir() + ": not a regular file (a directory?)");
    EXPECT_EQ(error_of_call([&] { load_obj(dir.dir()); }), dir.dir() + ": not a regular file (a directory?)");
}

TEST(FuzzRegressions, PlyValuesThatOverflowAFloatAreErrors) {
    test::TempDir dir("pellucid-plyfloat-");
    std::ofstream(dir.file("big.ply")) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
                                          "property double z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                          "end_header\n0 0 0\n1 0 1e300\n0 1 0\n3 0 1 2\n";
    std::string e = error_of_call([&] { load_ply(dir.file("big.ply")); });
    EXPECT_TRUE(contains(e, "element 'vertex' 1: vertex position z = 1e+300 is not a finite")) << e;
    EXPECT_TRUE(contains(e, "is not a finite number that fits a 32-bit float")) << e;
}

TEST(FuzzRegressions, NoiseFarFromTheOriginStaysDefined) {
    // Lattice coordinates beyond the int range (noise scale 1e30) converted float -> int out of
    // range: undefined behaviour. The lattice has period 256, so such points reduce modulo 256.
    Vec3f g;
    for (float x : {3e9f, -3e9f, 1e30f, -1e38f}) {
        float n = perlin_noise(Vec3f(x, 0.25f, 0.5f), &g);
        EXPECT_TRUE(std::isfinite(n) && std::fabs(n) <= 1.5f) << x;
        EXPECT_TRUE(std::isfinite(g.x) && std::isfinite(g.y) && std::isfinite(g.z)) << x;
    }
    // Within the int range the reduction changes nothing: period 256 in every axis.
    EXPECT_EQ(perlin_noise(Vec3f(1.25f, 2.75f, 0.5f)), perlin_noise(Vec3f(1.25f + 256.f * 4096.f, 2.75f, 0.5f)));
    EXPECT_EQ(perlin_noise(Vec3f(INFINITY, 0.f, 0.f), &g), 0.f);
}
