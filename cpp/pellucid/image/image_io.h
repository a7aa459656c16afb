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

/// One named layer of a multi-layer image: channel i of `image` is written as "<name>.<channels[i]>"
/// ("albedo.R", "normal.X", "depth.Z"), or as "<channels[i]>" for the unnamed layer (the beauty).
struct ImageLayer {
    std::string name;
    std::vector<std::string> channels;
    Image image;
};

/// Write by extension: .exr/.hdr keep linear float values; .png/.jpg/.tif(8-bit) are clamped and
/// encoded with the sRGB transfer curve (alpha, the 4th of 4 or 2nd of 2 channels, stays linear).
/// Any channel count the format holds (EXR: any; PNG: 1 to 4). Missing parent folders are created. `attributes` go into
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
/// is replicated, alpha dropped): what textures and environment maps read. Throws pellucid::Error
/// naming the path on failure.
Image read_image_file(const std::string& path);
/// Read every channel of an image file, in the file's order, as linear float (8-bit files are
/// decoded from sRGB except their alpha channel; colour is not multiplied by alpha, so what
/// write_image_file wrote reads back). Throws pellucid::Error naming the path.
Image read_image_channels(const std::string& path);
/// Write `layers` (all of one size, names unique) as one multi-layer OpenEXR file (float), with
/// `attributes` in its header. OpenEXR stores channels sorted by name, so the written order goes
/// into the header attribute "pellucid:channels" (comma-separated full channel names). The path
/// must end in .exr. Throws pellucid::Error naming the path.
void write_layers_file(const std::string& path, const std::vector<ImageLayer>& layers,
                       const std::vector<ImageAttribute>& attributes = {});
/// Read an image file back into layers: channels are grouped by the text before their last '.'
/// ("albedo.R" → layer "albedo", channel "R"; "R" → the unnamed layer). Layers and channels come in
/// the order write_layers_file wrote them ("pellucid:channels"); for other files the unnamed layer
/// comes first, then the others in the file's order, and within a layer channels named R, G, B, A
/// or X, Y, Z, W or U, V are put in that order, others keep the file's. Throws pellucid::Error
/// naming the path.
std::vector<ImageLayer> read_layers_file(const std::string& path);
}  // namespace pellucid
