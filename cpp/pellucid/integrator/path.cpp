// Path tracing with NEE and MIS (Veach 1997, ch. 9; the power heuristic, eq. 9.13).
// SPDX-License-Identifier: Apache-2.0
//
// Sample dimensions (sampling/sampler.h). Every path vertex uses the same layout, whichever branches
// run, so that with the sobol sampler a dimension always feeds the same decision and the points of
// that decision stay stratified over a pixel's samples:
//   0, 1                   pixel filter offset (render_tile)
//   vertex v = depth - 1 (0 at the first hit), base b = 2 + 7 v:
//   b                      light selection (NEE)                    1D
//   b + 1, b + 2           point on the light (NEE)                 2D
//   b + 3                  BSDF lobe selection                      1D
//   b + 4, b + 5           BSDF direction                           2D
//   b + 6                  Russian roulette                         1D
// A skipped branch (no NEE on a specular surface, no roulette before rr_depth) leaves its
// dimensions unused. The sampler's Sobol part covers 64 dimensions (8 vertices and most of the
// 9th); later ones draw from the sample's PCG32 stream. The independent sampler ignores set_dimension and consumes
// its stream in call order (the pre-Sampler order, so its images are unchanged).
#include "pellucid/integrator/path.h"

#include <algorithm>
#include <vector>

#include "pellucid/integrator/aov.h"
#include "pellucid/integrator/path_lanes.h"
#include "pellucid/sampling/mis.h"
#include "pellucid/util/error.h"

namespace pellucid {

std::unique_ptr<Integrator> make_integrator(const Scene& scene) {
    if (scene.integrator.type == "path") return std::make_unique<PathIntegrator>(scene.integrator);
    if (scene.integrator.type == "aov")
        return std::make_unique<AovIntegrator>(AovIntegrator::parse(scene.integrator.aov));
    throw Error("integrator.type: unknown integrator '" + scene.integrator.type + "'");
}

namespace {
/// render_tile for the path tracer with its rays traced in packets. Up to kSlots paths are in flight;
/// each round traces all their rays a packet at a time and advances every path one vertex
/// (PathIntegrator::vertex), then traces the shadow rays NEE left, a packet at a time. A finished
/// path's slot takes the next (pixel, sample), so packets stay full until the chunk runs out (a tile
/// goes through in chunks of whole pixels, about 4096 paths each).
/// Each path keeps its own Sampler, and the estimates reach the film in render_tile's order (pixel
/// by pixel, sample by sample), so the image equals the one-path-at-a-time loop's bit for bit.
uint64_t render_tile_packets(const PathIntegrator& integrator, const Scene& scene, const TileJob& job, Film& film,
                             SamplerType type) {
    constexpr int kPacket = EmbreeScene::kPacketSize, kSlots = 4 * kPacket;
    struct Slot {
        PathIntegrator::PathState st;
        Sampler sampler;
        int64_t k = 0;  ///< index into `done`
    };
    struct Estimate {
        Spectrum L;
        float fx, fy;
    };
    const int tile_w = job.x1 - job.x0, n_samples = job.s1 - job.s0;
    const int64_t n_pixels = int64_t(tile_w) * (job.y1 - job.y0);
    // The tile's pixels go through in chunks of about kChunkPaths paths (whole pixels, all their
    // samples), so the buffer of finished estimates stays small however many samples a pass takes.
    constexpr int64_t kChunkPaths = 4096;
    const int64_t chunk_pixels = std::max<int64_t>(1, kChunkPaths / n_samples);
    thread_local std::vector<Estimate> done;  // grows to the largest chunk, then is reused
    const bool splat = film.splats();
    uint64_t bad = 0;
    Slot slots[kSlots];
    int active[kSlots], shadowed[kSlots];
    bool alive[kSlots];
    SurfaceInteraction si[kPacket];
    const Ray* rays[kPacket];
    bool flag[kPacket];
    auto pixel_xy = [&](int64_t px, int* x, int* y) {
        *x = job.x0 + int(px % tile_w);
        *y = job.y0 + int(px / tile_w);
    };
    for (int64_t p0 = 0; p0 < n_pixels; p0 += chunk_pixels) {
        const int64_t n_paths = std::min(chunk_pixels, n_pixels - p0) * n_samples;
        done.resize(size_t(n_paths));
        int64_t next = 0;
        auto start = [&](Slot& slot) {  // path k of the chunk: pixel p0 + k / n_samples, sample k % n_samples
            if (next >= n_paths) return false;
            const int64_t k = next++;
            int x, y;
            pixel_xy(p0 + k / n_samples, &x, &y);
            slot.k = k;
            slot.sampler = Sampler(type, uint64_t(y) * uint64_t(scene.width) + uint64_t(x),
                                   uint64_t(job.s0 + int(k % n_samples)), job.seed);
            slot.st = PathIntegrator::PathState{};
            slot.st.ray = camera_sample(scene, splat, x, y, slot.sampler, &done[k].fx, &done[k].fy);
            return true;
        };
        int n_active = 0;
        for (int i = 0; i < kSlots && start(slots[i]); ++i) active[n_active++] = i;
        while (n_active > 0) {
            for (int b = 0; b < n_active; b += kPacket) {
                const int n = std::min(kPacket, n_active - b);
                for (int i = 0; i < n; ++i) rays[i] = &slots[active[b + i]].st.ray;
                scene.intersect_packet(n, rays, si, flag);
                for (int i = 0; i < n; ++i) {
                    Slot& s = slots[active[b + i]];
                    alive[b + i] = integrator.vertex(scene, s.st, flag[i], si[i], s.sampler);
                }
            }
            int n_shadowed = 0;
            for (int j = 0; j < n_active; ++j)
                if (slots[active[j]].st.has_shadow) shadowed[n_shadowed++] = active[j];
            for (int b = 0; b < n_shadowed; b += kPacket) {
                const int n = std::min(kPacket, n_shadowed - b);
                for (int i = 0; i < n; ++i) rays[i] = &slots[shadowed[b + i]].st.shadow;
                scene.occluded_packet(n, rays, flag);
                for (int i = 0; i < n; ++i) {
                    PathIntegrator::PathState& st = slots[shadowed[b + i]].st;
                    if (!flag[i]) st.L += st.Ld;
                    st.has_shadow = false;
                }
            }
            int m = 0;
            for (int j = 0; j < n_active; ++j) {
                Slot& s = slots[active[j]];
                if (alive[j]) {
                    active[m++] = active[j];
                    continue;
                }
                done[s.k].L = s.st.L;
                if (start(s)) active[m++] = active[j];
            }
            n_active = m;
        }
        for (int64_t k = 0; k < n_paths; ++k) {
            int x, y;
            pixel_xy(p0 + k / n_samples, &x, &y);
            if (!film_add<SampleValues::NonNegative>(film, x, y, done[k].fx, done[k].fy, done[k].L)) ++bad;
        }
    }
    return bad;
}
}  // namespace

RenderResult PathIntegrator::render(const Scene& scene, const RenderOptions& opts) const {
    const SamplerType type = sampler_type(scene, opts);
    // The simplest model that renders the scene: the lane kernel when it covers every material and
    // light of the scene (path_lanes.h), the general vertex loop otherwise.
    if (m_s.lanes && m_s.packets)
        if (std::shared_ptr<const LaneScene> lanes = make_lane_scene(scene, m_s))
            return render_loop(scene, opts, [&](const TileJob& job, Film& film) {
                return render_tile_lanes(*lanes, scene, LaneSettings{m_max_depth, m_s.rr_depth, m_use_nee, m_use_mis},
                                         job, film, type);
            });
    return render_loop(scene, opts, [&](const TileJob& job, Film& film) {
        if (m_s.packets) return render_tile_packets(*this, scene, job, film, type);
        return render_tile(scene, job, film, type, [&](const RayDifferential& r, Sampler& u) { return Li(scene, r, u); });
    });
}

std::string PathIntegrator::to_string() const {
    return "PathIntegrator[max_depth=" + std::to_string(m_s.max_depth) + ", rr_depth=" +
           std::to_string(m_s.rr_depth) + ", strategy=" + m_s.strategy + "]";
}

namespace {
constexpr int kVertexDims = 7;  ///< dimensions per path vertex (the layout at the top of this file)
constexpr int kLightSelectDim = 0, kLobeDim = 3, kRouletteDim = 6;

// Light contribution of one area/environment hit found by BSDF sampling, MIS-weighted against the
// light-sampling strategy that could have produced the same direction.
float bsdf_hit_weight(bool use_mis, bool use_nee, bool specular, float bsdf_pdf, float light_pdf) {
    if (specular || !use_nee) return 1.f;
    if (!use_mis) return 0.f;  // "nee": light sampling alone accounts for non-delta directions
    return power_heuristic(bsdf_pdf, light_pdf);
}
}  // namespace

Spectrum PathIntegrator::Li(const Scene& scene, RayDifferential ray, Sampler& sampler) const {
    PathState st;
    st.ray = ray;
    SurfaceInteraction si;
    for (;;) {
        const bool hit = scene.intersect(st.ray, si);
        const bool more = vertex(scene, st, hit, si, sampler);
        if (st.has_shadow && !scene.occluded(st.shadow)) st.L += st.Ld;
        if (!more) return st.L;
    }
}

// Not inlined, so that Li and the packet driver run the same instructions (same image, bit for bit).
[[gnu::noinline]] bool PathIntegrator::vertex(const Scene& scene, PathState& st, bool hit, SurfaceInteraction& si,
                                              Sampler& sampler) const {
    const bool use_nee = m_use_nee && !scene.lights.empty();
    const bool use_mis = m_use_mis;
    const int depth = st.depth;  // number of path segments, including st.ray
    st.has_shadow = false;
    if (!hit) {
        for (uint32_t li : scene.infinite_lights) {
            InfiniteHit env = infinite_hit(scene.lights[li], st.prev_ctx, st.ray.d);
            float lpdf = scene.light_pmf(li) * env.pdf;
            st.L += st.beta * env.Le * bsdf_hit_weight(use_mis, use_nee, st.specular, st.prev_pdf, lpdf);
        }
        return false;
    }
    if (si.light_id >= 0) {
        Spectrum Le = scene.emitted(si);
        if (!Le.is_black()) {
            float lpdf = 0.f;
            if (!st.specular) {
                const auto& al = std::get<AreaLight>(scene.lights[size_t(si.light_id)]);
                lpdf = scene.light_pmf(size_t(si.light_id)) * al.pdf_li(st.prev_ctx, st.ray.d, si.p, si.ng);
            }
            st.L += st.beta * Le * bsdf_hit_weight(use_mis, use_nee, st.specular, st.prev_pdf, lpdf);
        }
    }
    if (m_max_depth >= 0 && depth >= m_max_depth) return false;

    // The pixel footprint, for texture filtering and bump steps (and to carry differentials on).
    if (scene.has_textures) scene.compute_footprint(si, st.ray);
    BSDF bsdf = scene.bsdf(si);
    BxDFFlags flags = bsdf.flags();
    if (flags == BxDFFlags::None) return false;
    const Vec3f wo = si.wo;
    LightSampleContext ctx{si.p, si.ng};
    const int dim0 = Sampler::kPixelDims + kVertexDims * (depth - 1);

    // Next-event estimation: one light (uniformly or by power), one point on it. The shadow ray is
    // left to the caller, which may trace it in a packet with other paths'.
    if (use_nee && is_non_specular(flags)) {
        sampler.set_dimension(dim0 + kLightSelectDim);
        float u_light = sampler.get_1d();
        Vec2f u = sampler.get_2d();
        float pmf;
        size_t li = scene.sample_light(u_light, &pmf);
        auto ls = std::visit([&](const auto& l) { return l.sample_li(ctx, u); }, scene.lights[li]);
        if (ls && ls->pdf > 0.f) {
            float bsdf_pdf;
            Spectrum f = bsdf.eval(wo, ls->wi, TransportMode::Radiance, &bsdf_pdf);
            if (!f.is_black()) {
                float light_pdf = pmf * ls->pdf;
                float w = (ls->delta || !use_mis) ? 1.f : power_heuristic(light_pdf, bsdf_pdf);
                st.Ld = st.beta * f * ls->L * (w / light_pdf);
                st.shadow = ls->infinite ? si.spawn_ray(ls->wi) : si.spawn_ray_to(ls->p_light, ls->n_light, ls->p_error);
                st.has_shadow = true;
            }
        }
    }

    // Continue the path by sampling the BSDF.
    sampler.set_dimension(dim0 + kLobeDim);
    float u_lobe = sampler.get_1d();
    Vec2f u = sampler.get_2d();
    auto bs = bsdf.sample(wo, u_lobe, u);
    if (!bs) return false;
    st.beta *= bs->weight;
    st.prev_pdf = bs->pdf;
    st.specular = bs->is_specular();
    if (has_flag(bs->lobe, BxDFFlags::Transmission)) st.eta_scale *= sqr(bs->eta);
    st.prev_ctx = ctx;
    if (scene.has_textures && st.specular && st.ray.has_differentials)
        st.ray = scene.specular_differentials(si, st.ray, si.spawn_ray(bs->wi), has_flag(bs->lobe, BxDFFlags::Transmission),
                                              bs->eta);
    else
        st.ray = RayDifferential(si.spawn_ray(bs->wi));
    st.depth = depth + 1;

    // Russian roulette on the throughput with the η² factor removed (pbrt-v4 §13.4.1 / Mitsuba 3
    // path.cpp): survive with q = min(max β·η², 0.95) from rr_depth on.
    if (depth >= m_s.rr_depth) {
        float q = std::min(st.beta.max_component() * st.eta_scale, 0.95f);
        sampler.set_dimension(dim0 + kRouletteDim);
        if (!(sampler.get_1d() < q)) return false;
        st.beta /= q;
    }
    return !st.beta.is_black();
}
}  // namespace pellucid
