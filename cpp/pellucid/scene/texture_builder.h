// Building textures from the scene description: the scene's named `textures` and textures given
// inline as material parameters. Type table: texture_registry() in registry.cpp.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "pellucid/scene/properties.h"
#include "pellucid/texture/texture.h"

namespace pellucid {

struct BuildContext;

/// The values a texture can produce, per channel, with the key path (or file) that gives the
/// smallest and the largest: the constants of checkerboard, noise, scale and mix textures, an
/// image's texel range (ImageTextureInfo), combined by interval arithmetic.
struct TextureRange {
    Spectrum lo{0.f}, hi{0.f};
    std::string lo_from, hi_from;
};

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
    /// Append `t`, built at key path `path`; its value range is derived from its parameters.
    uint32_t add(Texture t, const std::string& path);

    const TextureRange& range(uint32_t id) const { return m_ranges.at(id); }
    /// The range policy (docs/scene-format.md, "Limits and numbers"): a parameter bound to texture
    /// `id` at key path `path` accepts it only if every value the texture can produce lies in
    /// [lo, hi], as a constant must. `average`: the parameter reads the channel average. Values
    /// above `hi` are clamped with a warning instead when `clamp_high` (the parameters whose
    /// constants are clamped the same way). Throws naming the key, the value and where it comes from.
    void check_range(uint32_t id, const std::string& path, float lo, float hi, bool average, bool clamp_high) const;
    /// Record the texel range of an image texture's handle (build_image_texture).
    void set_image_range(const ImageTextureHandle& h, const TextureRange& r) { m_image_ranges[h.handle] = r; }

    const BuildContext& context() const { return m_ctx; }
    bool linear_images() const { return m_linear; }

private:
    TextureList& m_list;
    const BuildContext& m_ctx;
    std::map<std::string, uint32_t> m_named;
    std::vector<TextureRange> m_ranges;  ///< per texture of m_list
    std::map<const void*, TextureRange> m_image_ranges;
    bool m_linear = false;
};

// Builders of the registry's texture types (texture_builder.cpp); they may add child textures.
Texture build_image_texture(Properties& p, TextureBuilder& b);
Texture build_checkerboard_texture(Properties& p, TextureBuilder& b);
Texture build_noise_texture(Properties& p, TextureBuilder& b);
Texture build_scale_texture(Properties& p, TextureBuilder& b);
Texture build_mix_texture(Properties& p, TextureBuilder& b);
}  // namespace pellucid
