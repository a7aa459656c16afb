// Image textures kept in memory, looked up over a lane type F (simd/lane.h): the bilinear value
// and its (s, t) derivatives with the Repeat wrap, as texture_system.cpp's lookups compute them
// (texel_floor, wrap_texel, memory_bilinear), so that each lane gives the bits of a one-lane lookup.
// The path tracer's packet pass evaluates the textures of the materials PathSetup::tex_lanes lists
// with these.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include "pellucid/math/lane_types.h"
#include "pellucid/simd/lane.h"

namespace pellucid {

/// An image as a lane lookup reads it: width × height texels of n floats (1, or 3 for RGB), rows
/// from the top (ImageTextureHandle::texels); width·height·n < 2³¹, so that indices fit an int32.
struct LaneImage {
    const float* texels = nullptr;
    int width = 0, height = 0, n = 1;
};

/// The bilinear interpolation of four texels (row t0: v00, v01; row t1: v10, v11) at fractions
/// (sf, tf), in OIIO's order of operations (memory_bilinear).
template <class F>
inline F bilinear_mix(const F& v00, const F& v01, const F& v10, const F& v11, const F& sf, const F& tf) {
    const F s1 = F(1.f) - sf, t1 = F(1.f) - tf;
    return t1 * (v00 * s1 + v01 * sf) + tf * (v10 * s1 + v11 * sf);
}
/// Its derivatives in s and t, for a width × height image (memory_bilinear's dvalue_ds, dvalue_dt).
template <class F>
inline void bilinear_derivatives(const F& v00, const F& v01, const F& v10, const F& v11, const F& sf, const F& tf,
                                 float width, float height, F* ds, F* dt) {
    const F s1 = F(1.f) - sf, t1 = F(1.f) - tf;
    *ds = F(width) * ((v01 - v00) * t1 + (v11 - v10) * tf);
    *dt = F(height) * ((v10 - v00) * s1 + (v11 - v01) * sf);
}

/// The texel below st of a row (or column) of n texels, wrapped by Repeat into [0, n), and the
/// fraction beyond it: texel_floor (x = st·n − ½, clamped to ±2²⁹, its floor and fraction) then
/// wrap_texel's Repeat (x mod n). x's floor is an integer float, so the quotient by n rounds to at
/// most one above its floor; the remainder is then below 0 and takes n back.
template <class F>
inline IntT<F> repeat_texel(const F& st, int n, F* frac) {
    using I = IntT<F>;
    constexpr float kLimit = 536870912.f;  // 2²⁹
    F x = st * F(float(n)) - F(0.5f);
    x = lane::select(lane::abs(x) < F(kLimit), x, lane::select(x > F(0.f), F(kLimit), F(-kLimit)));
    const F f = lane::floor(x);
    *frac = x - f;
    const I q = lane::to_int(lane::floor(f / F(float(n))));
    const I r = lane::to_int(f) - q * I(n);
    return lane::select(r < I(0), r + I(n), r);
}

/// Image `im` at (s, t), bilinear with the Repeat wrap: each channel's value (a one-channel image
/// in all three, as its Spectrum) and, where ds and dt are given, its derivatives in s and t.
template <class F>
inline void lane_bilinear(const LaneImage& im, const F& s, const F& t, RGB<F>* value, RGB<F>* ds = nullptr,
                          RGB<F>* dt = nullptr) {
    using I = IntT<F>;
    F sf, tf;
    const I s0 = repeat_texel<F>(s, im.width, &sf), t0 = repeat_texel<F>(t, im.height, &tf);
    const I s1 = lane::select(s0 + I(1) == I(im.width), I(0), s0 + I(1));
    const I t1 = lane::select(t0 + I(1) == I(im.height), I(0), t0 + I(1));
    const I row0 = t0 * I(im.width), row1 = t1 * I(im.width), n(im.n);
    const I k00 = (row0 + s0) * n, k01 = (row0 + s1) * n, k10 = (row1 + s0) * n, k11 = (row1 + s1) * n;
    F v[3], d_s[3], d_t[3];
    for (int c = 0; c < im.n; ++c) {
        const F v00 = lane::gather(im.texels, k00 + I(c)), v01 = lane::gather(im.texels, k01 + I(c));
        const F v10 = lane::gather(im.texels, k10 + I(c)), v11 = lane::gather(im.texels, k11 + I(c));
        v[c] = bilinear_mix<F>(v00, v01, v10, v11, sf, tf);
        if (ds) bilinear_derivatives<F>(v00, v01, v10, v11, sf, tf, float(im.width), float(im.height), &d_s[c], &d_t[c]);
    }
    const int g = im.n >= 3 ? 1 : 0, b = im.n >= 3 ? 2 : 0;
    *value = RGB<F>(v[0], v[g], v[b]);
    if (ds) {
        *ds = RGB<F>(d_s[0], d_s[g], d_s[b]);
        *dt = RGB<F>(d_t[0], d_t[g], d_t[b]);
    }
}
}  // namespace pellucid
