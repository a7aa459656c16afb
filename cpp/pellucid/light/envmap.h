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
// Sampling: a piecewise-constant Distribution2D over the W × (H − 1) interpolation cells, each
// weighted by the exact integral of the channel-averaged bilinear radiance times sin θ over the
// cell; inside a cell (u, v) is uniform. The solid-angle density is p(u, v) / (2π² sin θ)
// (pbrt-v4 §12.5.2, eq. 12.24: dω = sin θ dθ dφ = 2π² sin θ du dv).
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "pellucid/image/image.h"
#include "pellucid/light/light_types.h"
#include "pellucid/math/transform.h"
#include "pellucid/sampling/distribution_2d.h"

namespace pellucid {

class EnvmapLight {
public:
    /// image: linear RGB radiance, width ≥ 2, height ≥ 3, finite and ≥ 0 (the builder checks);
    /// rotation: the orthonormal linear part of to_world.
    EnvmapLight(const Image& image, float scale, const Mat3f& rotation, std::string name = "");

    /// Radiance arriving along -dir from direction dir (world, unit).
    Spectrum Le(const Vec3f& dir) const { return lookup(direction_to_uv(to_local(dir))); }
    std::optional<LightLiSample> sample_li(const LightSampleContext& ctx, Vec2f u) const;
    /// Solid-angle density with which sample_li produces direction wi (world, unit).
    float pdf_li(const LightSampleContext& ctx, const Vec3f& wi) const;
    /// Power through a disk of the scene's bounding radius: π r² ∫ L̄(ω) dω (as ConstantLight).
    float power(float scene_radius) const;
    /// ∫ over the sphere of the channel-averaged radiance (exact for the bilinear radiance).
    double integral() const { return m_integral; }
    std::string to_string() const;

    /// Mitsuba 3's lat-long mapping in the map's frame (see the header comment).
    static Vec3f uv_to_direction(Vec2f uv, float* sin_theta = nullptr);
    static Vec2f direction_to_uv(const Vec3f& d);
    /// Bilinear radiance at (u, v) ∈ [0,1]² of the map's frame.
    Spectrum lookup(Vec2f uv) const;

private:
    Vec3f to_local(const Vec3f& w) const { return glm::transpose(m_rot) * w; }
    float half_texel() const { return 0.5f / float(m_w); }

    int m_w = 0, m_h = 0;
    std::vector<Spectrum> m_texels;  ///< m_h rows of m_w texels, scale applied
    Distribution2D m_dist;           ///< over (u − half texel, v): m_w × (m_h − 1) cells
    Mat3f m_rot{1.f};
    double m_integral = 0.0;
    std::string m_name;
};
}  // namespace pellucid
