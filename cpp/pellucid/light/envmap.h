// Environment map: radiance at infinity from a latitude-longitude image, importance-sampled.
// SPDX-License-Identifier: Apache-2.0
//
// | parameter | type      | default  | meaning                                                      |
// |-----------|-----------|----------|--------------------------------------------------------------|
// | filename  | string    | required | lat-long image (EXR/HDR; 8-bit files are decoded from sRGB), relative to the scene file; at least 2×3 pixels, values finite and ≥ 0 |
// | scale     | float     | 1        | factor applied to the image's radiance, ≥ 0                  |
// | to_world  | transform | identity | rotation from the map's frame to world (a rotation, optionally uniformly scaled) |
// JSON: "lights": [{"type": "envmap", "filename": "sky.exr", "scale": 2,
//                   "to_world": [{"rotate": {"axis": [1, 0, 0], "angle": -90}}]}]
//
// Mapping (Mitsuba 3's envmap, so scenes import unchanged): in the map's frame +y is up; a direction
// d = (sin φ sin θ, cos θ, −cos φ sin θ) has u = φ/2π (image column) and v = θ/π (image row, row 0 at
// +y). Radiance is bilinear between texels, with column x centred at u = (x + ½)/W (wrapping in u)
// and row y centred at v = y/(H − 1), so the first and last rows sit on the poles.
//
// Sampling: the density in (u, v) follows g = Y sin θ (Y the texel's luminance, Rec. 709 weights)
// interpolated bilinearly between the texels, as the radiance is, so that it is proportional to
// the luminance times sin θ up to the interpolation of the product (Mitsuba 3's envmap samples the
// same interpolant). A cell of the W × (H − 1) interpolation cells is chosen by the mean of g at its
// four corners (sampling/piecewise_2d.h, float CDFs), and the point placed in it by the bilinear
// density through them (sample_bilinear); the density in (u, v) is the cell's times
// bilinear_density. The solid-angle density is p(u, v) / (2π² sin θ) (pbrt-v4 §12.5.2, eq. 12.24:
// dω = sin θ dθ dφ = 2π² sin θ du dv); g vanishes on the pole rows, so it stays finite there.
// Against a density constant inside each cell and weighted by the channel average, the per-pixel
// variance of bench/suite/aniso_metal.json falls by a fifth (bench/README.md, "Environment map
// sampling").
//
// Sampling, its density and the radiance are written once over a lane type F (simd/lane.h):
// EnvmapLight's sample_li, pdf_li, Le and lookup are the float instantiation, and the packet path
// tracer runs the same templates on its lanes (light/light_table.h). They use IEEE-exact lane
// operations only, and no libm: the angles come from detail::sincos_two_pi (warp.h) and
// lane_math::atan2_t (math/lane_atan.h), so every lane gives the bits of the float instantiation.
#pragma once
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "pellucid/image/image.h"
#include "pellucid/light/light_types.h"
#include "pellucid/math/constants.h"
#include "pellucid/math/lane_atan.h"
#include "pellucid/math/lane_types.h"
#include "pellucid/math/transform.h"
#include "pellucid/sampling/piecewise_2d.h"
#include "pellucid/sampling/warp.h"

namespace pellucid {

/// An environment map as lanes read it: the sampling distribution and the texels in one float
/// buffer (by offsets, per lane), the image size and the rotation to world (column-major:
/// rot[3c + k] is row k of column c).
template <class F>
struct EnvmapLanes {
    Piecewise2DLanes<F> dist;  ///< over (u − half texel, v): w × (h − 1) cells
    /// Offset of texel (0, 0)'s red: texel (x, y) at texels + 3(y·w + x), g (x, y) at
    /// texels + 3·w·h + y·w + x, the density of cell (i, j) (piecewise_2d_cell_pdf) at texels + 4·w·h + j·w + i.
    IntT<F> texels;
    IntT<F> w, h;
    F rot[9];
};

template <class F>
struct EnvmapSampleT {
    MaskT<F> valid;
    V3<F> wi;  ///< world, unit
    F pdf;     ///< solid angle
    RGB<F> L;
};

/// Mitsuba 3's lat-long mapping in the map's frame (see the header comment): the direction of
/// (u, v) ∈ [0,1)×[0,1], and sin θ.
template <class F>
inline V3<F> envmap_uv_to_direction(const V2<F>& uv, F* sin_theta) {
    F cp, sp, ct, st;
    detail::sincos_two_pi<F>(uv.x, &cp, &sp);              // φ = 2π u
    detail::sincos_two_pi<F>(uv.y * F(0.5f), &ct, &st);  // θ = π v = 2π (v/2)
    *sin_theta = st;
    return V3<F>(sp * st, ct, lane::neg(cp) * st);
}
/// (u, v) of a unit direction d of the map's frame, u ∈ [0, 1); sin_theta = √(d.x² + d.z²).
template <class F>
inline V2<F> envmap_direction_to_uv(const V3<F>& d, const F& sin_theta) {
    F u = lane_math::atan2_t<F>(d.x, lane::neg(d.z)) * F(kInv2Pi);
    u = lane::select(u < F(0.f), u + F(1.f), u);
    u = lane::select(u < F(1.f), u, F(0.f));
    const F v = lane_math::atan2_t<F>(sin_theta, d.y) * F(kInvPi);
    return V2<F>{u, v};
}

/// Bilinear radiance at (u, v) ∈ [0,1]² of the map's frame (column x centred at u = (x + ½)/w,
/// wrapping; row y at v = y/(h − 1)).
template <class F>
inline RGB<F> envmap_lookup(const EnvmapLanes<F>& e, const V2<F>& uv) {
    using I = IntT<F>;
    const F fw = lane::to_float(e.w), fh = lane::to_float(e.h);
    F s = uv.x - F(0.5f) / fw;
    s = s - lane::floor(s);
    s = lane::select(s > F(0.f), s, F(0.f));  // (NaN to 0: every texel index stays inside the map)
    const F v = lane::select(uv.y > F(0.f), lane::select(uv.y < F(1.f), uv.y, F(1.f)), F(0.f));
    const F fx = s * fw, fy = v * (fh - F(1.f));
    const I x0 = lane::min(detail::whole_to_int<F>(lane::floor(fx)), e.w - I(1));
    const I y0 = lane::min(detail::whole_to_int<F>(lane::floor(fy)), e.h - I(2));
    const F wx = fx - lane::to_float(x0), wy = fy - lane::to_float(y0);
    const auto wraps = x0 + I(1) >= e.w;
    const I x1 = lane::select(wraps, I(0), x0 + I(1));
    const I r0 = e.texels + I(3) * (y0 * e.w), r1 = r0 + I(3) * e.w;
    const I a = r0 + I(3) * x0, b = r0 + I(3) * x1, c = r1 + I(3) * x0, d = r1 + I(3) * x1;
    const float* t = e.dist.base;
    const F ox = F(1.f) - wx, oy = F(1.f) - wy;
    // The texels (x0, y0), (x0 + 1, y0) are six consecutive floats, as are those of row y0 + 1:
    // each lane reads the two runs as rows (lane::gather_rows; the buffer goes on past the texels,
    // with g), and the lanes whose x0 + 1 wraps to column 0 take their second texels by gathers.
    F top_row[8], bottom_row[8];
    lane::gather_rows<8>(t, a, top_row);
    lane::gather_rows<8>(t, c, bottom_row);
    if (lane::any(wraps)) {
        const MaskT<F> wf = lane::float_mask(wraps);
        for (int k = 0; k < 3; ++k) {
            top_row[3 + k] = lane::select(wf, lane::gather(t, b + I(k)), top_row[3 + k]);
            bottom_row[3 + k] = lane::select(wf, lane::gather(t, d + I(k)), bottom_row[3 + k]);
        }
    }
    auto channel = [&](int k) {
        const F top = top_row[k] * ox + top_row[3 + k] * wx;
        const F bottom = bottom_row[k] * ox + bottom_row[3 + k] * wx;
        return top * oy + bottom * wy;
    };
    return RGB<F>(channel(0), channel(1), channel(2));
}

/// The map's frame from world (the transpose of the rotation) and back.
template <class F>
inline V3<F> envmap_to_local(const EnvmapLanes<F>& e, const V3<F>& w) {
    const F* r = e.rot;
    return V3<F>(r[0] * w.x + r[1] * w.y + r[2] * w.z, r[3] * w.x + r[4] * w.y + r[5] * w.z,
                 r[6] * w.x + r[7] * w.y + r[8] * w.z);
}
template <class F>
inline V3<F> envmap_to_world(const EnvmapLanes<F>& e, const V3<F>& d) {
    const F* r = e.rot;
    return V3<F>(r[0] * d.x + r[3] * d.y + r[6] * d.z, r[1] * d.x + r[4] * d.y + r[7] * d.z,
                 r[2] * d.x + r[5] * d.y + r[8] * d.z);
}

/// Radiance arriving along −wi from world direction wi (unit).
template <class F>
inline RGB<F> envmap_Le(const EnvmapLanes<F>& e, const V3<F>& wi) {
    const V3<F> d = envmap_to_local<F>(e, wi);
    return envmap_lookup<F>(e, envmap_direction_to_uv<F>(d, lane::sqrt(d.x * d.x + d.z * d.z)));
}

namespace envmap_detail {
/// g at the corners of cell (i, j): texels (i, j), (i + 1, j) (wrapping), (i, j + 1), (i + 1, j + 1).
template <class F>
inline void cell_corners(const EnvmapLanes<F>& e, const IntT<F>& i, const IntT<F>& j, F* a, F* b, F* c, F* d) {
    using I = IntT<F>;
    const I g0 = e.texels + I(3) * (e.w * e.h) + j * e.w, g1 = g0 + e.w;
    const I i1 = lane::select(i + I(1) < e.w, i + I(1), I(0));
    const float* t = e.dist.base;
    *a = lane::gather(t, g0 + i), *b = lane::gather(t, g0 + i1);
    *c = lane::gather(t, g1 + i), *d = lane::gather(t, g1 + i1);
}
}  // namespace envmap_detail

/// The solid-angle density of envmap_sample at the map-frame point uv (envmap_direction_to_uv of a
/// unit direction whose sin θ is st); 0 at the poles.
template <class F>
inline F envmap_pdf_uv(const EnvmapLanes<F>& e, const V2<F>& uv, const F& st) {
    using I = IntT<F>;
    F s = uv.x - F(0.5f) / lane::to_float(e.w);
    s = s - lane::floor(s);
    // The cell as piecewise_2d_pdf finds it, and where in it the point lies.
    auto cell = [](const F& t, const I& n, F* frac) {
        const F c = lane::select(t > F(0.f), lane::select(t < F(1.f), t, F(1.f)), F(0.f));
        const F x = c * lane::to_float(n);
        const I k = lane::min(detail::whole_to_int<F>(lane::floor(x)), n - I(1));
        *frac = lane::min(lane::max(x - lane::to_float(k), F(0.f)), F(1.f));
        return k;
    };
    F fs, ft;
    const I i = cell(s, e.dist.nu, &fs), j = cell(uv.y, e.dist.nv, &ft);
    F a, b, c, dd;
    envmap_detail::cell_corners<F>(e, i, j, &a, &b, &c, &dd);
    const F cell_pdf = lane::gather(e.dist.base, e.texels + I(4) * (e.w * e.h) + j * e.w + i);
    const F p = cell_pdf * bilinear_density<F>(fs, ft, a, b, c, dd);
    const auto ok = st > F(0.f);
    return lane::select(ok, p / (F(2.f * kPi * kPi) * lane::select(ok, st, F(1.f))), F(0.f));
}

/// Solid-angle density with which envmap_sample produces world direction wi (unit); 0 at the poles.
template <class F>
inline F envmap_pdf(const EnvmapLanes<F>& e, const V3<F>& wi) {
    const V3<F> d = envmap_to_local<F>(e, wi);
    const F st = lane::sqrt(d.x * d.x + d.z * d.z);
    return envmap_pdf_uv<F>(e, envmap_direction_to_uv<F>(d, st), st);
}

/// envmap_Le and envmap_pdf toward world direction wi (unit) together, the direction's (u, v) found
/// once (the same bits as the two calls).
template <class F>
inline RGB<F> envmap_Le_pdf(const EnvmapLanes<F>& e, const V3<F>& wi, F* pdf) {
    const V3<F> d = envmap_to_local<F>(e, wi);
    const F st = lane::sqrt(d.x * d.x + d.z * d.z);
    const V2<F> uv = envmap_direction_to_uv<F>(d, st);
    *pdf = envmap_pdf_uv<F>(e, uv, st);
    return envmap_lookup<F>(e, uv);
}

/// A direction with u ∈ [0,1)²: a cell by its weight, placed in it by the bilinear density through
/// its corners, then to world.
template <class F>
inline EnvmapSampleT<F> envmap_sample(const EnvmapLanes<F>& e, const V2<F>& u) {
    const Piecewise2DSample<F> ps = sample_piecewise_2d<F>(e.dist, u);
    F a, b, c, dd;
    envmap_detail::cell_corners<F>(e, ps.i, ps.j, &a, &b, &c, &dd);
    const V2<F> st2 = sample_bilinear<F>(ps.du, ps.dv, a, b, c, dd);
    const F pdf_uv = ps.pdf * bilinear_density<F>(st2.x, st2.y, a, b, c, dd);
    const F nu = lane::to_float(e.dist.nu), nv = lane::to_float(e.dist.nv);
    const F px = lane::min((lane::to_float(ps.i) + st2.x) / nu, F(0x1.fffffep-1f));
    const F py = lane::min((lane::to_float(ps.j) + st2.y) / nv, F(0x1.fffffep-1f));
    F ux = px + F(0.5f) / lane::to_float(e.w);
    ux = lane::select(ux < F(1.f), ux, ux - F(1.f));
    const V2<F> uv{ux, py};
    F st;
    const V3<F> d = envmap_uv_to_direction<F>(uv, &st);
    const auto ok = pdf_uv > F(0.f) && st > F(0.f);
    EnvmapSampleT<F> s;
    s.wi = normalize(envmap_to_world<F>(e, d));
    s.pdf = pdf_uv / (F(2.f * kPi * kPi) * lane::select(ok, st, F(1.f)));
    s.L = envmap_lookup<F>(e, uv);
    s.valid = ok && !is_black(s.L) && s.pdf < F(kInfinity);
    return s;
}

class EnvmapLight {
public:
    /// image: linear RGB radiance, width ≥ 2, height ≥ 3, finite and ≥ 0 (the builder checks);
    /// rotation: the orthonormal linear part of to_world.
    EnvmapLight(const Image& image, float scale, const Mat3f& rotation, std::string name = "");

    /// Radiance arriving along -dir from direction dir (world, unit).
    Spectrum Le(const Vec3f& dir) const { return envmap_Le<float>(lanes(), dir); }
    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx, Vec2f u) const;
    /// Solid-angle density with which sample_li produces direction wi (world, unit).
    float pdf_li(const LightSampleContext&, const Vec3f& wi) const { return envmap_pdf<float>(lanes(), wi); }
    /// Power through a disk of the scene's bounding radius: π r² ∫ L̄(ω) dω (as ConstantLight).
    float power(float scene_radius) const;
    /// ∫ over the sphere of the channel-averaged radiance (exact for the bilinear radiance).
    double integral() const { return m_integral; }
    std::string to_string() const;

    /// Mitsuba 3's lat-long mapping in the map's frame (see the header comment).
    static Vec3f uv_to_direction(Vec2f uv, float* sin_theta = nullptr) {
        float st;
        const Vec3f d = envmap_uv_to_direction<float>(uv, &st);
        if (sin_theta) *sin_theta = st;
        return d;
    }
    static Vec2f direction_to_uv(const Vec3f& d) {
        return envmap_direction_to_uv<float>(d, std::sqrt(d.x * d.x + d.z * d.z));
    }
    /// Bilinear radiance at (u, v) ∈ [0,1]² of the map's frame.
    Spectrum lookup(Vec2f uv) const { return envmap_lookup<float>(lanes(), uv); }

    /// The map as the lane templates read it (float instantiation).
    EnvmapLanes<float> lanes() const {
        EnvmapLanes<float> e{{m_data->data(), m_dist.marginal, m_dist.conditional, m_dist.nu, m_dist.nv},
                             m_texels, m_w, m_h, {}};
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 3; ++k) e.rot[3 * c + k] = m_rot[c][k];
        return e;
    }
    /// The buffer lanes() reads (CDFs and texels), shared so that a light table can keep it.
    const std::shared_ptr<const std::vector<float>>& data() const { return m_data; }
    const Piecewise2DLayout& layout() const { return m_dist; }
    int32_t texel_offset() const { return m_texels; }
    int width() const { return m_w; }
    int height() const { return m_h; }
    const Mat3f& rotation() const { return m_rot; }

private:
    int m_w = 0, m_h = 0;
    std::shared_ptr<const std::vector<float>> m_data;  ///< the CDFs, then m_h rows of m_w RGB texels (scale applied)
    Piecewise2DLayout m_dist;                           ///< over (u − half texel, v): m_w × (m_h − 1) cells
    int32_t m_texels = 0;
    Mat3f m_rot{1.f};
    double m_integral = 0.0;
    std::string m_name;
};
}  // namespace pellucid
