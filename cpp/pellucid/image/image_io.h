// Image files through OpenImageIO (the only OIIO user).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <string>

#include "pellucid/image/image.h"

namespace pellucid {
/// Write by extension: .exr/.hdr keep linear float values; .png/.jpg/.tif(8-bit) are clamped and
/// encoded with the sRGB transfer curve. Throws pellucid::Error naming the path on failure.
void write_image_file(const std::string& path, const Image& img);
/// Read any format OIIO knows as linear float RGB (8-bit files are decoded from sRGB; one channel
/// is replicated, alpha dropped). Throws pellucid::Error naming the path on failure.
Image read_image_file(const std::string& path);
}  // namespace pellucid
