// AOVs: the AOV pass (all sampled AOVs of a render at once) and the one-AOV integrator.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/integrator/aov.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include "pellucid/scene/scene.h"
#include "pellucid/util/error.h"

namespace pellucid {
namespace {
constexpr Aov kAll[] = {Aov::Albedo,   Aov::Normal,     Aov::Depth,    Aov::Position,   Aov::Uv,
                        Aov::ShapeId,  Aov::MaterialId, Aov::Variance, Aov::SampleCount};
/// Consecutive delta bounces the denoiser guides follow; a longer chain gives albedo 0 and normal 0.
constexpr int kMaxDeltaBounces = 16;

bool is_sampled(Aov a) { return a == Aov::Albedo || a == Aov::Normal || a == Aov::Depth || a == Aov::Position || a == Aov::Uv; }

/// The denoiser guides of one camera sample (aov.h): albedo along delta bounces and the shading
/// normal where they end. `si` is the first hit of `ray`; sample dimensions from 2 on.
void denoiser_guides(const Scene& scene, RayDifferential ray, SurfaceInteraction si, Sampler& sampler,
                     Spectrum* albedo, Vec3f* normal) {
    Spectrum beta(1.f);
    sampler.set_dimension(Sampler::kPixelDims);
    for (int bounce = 0;; ++bounce) {
        if (scene.has_textures) scene.compute_footprint(si, ray);  // textured albedo, filtered like renders
        // Dimensions per vertex: the lobe (1), then the direction (2).
        const BSDF bsdf = scene.bsdf(si);
        const float u_lobe = sampler.get_1d();
        const Vec2f u = sampler.get_2d();
        const auto bs = bsdf.sample(si.wo, u_lobe, u);
        if (!bs || !bs->is_specular()) {
            // E[weight] = ρ(wo) = ∫ f(wo, wi) |cos θi| dωi (the sample weight is f·|cos θi|/pdf,
            // bxdf/bxdf_types.h); a BSDF that scatters nothing has albedo 0.
            *albedo = bs ? beta * bs->weight : Spectrum(0.f);
            *normal = si.shading.n;
            return;
        }
        if (bounce == kMaxDeltaBounces) break;
        beta *= bs->weight;
        const Ray next = si.spawn_ray(bs->wi);
        const RayDifferential next_d =
            scene.has_textures
                ? scene.specular_differentials(si, ray, next, has_flag(bs->lobe, BxDFFlags::Transmission), bs->eta)
                : RayDifferential(next);
        SurfaceInteraction s2;
        if (!scene.intersect(next_d, s2)) break;
        ray = next_d;
        si = s2;
    }
    *albedo = Spectrum(0.f);
    *normal = Vec3f(0.f);
}

/// Where each sampled AOV's channels lie in the films of the AOV pass: channels are packed three
/// to a film (the film accumulates RGB), so 14 channels need 5 films, not 5 × 3.
struct Layout {
    std::vector<Aov> sampled;
    std::vector<int> offset;  ///< first channel of sampled[i]
    int channels = 0;
    bool guides = false;      ///< albedo or normal requested
    int films() const { return (channels + 2) / 3; }
};
constexpr int kMaxSampledChannels = 3 + 3 + 1 + 3 + 2;

/// The sampled AOVs of one camera sample, written at their offsets into v.
void eval_sample(const Scene& scene, const Layout& lay, const RayDifferential& ray, Sampler& sampler, float* v) {
    std::fill(v, v + lay.channels, 0.f);
    SurfaceInteraction si;
    if (!scene.intersect(ray, si)) return;
    Spectrum albedo(0.f);
    Vec3f normal(0.f);
    if (lay.guides) denoiser_guides(scene, ray, si, sampler, &albedo, &normal);
    for (size_t i = 0; i < lay.sampled.size(); ++i) {
        float* o = v + lay.offset[i];
        switch (lay.sampled[i]) {
            case Aov::Albedo: o[0] = albedo[0], o[1] = albedo[1], o[2] = albedo[2]; break;
            case Aov::Normal: o[0] = normal.x, o[1] = normal.y, o[2] = normal.z; break;
            case Aov::Depth: o[0] = si.t; break;
            case Aov::Position: o[0] = si.p.x, o[1] = si.p.y, o[2] = si.p.z; break;
            case Aov::Uv: o[0] = si.uv.x, o[1] = si.uv.y; break;
            default: break;
        }
    }
}
}  // namespace

const char* aov_name(Aov aov) {
    switch (aov) {
        case Aov::Albedo: return "albedo";
        case Aov::Normal: return "normal";
        case Aov::Depth: return "depth";
        case Aov::Position: return "position";
        case Aov::Uv: return "uv";
        case Aov::ShapeId: return "shape_id";
        case Aov::MaterialId: return "material_id";
        case Aov::Variance: return "variance";
        case Aov::SampleCount: return "sample_count";
    }
    return "?";
}

std::vector<std::string> aov_channels(Aov aov) {
    switch (aov) {
        case Aov::Albedo:
        case Aov::Variance: return {"R", "G", "B"};
        case Aov::Normal:
        case Aov::Position: return {"X", "Y", "Z"};
        case Aov::Depth: return {"Z"};
        case Aov::Uv: return {"U", "V"};
        case Aov::ShapeId:
        case Aov::MaterialId:
        case Aov::SampleCount: return {"X"};
    }
    return {};
}

std::string known_aovs() {
    std::string s;
    for (Aov a : kAll) s += (s.empty() ? "" : ", ") + std::string(aov_name(a));
    return s;
}

Aov parse_aov(const std::string& name, const std::string& where) {
    for (Aov a : kAll)
        if (name == aov_name(a)) return a;
    throw Error(where + ": unknown aov '" + name + "' (known: " + known_aovs() + ")");
}

std::vector<Aov> parse_aov_list(const std::string& list, const std::string& where) {
    std::vector<Aov> out;
    size_t start = 0;
    while (start <= list.size()) {
        size_t end = list.find(',', start);
        if (end == std::string::npos) end = list.size();
        std::string name = list.substr(start, end - start);
        const size_t a = name.find_first_not_of(" \t"), b = name.find_last_not_of(" \t");
        name = a == std::string::npos ? "" : name.substr(a, b - a + 1);
        if (name.empty()) throw Error(where + ": empty aov name in '" + list + "' (known: " + known_aovs() + ")");
        const Aov aov = parse_aov(name, where);
        if (std::find(out.begin(), out.end(), aov) == out.end()) out.push_back(aov);
        start = end + 1;
    }
    return out;
}

std::vector<ImageLayer> render_aovs(const Scene& scene, const std::vector<Aov>& requested, const RenderResult& beauty,
                                    const RenderOptions& opts, bool* cancelled, double* seconds) {
    if (cancelled) *cancelled = false;
    if (seconds) *seconds = 0.0;
    std::vector<Aov> aovs;
    for (Aov a : requested)
        if (std::find(aovs.begin(), aovs.end(), a) == aovs.end()) aovs.push_back(a);
    const int W = scene.width, H = scene.height;
    if (!beauty.state || beauty.image.width != W || beauty.image.height != H)
        throw Error("aovs: the beauty render is not a render of this scene");

    Layout lay;
    bool ids = false;
    for (Aov a : aovs) {
        if (is_sampled(a)) {
            lay.sampled.push_back(a);
            lay.offset.push_back(lay.channels);
            lay.channels += int(aov_channels(a).size());
            lay.guides = lay.guides || a == Aov::Albedo || a == Aov::Normal;
        }
        ids = ids || a == Aov::ShapeId || a == Aov::MaterialId;
    }

    // The AOV pass: the beauty's camera samples (seed, sampler, spp), the sampled AOVs into films
    // packed three channels to a film (the render loop's film is the first), the ids of the
    // pixel-centre ray into `id_image`.
    std::vector<Image> film_means;
    Image id_image(W, H, 2);
    if (!lay.sampled.empty() || ids) {
        const std::optional<Filter> splat = scene.film_splatting ? std::optional<Filter>(scene.filter) : std::nullopt;
        // The layers are means only: their films keep no variance.
        std::vector<Film> extra(size_t(std::max(0, lay.films() - 1)), Film(W, H, splat, false));
        RenderOptions o;
        o.spp = std::max(1, beauty.stats.spp);
        o.seed = int64_t(beauty.state->seed);
        o.sampler = beauty.state->sampler;
        o.threads = opts.threads;
        o.cancel = opts.cancel;
        o.variance = false;
        const SamplerType type = parse_sampler_type(o.sampler, "sampler");
        const int n_films = lay.films();
        RenderResult r = render_loop(scene, o, [&](const TileJob& job, Film& film) -> uint64_t {
            uint64_t bad = 0;
            float v[kMaxSampledChannels + 2];
            const bool splats = film.splats();
            for (int y = job.y0; y < job.y1; ++y)
                for (int x = job.x0; x < job.x1; ++x) {
                    if (ids && job.s0 == 0) {
                        SurfaceInteraction si;
                        const bool hit = scene.intersect(scene.camera.generate_ray(float(x) + 0.5f, float(y) + 0.5f), si);
                        float* px = id_image.pixel(x, y);
                        px[0] = hit ? float(si.shape_id) : -1.f;
                        px[1] = hit ? float(si.material_id) : -1.f;
                    }
                    if (n_films == 0) continue;
                    const uint64_t pixel = uint64_t(y) * uint64_t(W) + uint64_t(x);
                    for (int s = job.s0; s < job.s1; ++s) {
                        Sampler sampler(type, pixel, uint64_t(s), job.seed);
                        float fx, fy;
                        const RayDifferential ray = camera_sample(scene, splats, x, y, sampler, &fx, &fy);
                        eval_sample(scene, lay, ray, sampler, v);
                        v[lay.channels] = v[lay.channels + 1] = 0.f;
                        bool ok = true;
                        for (int f = 0; f < n_films; ++f)
                            ok &= film_add<SampleValues::Signed>(f == 0 ? film : extra[size_t(f - 1)], x, y, fx, fy,
                                                                Spectrum(v[3 * f], v[3 * f + 1], v[3 * f + 2]));
                        bad += ok ? 0 : 1;
                    }
                }
            return bad;
        });
        if (seconds) *seconds = r.stats.seconds;
        if (r.stats.cancelled) {
            if (cancelled) *cancelled = true;
            return {};
        }
        film_means.push_back(std::move(r.image));
        for (const Film& f : extra) film_means.push_back(f.mean());
    }

    std::vector<ImageLayer> out;
    for (Aov a : aovs) {
        ImageLayer layer{aov_name(a), aov_channels(a), Image(W, H, int(aov_channels(a).size()))};
        Image& img = layer.image;
        const size_t n = size_t(W) * size_t(H);
        if (is_sampled(a)) {
            const int off = lay.offset[size_t(std::find(lay.sampled.begin(), lay.sampled.end(), a) - lay.sampled.begin())];
            for (size_t p = 0; p < n; ++p)
                for (int k = 0; k < img.channels; ++k)
                    img.data[p * size_t(img.channels) + size_t(k)] = film_means[size_t((off + k) / 3)].data[3 * p + size_t((off + k) % 3)];
        } else if (a == Aov::ShapeId || a == Aov::MaterialId) {
            const int k = a == Aov::ShapeId ? 0 : 1;
            for (size_t p = 0; p < n; ++p) img.data[p] = id_image.data[2 * p + size_t(k)];
        } else if (a == Aov::Variance) {
            if (beauty.variance.data.empty())
                throw Error("aovs: 'variance' needs the beauty render's variance, which it did not keep (render with "
                            "variance on)");
            img = beauty.variance;
        } else {  // SampleCount
            for (int y = 0; y < H; ++y)
                for (int x = 0; x < W; ++x) *img.pixel(x, y) = float(beauty.state->film.samples(x, y));
        }
        out.push_back(std::move(layer));
    }
    return out;
}

AovIntegrator::Kind AovIntegrator::parse(const std::string& name) {
    if (name == "albedo") return Kind::Albedo;
    if (name == "normal") return Kind::Normal;
    if (name == "depth") return Kind::Depth;
    throw Error("aov: unknown aov '" + name + "' (known: albedo, depth, normal)");
}

std::string AovIntegrator::to_string() const { return std::string("AovIntegrator[aov=") + name(m_kind) + "]"; }

Spectrum AovIntegrator::Li(const Scene& scene, const RayDifferential& ray, Sampler& sampler) const {
    SurfaceInteraction si;
    if (!scene.intersect(ray, si)) return Spectrum(0.f);
    if (m_kind == Kind::Depth) return Spectrum(si.t);
    Spectrum albedo(0.f);
    Vec3f normal(0.f);
    denoiser_guides(scene, ray, si, sampler, &albedo, &normal);
    return m_kind == Kind::Albedo ? albedo : Spectrum(normal.x, normal.y, normal.z);
}

RenderResult AovIntegrator::render(const Scene& scene, const RenderOptions& opts) const {
    // Normals are signed: the film takes every finite sample.
    const SamplerType type = sampler_type(scene, opts);
    return render_loop(scene, opts, [&](const TileJob& job, Film& film) {
        return render_tile<SampleValues::Signed>(
            scene, job, film, type, [&](const RayDifferential& r, Sampler& u) { return Li(scene, r, u); });
    });
}
}  // namespace pellucid
