// Building textures from the scene description: the scene's named `textures` and textures given
// inline as material parameters. Type table: texture_registry() in registry.cpp.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <map>
#include <string>

#include "pellucid/scene/properties.h"
#include "pellucid/texture/texture.h"

namespace pellucid {

struct BuildContext;

class TextureBuilder {
public:
    TextureBuilder(TextureList& list, const BuildContext& ctx) : m_list(list), m_ctx(ctx) {}

    /// The scene's top-level `textures` object: {"name": {"type": ...}, ...}.
    void build_named(const Node& textures, const std::string& path);
    /// Is this parameter value a texture? An object with a "type", or (when `names_ok`) a string
    /// naming one of the scene's textures.
    bool is_texture(const Node& value, bool names_ok) const;
    /// Build (object) or resolve (name) the texture at `path`; returns its index in the list.
    /// `linear` makes images default to linear values (normal maps, heights).
    uint32_t texture(const Node& value, const std::string& path, bool linear = false);
    /// A parameter of a texture that is itself a texture or a constant (number / RGB triple).
    uint32_t texture_or_constant(Properties& p, const std::string& key, const Spectrum& def);
    uint32_t add(Texture t);

    const BuildContext& context() const { return m_ctx; }
    bool linear_images() const { return m_linear; }

private:
    TextureList& m_list;
    const BuildContext& m_ctx;
    std::map<std::string, uint32_t> m_named;
    bool m_linear = false;
};

// Builders of the registry's texture types (texture_builder.cpp); they may add child textures.
Texture build_image_texture(Properties& p, TextureBuilder& b);
Texture build_checkerboard_texture(Properties& p, TextureBuilder& b);
Texture build_noise_texture(Properties& p, TextureBuilder& b);
Texture build_scale_texture(Properties& p, TextureBuilder& b);
Texture build_mix_texture(Properties& p, TextureBuilder& b);
}  // namespace pellucid
