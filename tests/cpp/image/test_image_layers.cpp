// Image files with any channel count and multi-layer EXR (image/image_io.h): round trips and errors.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <functional>
#include <string>

#include "pellucid/image/image_io.h"
#include "pellucid/util/error.h"

using namespace pellucid;

namespace {
std::string temp_path(const std::string& name) {
    auto dir = std::filesystem::temp_directory_path() / ("pellucid_layers_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    return (dir / name).string();
}

Image ramp(int w, int h, int c, float scale) {
    Image img(w, h, c);
    for (size_t i = 0; i < img.data.size(); ++i) img.data[i] = scale * float(i) - 3.f;  // signed values too
    return img;
}

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}
}  // namespace

TEST(ImageLayers, MultiLayerExrRoundTripsNamesChannelsAndValues) {
    const std::string path = temp_path("layers.exr");
    std::vector<ImageLayer> layers = {
        {"", {"R", "G", "B"}, ramp(5, 3, 3, 0.25f)},
        {"albedo", {"R", "G", "B"}, ramp(5, 3, 3, 0.01f)},
        {"normal", {"X", "Y", "Z"}, ramp(5, 3, 3, -0.5f)},
        {"depth", {"Z"}, ramp(5, 3, 1, 2.f)},
        {"uv", {"U", "V"}, ramp(5, 3, 2, 0.1f)},
        {"custom", {"first", "second", "third", "fourth", "fifth"}, ramp(5, 3, 5, 1.5f)},
    };
    write_layers_file(path, layers, {{"pellucid:spp", int64_t(7)}});
    std::vector<ImageLayer> back = read_layers_file(path);
    ASSERT_EQ(back.size(), layers.size());
    for (size_t i = 0; i < layers.size(); ++i) {
        EXPECT_EQ(back[i].name, layers[i].name);
        EXPECT_EQ(back[i].channels, layers[i].channels) << layers[i].name;
        EXPECT_EQ(back[i].image.channels, layers[i].image.channels);
        EXPECT_EQ(back[i].image.data, layers[i].image.data) << layers[i].name;
    }
    bool found = false;
    for (const ImageAttribute& a : read_image_attributes(path))
        found = found || (a.name == "pellucid:spp" && std::get<int64_t>(a.value) == 7);
    EXPECT_TRUE(found);
    // All channels as one image: 3 + 3 + 3 + 1 + 2 + 5.
    EXPECT_EQ(read_image_channels(path).channels, 17);
}

TEST(ImageLayers, AnyChannelCountAndAlphaSurvive) {
    const std::string exr = temp_path("seven.exr");
    Image seven = ramp(4, 2, 7, 0.5f);
    write_image_file(exr, seven);
    Image back = read_image_channels(exr);
    EXPECT_EQ(back.channels, 7);
    EXPECT_EQ(back.data, seven.data);
    // 8-bit RGBA: alpha is stored linearly (not sRGB-encoded) and read back.
    const std::string png = temp_path("rgba.png");
    Image rgba(2, 1, 4);
    rgba.data = {1.f, 0.f, 0.f, 0.5f, 0.f, 1.f, 0.f, 0.25f};
    write_image_file(png, rgba);
    Image p = read_image_channels(png);
    ASSERT_EQ(p.channels, 4);
    EXPECT_NEAR(p.data[3], 128.f / 255.f, 1e-6);
    EXPECT_NEAR(p.data[7], 64.f / 255.f, 1e-6);
    EXPECT_NEAR(p.data[0], 1.f, 1e-6);
    EXPECT_EQ(read_image_file(png).channels, 3);  // textures still read RGB
    EXPECT_NE(error_of([&] { write_image_file(temp_path("seven.png"), seven); }).find("holds 1 to 4 channels, the image has 7"),
              std::string::npos);
}

TEST(ImageLayers, BadLayersAreErrorsNamingThePath) {
    const std::string path = temp_path("bad.exr");
    EXPECT_EQ(error_of([&] { write_layers_file(temp_path("x.png"), {{"", {"R", "G", "B"}, Image(2, 2, 3)}}); }),
              temp_path("x.png") + ": layers (AOVs) are written to one multi-layer OpenEXR file: use a .exr path");
    EXPECT_EQ(error_of([&] {
                  write_layers_file(path, {{"", {"R", "G", "B"}, Image(2, 2, 3)}, {"depth", {"Z"}, Image(3, 2, 1)}});
              }),
              path + ": layer 'depth' is 3x2, the first layer 2x2");
    EXPECT_EQ(error_of([&] {
                  write_layers_file(path, {{"a", {"R", "G", "B"}, Image(2, 2, 3)}, {"a", {"R"}, Image(2, 2, 1)}});
              }),
              path + ": channel 'a.R' appears twice");
    EXPECT_EQ(error_of([&] { write_layers_file(path, {{"a", {"R", "G"}, Image(2, 2, 3)}}); }),
              path + ": layer 'a' has 3 channels but 2 channel names");
}
