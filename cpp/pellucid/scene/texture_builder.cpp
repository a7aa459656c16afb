// Texture builders: parameters, validation, file resolution.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/scene/texture_builder.h"

#include <initializer_list>

#include "pellucid/scene/registry.h"
#include "pellucid/util/error.h"

namespace pellucid {
namespace {
UVTransform read_to_uv(Properties& p) { return UVTransform::from(p.get_transform("to_uv")); }
}  // namespace

void TextureBuilder::build_named(const Node& textures, const std::string& path) {
    if (!textures.is_object())
        throw Error(format_error(m_ctx.source, path, std::string("expected an object of named textures, got a ") +
                                                          textures.kind_name()));
    for (const auto& [name, node] : textures.members()) m_named[name] = texture(node, path_join(path, name));
}

bool TextureBuilder::is_texture(const Node& v, bool names_ok) const {
    if (v.is_object()) return v.find("type") != nullptr;
    return names_ok && v.is_string() && m_named.count(v.as_string());
}

uint32_t TextureBuilder::add(Texture t) {
    m_list.push_back(std::move(t));
    return uint32_t(m_list.size() - 1);
}

uint32_t TextureBuilder::texture(const Node& value, const std::string& path, bool linear) {
    if (value.is_string()) {
        auto it = m_named.find(value.as_string());
        if (it == m_named.end()) {
            std::string names;
            for (const auto& [k, v] : m_named) names += (names.empty() ? "" : ", ") + k;
            throw Error(format_error(m_ctx.source, path, "no texture '" + value.as_string() + "'" +
                                                              (names.empty() ? "" : " (known: " + names + ")")));
        }
        return it->second;
    }
    Properties p(value, m_ctx.source, path);
    std::string type = p.type();
    auto it = texture_registry().find(type);
    if (it == texture_registry().end()) {
        std::vector<std::string> names;
        for (const auto& [k, v] : texture_registry()) names.push_back(k);
        p.fail("type", unknown_type_message("texture", type, names));
    }
    bool saved = m_linear;
    m_linear = linear;
    Texture t = it->second(p, *this);
    m_linear = saved;
    p.check_unqueried();
    return add(std::move(t));
}

uint32_t TextureBuilder::texture_or_constant(Properties& p, const std::string& key, const Spectrum& def) {
    const Node* n = p.get_node(key);
    if (n && is_texture(*n, true)) return texture(*n, p.key_path(key), m_linear);
    return add(ConstantTexture{p.get_spectrum(key, def)});
}

Texture build_image_texture(Properties& p, TextureBuilder& b) {
    ImageTexture t;
    std::string file = b.context().resolve(p.get_string("filename"));
    std::string filter = p.get_choice("filter", "anisotropic", "filter", {"anisotropic", "trilinear", "bilinear", "nearest"});
    t.filter = filter == "anisotropic" ? TextureFilter::Anisotropic
               : filter == "trilinear" ? TextureFilter::Trilinear
               : filter == "bilinear"  ? TextureFilter::Bilinear
                                       : TextureFilter::Nearest;
    std::string wrap = p.get_choice("wrap_mode", "repeat", "wrap mode", {"repeat", "mirror", "clamp", "black"});
    t.wrap = wrap == "repeat" ? TextureWrap::Repeat
             : wrap == "mirror" ? TextureWrap::Mirror
             : wrap == "clamp"  ? TextureWrap::Clamp
                                : TextureWrap::Black;
    std::string cs = p.get_choice("color_space", b.linear_images() ? "linear" : "auto", "color space", {"auto", "srgb", "linear"});
    TextureColorSpace space = cs == "srgb" ? TextureColorSpace::SRGB
                              : cs == "linear" ? TextureColorSpace::Linear
                                               : TextureColorSpace::Auto;
    t.to_uv = read_to_uv(p);
    try {
        t.handle = open_image_texture(file, space, nullptr);
    } catch (const Error& e) {
        p.fail("filename", e.what());
    }
    return t;
}

Texture build_checkerboard_texture(Properties& p, TextureBuilder&) {
    CheckerboardTexture t;
    t.color0 = p.get_spectrum("color0", t.color0);
    t.color1 = p.get_spectrum("color1", t.color1);
    t.filtered = p.get_bool("filtered", true);
    t.to_uv = read_to_uv(p);
    return t;
}

Texture build_noise_texture(Properties& p, TextureBuilder&) {
    NoiseTexture t;
    t.fbm = p.get_choice("variant", "perlin", "variant", {"perlin", "fbm"}) == "fbm";
    t.scale = p.get_float("scale", 1.f);
    if (!(t.scale > 0.f)) p.fail("scale", "value " + format_float(t.scale) + " must be > 0");
    t.octaves = p.get_int("octaves", 6);
    if (t.octaves < 1 || t.octaves > 16) p.fail("octaves", "value " + std::to_string(t.octaves) + " must be in [1, 16]");
    t.roughness = p.check_range("roughness", p.get_float("roughness", 0.5f), 0.f, 1.f);
    t.color0 = p.get_spectrum("color0", t.color0);
    t.color1 = p.get_spectrum("color1", t.color1);
    t.to_local = p.get_transform("to_world").inverse();
    return t;
}

Texture build_scale_texture(Properties& p, TextureBuilder& b) {
    ScaleTexture t;
    if (!p.has("texture")) p.fail("", "missing required key 'texture'");
    t.texture = b.texture_or_constant(p, "texture", Spectrum(1.f));
    t.scale = p.get_spectrum("scale", Spectrum(1.f));
    return t;
}

Texture build_mix_texture(Properties& p, TextureBuilder& b) {
    MixTexture t;
    t.texture0 = b.texture_or_constant(p, "texture0", Spectrum(0.f));
    t.texture1 = b.texture_or_constant(p, "texture1", Spectrum(1.f));
    t.amount = b.texture_or_constant(p, "amount", Spectrum(0.5f));
    return t;
}
}  // namespace pellucid
