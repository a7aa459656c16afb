// Texture builders: parameters, validation, file resolution.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/scene/texture_builder.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <sstream>

#include "pellucid/scene/registry.h"
#include "pellucid/util/error.h"
#include "pellucid/util/log.h"

namespace pellucid {
namespace {
UVTransform read_to_uv(Properties& p) { return UVTransform::from(p.get_transform("to_uv")); }

/// Per channel: the smallest and largest of a·b over a ∈ [a0, a1], b ∈ [b0, b1].
void interval_product(float a0, float a1, float b0, float b1, float& lo, float& hi) {
    const float c[4] = {a0 * b0, a0 * b1, a1 * b0, a1 * b1};
    lo = *std::min_element(c, c + 4);
    hi = *std::max_element(c, c + 4);
}

/// The range of lerp(c0, c1, w) for w ∈ [0, 1] (checkerboard, noise): each channel between the two.
TextureRange two_colour_range(const Spectrum& c0, const Spectrum& c1, const std::string& path) {
    TextureRange r;
    float lo = INFINITY, hi = -INFINITY;
    for (int c = 0; c < 3; ++c) {
        r.lo[c] = std::min(c0[c], c1[c]);
        r.hi[c] = std::max(c0[c], c1[c]);
        if (r.lo[c] < lo) lo = r.lo[c], r.lo_from = path_join(path, c0[c] <= c1[c] ? "color0" : "color1");
        if (r.hi[c] > hi) hi = r.hi[c], r.hi_from = path_join(path, c0[c] >= c1[c] ? "color0" : "color1");
    }
    return r;
}

std::string number(float v) {
    std::ostringstream os;
    os << v;
    return os.str();
}
}  // namespace

uint32_t TextureBuilder::add(Texture t, const std::string& path) {
    TextureRange r = std::visit([&](const auto& x) -> TextureRange {
        using T = std::decay_t<decltype(x)>;
        TextureRange out;
        if constexpr (std::is_same_v<T, ConstantTexture>) {
            out = {x.value, x.value, path, path};
        } else if constexpr (std::is_same_v<T, ImageTexture>) {
            auto it = m_image_ranges.find(x.handle.handle);
            PELLUCID_CHECK(it != m_image_ranges.end(), "image texture without a recorded texel range");
            out = it->second;
        } else if constexpr (std::is_same_v<T, CheckerboardTexture> || std::is_same_v<T, NoiseTexture>) {
            out = two_colour_range(x.color0, x.color1, path);
        } else if constexpr (std::is_same_v<T, ScaleTexture>) {
            const TextureRange& a = m_ranges.at(x.texture);
            out.lo_from = out.hi_from = path;
            for (int c = 0; c < 3; ++c) interval_product(a.lo[c], a.hi[c], x.scale[c], x.scale[c], out.lo[c], out.hi[c]);
        } else {  // mix: t0·(1 − a) + t1·a, a the amount's channel average; linear in each, so the
                  // extremes lie at the corners of the box of the three ranges
            const TextureRange &t0 = m_ranges.at(x.texture0), &t1 = m_ranges.at(x.texture1), &am = m_ranges.at(x.amount);
            const float a[2] = {am.lo.average(), am.hi.average()};
            out.lo_from = out.hi_from = path;
            for (int c = 0; c < 3; ++c) {
                out.lo[c] = INFINITY;
                out.hi[c] = -INFINITY;
                for (float w : a)
                    for (float v0 : {t0.lo[c], t0.hi[c]})
                        for (float v1 : {t1.lo[c], t1.hi[c]}) {
                            const float v = v0 * (1.f - w) + v1 * w;
                            out.lo[c] = std::min(out.lo[c], v);
                            out.hi[c] = std::max(out.hi[c], v);
                        }
            }
        }
        return out;
    }, t);
    for (int c = 0; c < 3; ++c)
        if (!std::isfinite(r.lo[c]) || !std::isfinite(r.hi[c]))
            throw Error(format_error(m_ctx.source, path, "the texture's values overflow a 32-bit float (up to " +
                                                             number(std::max(std::fabs(r.lo[c]), std::fabs(r.hi[c]))) + ")"));
    m_list.push_back(std::move(t));
    m_ranges.resize(m_list.size());
    m_ranges.back() = std::move(r);
    return uint32_t(m_list.size() - 1);
}

void TextureBuilder::check_range(uint32_t id, const std::string& path, float lo, float hi, bool average,
                                 bool clamp_high) const {
    const TextureRange& r = m_ranges.at(id);
    const float vlo = average ? r.lo.average() : std::min({r.lo[0], r.lo[1], r.lo[2]});
    const float vhi = average ? r.hi.average() : std::max({r.hi[0], r.hi[1], r.hi[2]});
    const std::string what = average ? "the texture's channel average reaches " : "the texture reaches ";
    const std::string range = "[" + number(lo) + ", " + number(hi) + "]";
    if (!(vlo >= lo)) {
        if (clamp_high)
            throw Error(format_error(m_ctx.source, path, what + number(vlo) + " (from " + r.lo_from + "); it must be >= " + number(lo)));
        throw Error(format_error(m_ctx.source, path, what + number(vlo) + " (from " + r.lo_from + "), out of range " + range));
    }
    if (!(vhi <= hi)) {
        if (!clamp_high)
            throw Error(format_error(m_ctx.source, path, what + number(vhi) + " (from " + r.hi_from + "), out of range " + range));
        log_warning(format_error(m_ctx.source, path, what + number(vhi) + " (from " + r.hi_from + "); values above " +
                                                         number(hi) + " are clamped to " + number(hi)));
    }
}

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
    return add(std::move(t), path);
}

uint32_t TextureBuilder::texture_or_constant(Properties& p, const std::string& key, const Spectrum& def) {
    const Node* n = p.get_node(key);
    if (n && is_texture(*n, true)) return texture(*n, p.key_path(key), m_linear);
    return add(ConstantTexture{p.get_spectrum(key, def)}, p.key_path(key));
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
    ImageTextureInfo info;
    try {
        t.handle = open_image_texture(file, space, &info);
    } catch (const Error& e) {
        p.fail("filename", e.what());
    }
    b.set_image_range(t.handle, TextureRange{info.lo, info.hi, file, file});
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
    b.check_range(t.amount, p.key_path("amount"), 0.f, 1.f, true, false);
    return t;
}
}  // namespace pellucid
