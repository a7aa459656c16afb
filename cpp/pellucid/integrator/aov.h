// AOVs (arbitrary output variables): per-pixel images besides the beauty image, and the AOV
// integrator that renders one of them instead of radiance.
// SPDX-License-Identifier: Apache-2.0
//
// What each AOV holds (docs/rendering.md, "AOVs"). "Denoiser guides" follow delta (specular) bounces
// as denoisers expect; the geometric AOVs are those of the first hit.
//
// | name         | channels          | value per camera sample                                                  | on a miss |
// |--------------|-------------------|--------------------------------------------------------------------------|-----------|
// | albedo       | albedo.R, .G, .B  | denoiser guide: along delta bounces (their sample weights multiplied),    | 0         |
// |              |                   | one BSDF sample weight f·|cos θi|/pdf at the first vertex whose sampled   |           |
// |              |                   | lobe is not delta; its mean converges to the directional albedo          |           |
// |              |                   | ∫ f |cos θi| dωi there (times the delta lobes' reflectances on the way)   |           |
// | normal       | normal.X, .Y, .Z  | denoiser guide: the world-space shading normal at that same vertex       | 0         |
// |              |                   | (components in [−1, 1], not remapped)                                    |           |
// | depth        | depth.Z           | distance from the camera along the unit camera ray to the first hit      | 0         |
// | position     | position.X, .Y, .Z| world-space position of the first hit                                    | 0         |
// | uv           | uv.U, .V          | surface (u, v) of the first hit (the shape's parameterisation)           | 0         |
// | shape_id     | shape_id.X        | index of the shape hit by the ray through the pixel centre, in the order | −1        |
// |              |                   | of the scene's shapes (not averaged: one ray per pixel)                  |           |
// | material_id  | material_id.X     | index of that hit's material in the scene's material table (same ray)   | −1        |
// | variance     | variance.R, .G, .B| the film's variance of the beauty pixel's mean (image/film.h)            | —         |
// | sample_count | sample_count.X    | camera samples taken in the pixel (the film's count)                     | —         |
//
// The sampled AOVs (albedo … uv) are filtered like the beauty image: a pixel is the film's
// filter-weighted mean over its samples, so values are averaged across edges (misses count as 0).
// They are rendered in one AOV pass after the beauty render, with the beauty's seed, sampler and
// spp: every camera sample is the very ray the beauty render traced (sample dimensions 0 and 1;
// integrator/render_loop.h camera_sample). The AOV pass ignores media and lights: albedo and normal
// are properties of surfaces.
//
// The AOV integrator ("integrator": {"type": "aov", "aov": "normal"}, pellucid-render --aov) renders
// one of albedo, normal or depth as the RGB image (depth replicated to three channels).
#pragma once
#include <string>
#include <vector>

#include "pellucid/image/image_io.h"
#include "pellucid/integrator/integrator.h"
#include "pellucid/sampling/sampler.h"

namespace pellucid {

enum class Aov { Albedo, Normal, Depth, Position, Uv, ShapeId, MaterialId, Variance, SampleCount };

/// "albedo", "normal", ... (the names of the table above).
const char* aov_name(Aov aov);
/// The channel names of the AOV's layer ("R", "G", "B" for albedo; "Z" for depth; ...).
std::vector<std::string> aov_channels(Aov aov);
/// Every AOV name, comma-separated, in the order of the enum.
std::string known_aovs();
/// The AOV named `name`; anything else throws pellucid::Error "<where>: unknown aov 'x' (known: ...)".
Aov parse_aov(const std::string& name, const std::string& where = "aovs");
/// A comma-separated list ("albedo,normal"; spaces around names are ignored); duplicates are
/// dropped, the order kept. An empty list or an unknown name throws pellucid::Error naming `where`.
std::vector<Aov> parse_aov_list(const std::string& list, const std::string& where = "aovs");

/// The AOVs of a finished render `beauty` of `scene` as named layers, in the order of `aovs`
/// (duplicates dropped). The sampled AOVs come from one AOV pass with the beauty's seed, sampler
/// and spp, on opts.threads threads; opts.cancel stops it (then `*cancelled` is set and the result
/// is empty). variance and sample_count are read from the beauty's film. `*seconds` receives the
/// AOV pass's wall time.
std::vector<ImageLayer> render_aovs(const Scene& scene, const std::vector<Aov>& aovs, const RenderResult& beauty,
                                    const RenderOptions& opts, bool* cancelled = nullptr, double* seconds = nullptr);

class AovIntegrator final : public Integrator {
public:
    using Kind = Aov;
    explicit AovIntegrator(Kind kind) : m_kind(kind) {}
    /// "albedo" | "normal" | "depth"; anything else throws pellucid::Error naming the known AOVs.
    static Kind parse(const std::string& name);
    static const char* name(Kind kind) { return aov_name(kind); }

    RenderResult render(const Scene& scene, const RenderOptions& opts) const override;
    std::string to_string() const override;
    /// The AOV value of one camera ray.
    Spectrum Li(const Scene& scene, const RayDifferential& ray, Sampler& sampler) const;

private:
    Kind m_kind;
};
}  // namespace pellucid
