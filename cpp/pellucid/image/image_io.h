// Image files through OpenImageIO (the only OIIO user).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include "pellucid/image/image.h"

namespace pellucid {
/// One header attribute of an image file (an EXR attribute, a PNG text chunk, ...).
struct ImageAttribute {
    std::string name;
    std::variant<int64_t, double, std::string> value;
};

/// Write by extension: .exr/.hdr keep linear float values; .png/.jpg/.tif(8-bit) are clamped and
/// encoded with the sRGB transfer curve. Missing parent folders are created. `attributes` go into
/// the header where the format has one (integers that fit 32 bits as int, larger ones as strings).
/// Throws pellucid::Error naming the path on failure.
void write_image_file(const std::string& path, const Image& img, const std::vector<ImageAttribute>& attributes = {});
/// What write_image_file checks before it writes, for a front end to call before rendering: the
/// extension names a format OpenImageIO can write, missing parent folders are created, and the folder
/// is writable. Throws pellucid::Error naming the path.
void check_image_output(const std::string& path);
/// The header attributes of an image file (numbers as int64 or double, the rest as strings).
std::vector<ImageAttribute> read_image_attributes(const std::string& path);
/// Read any format OIIO knows as linear float RGB (8-bit files are decoded from sRGB; one channel
/// is replicated, alpha dropped). Throws pellucid::Error naming the path on failure.
Image read_image_file(const std::string& path);
}  // namespace pellucid
