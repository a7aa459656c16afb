// Typed material parameters: `Tex<float>` and `Tex<Spectrum>`, a constant or a texture, and
// `TexEval`, the evaluation of such parameters at one hit (or of their constants, at load).
// SPDX-License-Identifier: Apache-2.0
//
// A material is a plain Params struct whose varying fields are Tex<T> (material/material.h). The
// builders (material/builders.cpp) fill a Tex with the key's constant, or bind it to a texture of
// the scene with the parameter's valid range; the one function per model that builds its BxDF
// (make_bxdf) reads every Tex through a TexEval. At load, TexEval{} yields the constants (the
// scene's prebuilt BxDF of an untextured material); at a hit of a textured material, a TexEval over
// the scene's textures and the hit's lookup context yields the texture values, clamped into the
// parameter's range and mapped (perceptual roughness r → α = r²).
#pragma once
#include <cstdint>

#include "pellucid/math/constants.h"
#include "pellucid/math/spectrum.h"
#include "pellucid/texture/texture.h"

namespace pellucid {

/// How a texture value maps into the parameter: Square is perceptual roughness r → α = r²
/// (Burley 2012 §5.4), applied after the clamp into [lo, hi].
enum class TexMap : uint8_t { Identity, Square };

/// A material parameter of type T (float or Spectrum): `value`, or texture `texture` of the scene's
/// TextureList when bound (texture ≥ 0). A bound parameter keeps its default as `value`, which is
/// what interfaces without textures (TexEval{}) read.
template <class T>
struct Tex {
    T value{};
    int32_t texture = -1;
    TexMap map = TexMap::Identity;
    float lo = 0.f, hi = 1.f;  ///< the parameter's valid range; texture values are clamped into it

    Tex() = default;
    Tex(const T& v) : value(v) {}  // NOLINT: a constant is a Tex
    bool textured() const { return texture >= 0; }
};

/// Evaluates Tex parameters: constants only (default-constructed), or at one hit.
class TexEval {
public:
    TexEval() = default;
    TexEval(const TextureList& textures, const TextureEvalContext& ctx) : m_textures(&textures), m_ctx(&ctx) {}

    float operator()(const Tex<float>& t) const {
        if (!t.textured() || !m_textures) return t.value;
        // A float parameter reads its texture's channel average.
        float f = clamp(eval_texture(*m_textures, uint32_t(t.texture), *m_ctx).average(), t.lo, t.hi);
        return t.map == TexMap::Square ? f * f : f;
    }
    Spectrum operator()(const Tex<Spectrum>& t) const {
        if (!t.textured() || !m_textures) return t.value;
        Spectrum v = eval_texture(*m_textures, uint32_t(t.texture), *m_ctx);
        for (int c = 0; c < 3; ++c) v[c] = clamp(v[c], t.lo, t.hi);
        return v;
    }

private:
    const TextureList* m_textures = nullptr;
    const TextureEvalContext* m_ctx = nullptr;
};
}  // namespace pellucid
