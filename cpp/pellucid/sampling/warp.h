// Warps from the unit square to common domains, each with its density. All pdfs are with respect to
// the natural measure of the target domain (solid angle for directions, area for disks/triangles).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include "pellucid/math/vec.h"

namespace pellucid {
Vec2f square_to_uniform_disk_concentric(Vec2f u);
float square_to_uniform_disk_concentric_pdf(Vec2f p);

/// Cosine-weighted hemisphere about +z (Malley's method); pdf = cos θ / π.
Vec3f square_to_cosine_hemisphere(Vec2f u);
float square_to_cosine_hemisphere_pdf(const Vec3f& w);

Vec3f square_to_uniform_hemisphere(Vec2f u);
float square_to_uniform_hemisphere_pdf(const Vec3f& w);

Vec3f square_to_uniform_sphere(Vec2f u);
float square_to_uniform_sphere_pdf(const Vec3f& w);

/// Uniform over the spherical cap {w : w.z ≥ cos_theta_max}.
Vec3f square_to_uniform_cone(Vec2f u, float cos_theta_max);
float square_to_uniform_cone_pdf(const Vec3f& w, float cos_theta_max);

/// Uniform barycentrics (b0, b1) over a triangle (Heitz 2019, "A Low-Distortion Map Between
/// Triangle and Square"); the area pdf is 1/area of the triangle.
Vec2f square_to_uniform_triangle(Vec2f u);

/// Tent on [-r, r] (1D): pdf = (r - |x|)/r².
float sample_tent(float u, float r);
float tent_pdf(float x, float r);
/// Standard normal through the inverse CDF (Giles 2010 erfinv approximation), scaled by sigma and
/// truncated to [-radius, radius].
float sample_truncated_gaussian(float u, float sigma, float radius);
/// The same with erf(radius/(σ√2)) precomputed by the caller.
float sample_truncated_gaussian(float u, float sigma, float radius, float erf_radius);
float truncated_gaussian_pdf(float x, float sigma, float radius);
}  // namespace pellucid
