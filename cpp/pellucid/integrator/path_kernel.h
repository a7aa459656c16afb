// The path tracer, written once over a lane type F (simd/lane.h): unidirectional path tracing with
// next-event estimation and multiple importance sampling (Veach 1997, ch. 9; the power heuristic,
// eq. 9.13), Russian roulette on the throughput with η² removed (pbrt-v4 §13.4.1).
// SPDX-License-Identifier: Apache-2.0
//
// render_tile_kernel<F> runs kLaneWidth<F> paths side by side, one per lane: F = float is one path
// at a time (the scalar target, which the tests compare every packet target with); F = a 16-, 8- or 4-wide packet is the
// renderer (integrator/kernel_*.cpp instantiate it, one translation unit per instruction set). A
// lane whose path ends takes the tile's next (pixel, sample) at once, so packets stay full.
//
// Per vertex, every lane's quantities are packets: throughput, radiance, MIS densities, the
// shading frame, the roulette. The BSDF is dispatched per lane group: the lanes of each packet form
// present (PathSetup::packet_kind; a textured material's where the BSDF built at its hit has one,
// PathSetup::textured_packet) are shaded by it in one pass, masked (on the half-width packet where
// at most half the lanes take part: integrator/form_lanes.h); the other lanes go through BSDF one at a time (path_services.h), as do emission, the samplers'
// seeding (the independent sampler's numbers are drawn for all lanes at once) and the sampling of
// lights with neither a row in the light table (LightTable) nor an emitter table (EmitterTable),
// until those have packet forms too. Rays that escape the scene
// take the radiance of the lights at infinity as a packet (escaped_radiance). Every lane keeps its
// own sampler stream and the estimates reach the film in (pixel, sample) order, so images do not depend on
// the thread count.
//
// Media (medium/medium.h, docs/media.md), when the scene has any: each lane tracks the medium its
// ray runs through. Before a hit is shaded, distance sampling over the segment either finds a
// collision, which becomes a vertex scattered by the medium's phase function in place of a BSDF
// (with NEE and MIS as at a surface), or passes to the surface with the throughput reweighted. A
// `null` boundary is crossed without a vertex, changing only the medium. Leaving a surface that
// bounds media enters its interior or exterior by the side, and shadow rays carry the
// transmittance of the media and null boundaries they cross: the packet traces their first segments,
// and a lane goes on alone only past a null boundary (path_services::shadow_transmittance).
//
// Subsurface scattering (bssrdf/separable.h, docs/subsurface.md), when a shape renders with a
// diffusion BSSRDF: a BSDF sample that refracts into it becomes a probe for an exit point, with the
// weight Sp/pdf; the lane's next vertex is that exit, shaded by the BSSRDF's exit lobe with NEE and
// MIS like any diffuse vertex, without a ray traced to it. The random walk needs nothing here: it is
// a dielectric around an interior medium.
#pragma once
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "pellucid/bxdf/conductor.h"
#include "pellucid/bxdf/dielectric.h"
#include "pellucid/bxdf/lambertian.h"
#include "pellucid/bxdf/oren_nayar.h"
#include "pellucid/bxdf/plastic.h"
#include "pellucid/bxdf/principled_bsdf.h"
#include "pellucid/integrator/form_lanes.h"
#include "pellucid/integrator/path_services.h"
#include "pellucid/material/textured.h"
#include "pellucid/math/frame.h"
#include "pellucid/sampling/mis.h"
#include "pellucid/scene/hit_packets.h"

namespace pellucid {

// PELLUCID_FORM_CALL(kind, where, statement): the statement that runs packet form `kind` masked to
// the lanes `where`. The diagnostic build (CMake PELLUCID_DISPATCH_STATS, bench/dispatch_stats.py)
// times it and counts its lanes (dispatch_record), and likewise the tile (kind −1) and the packet
// pass with its lanes that go on (kind −2); every other build is the statement alone.
#if PELLUCID_DISPATCH_STATS
template <class M>
int dispatch_lane_count(const M& m, int width) {
    bool b[16];
    lane::store(b, m);
    int n = 0;
    for (int i = 0; i < width; ++i) n += b[i];
    return n;
}
#define PELLUCID_FORM_CALL(kind, where, ...)                                                      \
    do {                                                                                          \
        const uint64_t form_t0 = dispatch_clock();                                               \
        __VA_ARGS__;                                                                              \
        dispatch_record(kind, dispatch_lane_count(where, W), W, dispatch_clock() - form_t0);     \
    } while (0)
#else
#define PELLUCID_FORM_CALL(kind, where, ...) __VA_ARGS__
#endif

/// Row `row` of `table` (`stride` floats a row), its first n entries, into out[0..n) on the lanes
/// `on` (other lanes keep out). A packet's lanes mostly share a few rows (a scene's spheres), so
/// each distinct row among them takes a broadcast and a select an entry, for up to kRowPasses rows;
/// the lanes left after those gather theirs. (A gather of 16 lanes costs about 20 cycles on the
/// AVX-512 machines of bench/README.md: the sphere table's 15 entries took 5-10 % of a render.)
template <class F>
void rows_by_lane(const float* table, int stride, const IntT<F>& row, const MaskT<F>& on, int n, F* out) {
    constexpr int W = kLaneWidth<F>, kRowPasses = 3;
    using I = IntT<F>;
    alignas(64) bool rem[W];
    alignas(64) int32_t rows[W];
    lane::store(rem, on);
    lane::store(rows, row);
    MaskT<F> left = on;
    int passes = 0;
    for (int i = 0; i < W; ++i) {
        if (!rem[i]) continue;
        if (passes++ == kRowPasses) {
            const I base = lane::select(lane::int_mask(left), row, I(0)) * I(stride);
            for (int k = 0; k < n; ++k) out[k] = lane::select(left, lane::gather(table, base + I(k)), out[k]);
            return;
        }
        const int32_t r = rows[i];
        const MaskT<F> same = left && lane::float_mask(row == I(r));
        const float* v = table + size_t(r) * size_t(stride);
        for (int k = 0; k < n; ++k) out[k] = lane::select(same, F(v[k]), out[k]);
        left = left && !same;
        lane::store(rem, left);
    }
}

/// The lanes i < W where b[i], as the bits of a word (lane i at bit i). The per-lane loops over a
/// subset of the lanes walk its set bits (`for (m = lane_bits<F>(b); m; m &= m - 1)`, lane
/// lowest_lane<F>(m)) instead of testing every lane: which lanes a step takes changes from packet to
/// packet, and a test per lane mispredicts where a walk over the bits does not.
/// (Templated on the lane type F, as every helper of the kernel is: one compiled for one instruction set
/// must not stand in for another's at link time.)
/// Eight lanes at a time: the bools' bytes b0 … b7 (each 0 or 1) as one word x = Σ b_i·2^(8i), times
/// M = Σ 2^(56 − 7i), put b_i at bit 56 + i; every other product b_i·2^(56 + 8i − 7k) lands above
/// bit 63 (i > k) or alone on a bit below 56 (i < k: the positions 56 + 8i − 7k are distinct), so no
/// carry reaches bits 56–63, which the shift returns. (A loop over the lanes is a load, a shift and
/// an or a lane.)
template <class F>
inline uint32_t lane_bits(const bool* b) {
    constexpr int W = kLaneWidth<F>;
    static_assert(W <= 32, "lanes fit a word");
    static_assert(sizeof(bool) == 1, "one byte a bool");
    uint32_t m = 0;
#if __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    if constexpr (W % 8 == 0 || W == 4) {
        for (int i = 0; i < W; i += 8) {
            uint64_t x = 0;
            std::memcpy(&x, b + i, W == 4 ? 4 : 8);
            m |= uint32_t((x * 0x0102040810204080ULL) >> 56) << i;
        }
        return m;
    }
#endif
    for (int i = 0; i < W; ++i) m |= uint32_t(b[i]) << i;
    return m;
}
template <class F>
inline int lowest_lane(uint32_t m) {
    return __builtin_ctz(m);
}

template <class F>
uint64_t render_tile_kernel(const PathSetup& ps_in, const TileJob& job, Film& film) {
    constexpr int W = kLaneWidth<F>;
    using M = MaskT<F>;
    static_assert(W <= 16, "one Embree packet per vertex");
#if PELLUCID_DISPATCH_STATS
    const uint64_t tile_t0 = dispatch_clock();
    struct TileClock {
        uint64_t t0;
        ~TileClock() { dispatch_record(-1, 0, W, dispatch_clock() - t0); }
    } tile_clock{tile_t0};
#endif
    const PathSetup& ps = ps_in;
    const bool splat = film.splats();
    const Scene& scene = *ps.scene;
    const int tile_w = job.x1 - job.x0, n_samples = job.s1 - job.s0;
    const int64_t n_pixels = int64_t(tile_w) * (job.y1 - job.y0);
    // Whole pixels of about kChunkPaths paths at a time, so the buffer of estimates stays small.
    constexpr int64_t kChunkPaths = 4096;
    const int64_t chunk_pixels = std::max<int64_t>(1, kChunkPaths / n_samples);
    // The chunk's estimates, pixel by pixel (an array, not a vector: its members would be emitted
    // in this object under names other objects use).
    const std::unique_ptr<FilmSample[]> done(new FilmSample[size_t(std::min<int64_t>(n_pixels, chunk_pixels) * n_samples)]);

    // Per-lane records (one lane's scalars) and the state of each lane's path as arrays, loaded
    // into packets at each vertex.
    Sampler sampler[W];
    RayDifferential ray[W];
    SurfaceInteraction si[W];
    alignas(BSDF) unsigned char bsdf_mem[W][sizeof(BSDF)];
    auto bsdf = [&](int i) -> BSDF& { return *reinterpret_cast<BSDF*>(bsdf_mem[i]); };
    Ray shadow[W];  // a shadow ray NEE sampled one lane at a time (then copied into Arrays::sh)
    int64_t path_of[W];
    // Media (PathSetup::media): the medium each lane's ray runs through, the stream of its medium
    // events, and how many null boundaries its path has crossed.
    int32_t medium[W]{};
    PCG32 medium_rng[W];
    int crossings[W]{};
    // A lane in a medium whose ray hit a surface makes that hit's record (si) only once distance
    // sampling has passed the medium up to it (a collision before it makes the record of no use).
    bool deferred[W]{};
    // Subsurface scattering (PathSetup::subsurface): a lane whose path refracted into a diffusion
    // BSSRDF continues at the exit point the probe found, without tracing a ray: pending_exit marks
    // it for the next vertex, exit_si holds the exit and exit_ss its BSSRDF.
    bool pending_exit[W]{};
    int32_t exit_ss[W]{};
    SurfaceInteraction exit_si[W];
    bool hit[W], active[W], blocked[W];
    // Hit records: the kernel's hits, and which lanes have a full SurfaceInteraction in si (the
    // others only their vertex, as packets: scene/hit_packets.h), with each hit's material and light.
    HitLanes hl;
    HitLanes sh_hl;  // the first hits of the shadow rays in media
    bool full[W];
    uint32_t mat_of[W]{};
    int32_t light_of[W]{};
    // Without media or subsurface scattering, a hit on a sphere or a triangle whose material has a
    // packet form and emits nothing needs no more than its vertex; in a scene whose materials read
    // pixel footprints (Scene::needs_footprints), unless the material has a delta lobe (a delta
    // bounce carries the hit's footprint on to the next hit as ray differentials,
    // Scene::specular_differentials).
    const bool vertex_lanes = !(ps.media || ps.subsurface);
    // The fewest escaped lanes a vertex restarts before its packet pass: 4 of 16 (measured on the
    // suite, bench/README.md), every escape for one lane.
    constexpr int kRestartMinLanes = std::max(1, W / 4);
    HitVertexInputs<W> hv{};
    struct alignas(64) Arrays {
        float Lr[W], Lg[W], Lb[W], br[W], bg[W], bb[W];
        float prev_pdf[W], eta_scale[W], depth[W];
        float ppx[W], ppy[W], ppz[W], pnx[W], pny[W], pnz[W];  // the previous vertex (MIS of emission)
        bool specular[W];
        // This vertex.
        float Ler[W], Leg[W], Leb[W], le_pdf[W];
        float pex[W], pey[W], pez[W];  // error bound of the hit point
        float px[W], py[W], pz[W], ngx[W], ngy[W], ngz[W], wox[W], woy[W], woz[W];
        float sx[W], sy[W], sz[W], tx[W], ty[W], tz[W], nx[W], ny[W], nz[W];
        float q[kPacketParams][W];  // the packet form's parameters (PathSetup::packet_params)
        float kind[W];              // PacketKind of the lane's material
        // A material of PathSetup::tex_lanes: its hit's uv, ∂p/∂u and ∂p/∂v (the rest of its record
        // is the vertex's), its textures evaluated in the packet pass.
        bool tl[W];
        float tu[W], tv[W], dux[W], duy[W], duz[W], dvx[W], dvy[W], dvz[W];
        bool fast[W], goes_on[W], nee[W];
        bool esc[W];                   // the ray escaped: the lights at infinity, as a packet
        float edx[W], edy[W], edz[W];  // its direction
        bool soft[W], est[W];          // a packet form's terminator is softened (Estevez's, else Chiang's)
        float n0x[W], n0y[W], n0z[W];  // about this unperturbed normal (terminator_factor)
        bool cam[W];                   // the lane's path starts: its camera ray through (cfx, cfy) is due
        float cfx[W], cfy[W];
        bool in_medium[W];   // this vertex is a collision in a medium (the phase function scatters)
        bool crossing[W];    // the ray crossed a null boundary: the path goes on unchanged
        bool at_exit[W];     // this vertex is a BSSRDF's exit point (its exit lobe scatters)
        bool to_exit[W];     // this vertex's sample entered a BSSRDF: the next vertex is its exit
        float u[7][W];
        // The independent sampler's PCG32 streams (state, increment), lane i at [i]: its numbers are
        // drawn from here for all lanes at once (draw_independent), so they stay in arrays and never
        // go through the lanes' Sampler records (which other samplers use).
        uint64_t rs[W], ri[W];
        // Each lane's ray (origin, direction, tmax) as arrays: what the packet trace reads
        // (EmbreeScene::intersect_lanes), and the ray itself: ray[i] holds a lane's ray
        // differentials, and its origin, direction and tmax only once lane_ray(i) has copied them
        // from here (the one-lane code that reads a ray calls it).
        float ray_soa[7][W];
        bool traced[W];  // the lane's ray is traced (active, without a pending BSSRDF exit)
        int32_t draw0[W], draw1[W];  // the independent sampler's numbers u[draw0, draw1) of this vertex
        // NEE.
        bool nee_ok[W], delta[W];
        bool plight[W];      // the lane's light has a packet form (PathSetup::lights)
        int32_t light[W];    // the light the lane picked, and its probability
        float lsel[W];
        float lwx[W], lwy[W], lwz[W], lLr[W], lLg[W], lLb[W], lpdf[W];
        float gfr[W], gfg[W], gfb[W], gpdf[W];  // BSDF-lane eval toward the light
        // BSDF sampling of the BSDF lanes.
        bool s_ok[W];
        float swx[W], swy[W], swz[W], swr[W], swg[W], swb[W], spdf[W], seta[W];
        int32_t slobe[W];
        // Results.
        bool has_shadow[W], alive[W], sampled[W];
        float sh[7][W];  // the shadow rays: origin, direction, tmax (EmbreeScene::occluded_lanes)
        float Ldr[W], Ldg[W], Ldb[W];
        float nwx[W], nwy[W], nwz[W];
    } a{};
    // This vertex's point, error bound, geometric normal, wo and shading frame, into lane i.
    auto load_vertex = [&a](int i, const SurfaceInteraction& h) {
        a.px[i] = h.p.x, a.py[i] = h.p.y, a.pz[i] = h.p.z;
        a.pex[i] = h.p_error.x, a.pey[i] = h.p_error.y, a.pez[i] = h.p_error.z;
        a.ngx[i] = h.ng.x, a.ngy[i] = h.ng.y, a.ngz[i] = h.ng.z;
        a.wox[i] = h.wo.x, a.woy[i] = h.wo.y, a.woz[i] = h.wo.z;
        a.sx[i] = h.shading.s.x, a.sy[i] = h.shading.s.y, a.sz[i] = h.shading.s.z;
        a.tx[i] = h.shading.t.x, a.ty[i] = h.shading.t.y, a.tz[i] = h.shading.t.z;
        a.nx[i] = h.shading.n.x, a.ny[i] = h.shading.n.y, a.nz[i] = h.shading.n.z;
    };
    // Lane i's ray from the arrays into ray[i] (what one-lane code reads), and back (where it
    // changed one lane at a time).
    auto lane_ray = [&](int i) -> RayDifferential& {
        RayDifferential& r = ray[i];
        r.o = Vec3f(a.ray_soa[0][i], a.ray_soa[1][i], a.ray_soa[2][i]);
        r.d = Vec3f(a.ray_soa[3][i], a.ray_soa[4][i], a.ray_soa[5][i]);
        r.tmax = a.ray_soa[6][i];
        return r;
    };
    auto set_ray_soa = [&](int i) {
        const Ray& r = ray[i];
        a.ray_soa[0][i] = r.o.x, a.ray_soa[1][i] = r.o.y, a.ray_soa[2][i] = r.o.z;
        a.ray_soa[3][i] = r.d.x, a.ray_soa[4][i] = r.d.y, a.ray_soa[5][i] = r.d.z, a.ray_soa[6][i] = r.tmax;
    };
    auto LD = [](const float* p) { return lane::load_as<F>(p); };
    auto LM = [](const bool* p) { return lane::load_mask_as<M>(p); };
    auto ST = [](float* p, const F& v) { lane::store(p, v); };
    auto SM = [](bool* p, const M& v) { lane::store(p, v); };
    uint64_t bad = 0;
    bool any_cam = false;  // some lane's camera ray is due (Arrays::cam)

    for (int64_t p0 = 0; p0 < n_pixels; p0 += chunk_pixels) {
        const int64_t n_paths = std::min(chunk_pixels, n_pixels - p0) * n_samples;
        int64_t next = 0;
        auto pixel_xy = [&](int64_t k, int* x, int* y) {
            const int64_t px = p0 + k / n_samples;
            *x = job.x0 + int(px % tile_w);
            *y = job.y0 + int(px / tile_w);
        };
        // Path `next` is sample next_s of the chunk's pixel (next_x, next_y), whose shared seeding
        // (Sampler::PixelSeed) pixel_seed holds: kept up to date as paths start, without divisions.
        int next_s = 0, next_x, next_y;
        pixel_xy(0, &next_x, &next_y);
        Sampler::PixelSeed pixel_seed = path_services::pixel_seed(ps, next_x, next_y, job.seed);
        // The lanes `go` take the chunk's next paths, in lane order, or go idle. The paths are dealt
        // out one lane at a time (a counter over the chunk's pixels and samples); with the
        // independent sampler and a splatting film, each sample's seeding and pixel offset are
        // computed for all lanes at once, from PCG32's parts, eight streams at a time (PCG32x8)
        // (the numbers path_services::start_sample gives); otherwise one lane at a time by it.
        const bool packet_seeding = ps.sampler == SamplerType::Independent && splat;
        auto start_lanes = [&](const bool* go) {
            alignas(64) uint64_t stream[W]{}, sample_of[W]{};
            alignas(64) float x0[W]{}, y0[W]{};  // the pixel's centre
            alignas(64) bool started[W]{};
            bool any_started = false;
            // The counters in locals for the loop (through the closure each would be a load and a
            // store a lane), written back after it.
            int64_t next_l = next;
            int next_s_l = next_s, next_x_l = next_x, next_y_l = next_y;
            Sampler::PixelSeed seed_l = pixel_seed;
            for (uint32_t m = lane_bits<F>(go); m; m &= m - 1) {
                const int i = lowest_lane<F>(m);
                if (next_l >= n_paths) {
                    active[i] = false;
                    continue;
                }
                const int64_t k = next_l++;
                const int x = next_x_l, y = next_y_l, sample = job.s0 + next_s_l;
                path_of[i] = k;
                if (packet_seeding) {
                    stream[i] = seed_l.stream, sample_of[i] = uint64_t(sample);
                    x0[i] = float(x) + 0.5f, y0[i] = float(y) + 0.5f;
                } else {
                    path_services::start_sample(ps, splat, x, y, sample, seed_l, &sampler[i], &done[k].fx, &done[k].fy);
                    a.cfx[i] = done[k].fx, a.cfy[i] = done[k].fy;
                    if (ps.sampler == SamplerType::Independent)
                        a.rs[i] = sampler[i].stream().state(), a.ri[i] = sampler[i].stream().increment();
                }
                if (ps.media || ps.subsurface)
                    medium_rng[i] = path_services::medium_rng(ps, x, y, sample, job.seed);
                if (ps.media) {
                    medium[i] = ps.camera_medium;
                    crossings[i] = 0;
                }
                if (++next_s_l == n_samples && next_l < n_paths) {  // on to the next pixel of the tile
                    next_s_l = 0;
                    if (++next_x_l == job.x1) next_x_l = job.x0, ++next_y_l;
                    seed_l = path_services::pixel_seed(ps, next_x_l, next_y_l, job.seed);
                }
                pending_exit[i] = false;
                active[i] = started[i] = any_started = true;
            }
            next = next_l, next_s = next_s_l, next_x = next_x_l, next_y = next_y_l, pixel_seed = seed_l;
            if (!any_started) return;
            // The started lanes' path state, as packets; their camera rays follow for all of them
            // at once (camera_rays).
            const M st = LM(started);
            auto reset = [&](float* f, float v) { ST(f, lane::select(st, F(v), LD(f))); };
            for (float* f : {a.Lr, a.Lg, a.Lb, a.prev_pdf, a.ppx, a.ppy, a.ppz, a.pnx, a.pny, a.pnz}) reset(f, 0.f);
            for (float* f : {a.br, a.bg, a.bb, a.eta_scale, a.depth}) reset(f, 1.f);
            SM(a.specular, st || LM(a.specular));  // the camera ray counts as a delta bounce
            SM(a.cam, st || LM(a.cam));
            any_cam = true;
            if (!packet_seeding) return;
            // The stream of Sampler(Independent, pixel seed, sample) after its get_pixel_2d(), and the
            // film positions, as start_sample's.
            alignas(64) uint64_t state[W], inc[W];
            alignas(64) float fx[W], fy[W];
            path_services::start_independent_samples<W>(stream, sample_of, x0, y0, state, inc, fx, fy);
            for (uint32_t m = lane_bits<F>(started); m; m &= m - 1) {
                const int i = lowest_lane<F>(m);
                a.rs[i] = state[i], a.ri[i] = inc[i];
                FilmSample& d = done[size_t(path_of[i])];
                a.cfx[i] = d.fx = fx[i], a.cfy[i] = d.fy = fy[i];
            }
        };
        // The camera rays of the lanes start_lanes() left without one, as a packet; in a scene with
        // textures with their differentials toward the pixels (x + 1, y) and (x, y + 1), whose
        // footprints filter the textures (PerspectiveCamera::generate_ray_differential's rays).
        auto camera_rays = [&]() {
            if (!any_cam) return;
            any_cam = false;
            const F fx = LD(a.cfx), fy = LD(a.cfy);
            const V3<F> d = scene.camera.direction<F>(fx, fy);
            alignas(64) float b[9][W];
            ST(b[0], d.x), ST(b[1], d.y), ST(b[2], d.z);
            const Point3f o = scene.camera.origin();
            if (scene.needs_footprints) {
                const V3<F> dx = scene.camera.direction<F>(fx + F(1.f), fy), dy = scene.camera.direction<F>(fx, fy + F(1.f));
                ST(b[3], dx.x), ST(b[4], dx.y), ST(b[5], dx.z), ST(b[6], dy.x), ST(b[7], dy.y), ST(b[8], dy.z);
            }
            {  // the arrays the trace reads
                const M cam = LM(a.cam);
                ST(a.ray_soa[0], lane::select(cam, F(o.x), LD(a.ray_soa[0])));
                ST(a.ray_soa[1], lane::select(cam, F(o.y), LD(a.ray_soa[1])));
                ST(a.ray_soa[2], lane::select(cam, F(o.z), LD(a.ray_soa[2])));
                ST(a.ray_soa[3], lane::select(cam, d.x, LD(a.ray_soa[3])));
                ST(a.ray_soa[4], lane::select(cam, d.y, LD(a.ray_soa[4])));
                ST(a.ray_soa[5], lane::select(cam, d.z, LD(a.ray_soa[5])));
                ST(a.ray_soa[6], lane::select(cam, F(kInfinity), LD(a.ray_soa[6])));
            }
            if (scene.needs_footprints) {
                for (uint32_t m = lane_bits<F>(a.cam); m; m &= m - 1) {
                    const int i = lowest_lane<F>(m);
                    RayDifferential& r = ray[i];
                    r.has_differentials = true;
                    r.rx_o = r.ry_o = o;
                    r.rx_d = Vec3f(b[3][i], b[4][i], b[5][i]);
                    r.ry_d = Vec3f(b[6][i], b[7][i], b[8][i]);
                }
            }
            SM(a.cam, M(false));
        };
        // The paths of the lanes esc_b whose rays escaped end: they add the radiance of the lights at
        // infinity, MIS-weighted as the packet pass weighs emission (escaped_radiance, or
        // path_services::escaped for lights without a table row), hand their estimates over, and
        // their lanes start the next paths.
        auto end_escaped = [&](const bool* esc_b) {
            const M esc = LM(esc_b);
            RGB<F> Le(F(0.f));
            if (!ps.lights.infinite.empty()) {
                // (The other lanes look along +z: a direction the lights take without a NaN.)
                const V3<F> d = lane::select(esc, V3<F>(LD(a.ray_soa[3]), LD(a.ray_soa[4]), LD(a.ray_soa[5])),
                                             V3<F>(F(0.f), F(0.f), F(1.f)));
                run_on_lanes<F>(esc, [&](const auto& c) {
                    c.put(Le, escaped_radiance<typename std::decay_t<decltype(c)>::L>(
                                  ps.lights, c.in(d), ps.use_mis, ps.use_nee, c.in(LM(a.specular)), c.in(LD(a.prev_pdf))));
                });
            } else if (!scene.infinite_lights.empty()) {  // (without lights at infinity, Le is 0)
                alignas(64) float e[3][W];
                for (int i = 0; i < W; ++i) {
                    Spectrum l(0.f);
                    if (esc_b[i]) {
                        const LightSampleContext prev{Vec3f(a.ppx[i], a.ppy[i], a.ppz[i]),
                                                      Vec3f(a.pnx[i], a.pny[i], a.pnz[i])};
                        l = path_services::escaped(ps, prev, lane_ray(i).d, a.specular[i], a.prev_pdf[i]);
                    }
                    e[0][i] = l.r, e[1][i] = l.g, e[2][i] = l.b;
                }
                Le = RGB<F>(LD(e[0]), LD(e[1]), LD(e[2]));
            }
            const RGB<F> beta(LD(a.br), LD(a.bg), LD(a.bb));
            const RGB<F> L0(LD(a.Lr), LD(a.Lg), LD(a.Lb));
            const RGB<F> L = lane::select(esc, L0 + beta * Le * F(1.f), L0);
            ST(a.Lr, L.r), ST(a.Lg, L.g), ST(a.Lb, L.b);
            for (uint32_t m = lane_bits<F>(esc_b); m; m &= m - 1) {
                const int i = lowest_lane<F>(m);
                done[size_t(path_of[i])].L = Spectrum(a.Lr[i], a.Lg[i], a.Lb[i]);
            }
            start_lanes(esc_b);
        };
        {
            bool all[W];
            std::fill(all, all + W, true);
            start_lanes(all);
        }
        camera_rays();
        for (;;) {
            bool any = false;
            for (int i = 0; i < W; ++i) {
                any |= active[i];  // (bitwise: no branch a lane)
                a.traced[i] = active[i] & !pending_exit[i];  // idle lanes hold no ray
            }
            if (!any) break;
            const float* const ray_soa[7] = {a.ray_soa[0], a.ray_soa[1], a.ray_soa[2], a.ray_soa[3],
                                             a.ray_soa[4], a.ray_soa[5], a.ray_soa[6]};
            path_services::trace_lanes(scene, W, ray_soa, a.traced, hl, hit);
            if (ps.prefetch_hits) prefetch_index_rows<W>(scene, hl.geom_id, hl.prim_id, hit);
            // Hit records (below, after the restarts): full ones one lane at a time (Scene::fill_hit),
            // then the vertices of the lanes that need no more, as packets (the same templates
            // fill_hit uses, so the same bits).
            auto record_hit = [&](int i) {
                full[i] = true;
                deferred[i] = false;
                if (!hit[i]) return;
                lane_ray(i);
                const RayHit h = hl.lane(i);
                const ShapeRecord& s = scene.shapes[h.geom_id];
                mat_of[i] = s.face_materials.empty() ? s.material : s.face_materials[h.prim_id];
                light_of[i] = s.light;
                if (ps.media && medium[i] >= 0) {  // (made after distance sampling, if still needed)
                    deferred[i] = true;
                    return;
                }
                if (!vertex_lanes || s.light >= 0 || ps.packet_kind[mat_of[i]] == kBSDFLane ||
                    (scene.needs_footprints && is_specular(BxDFFlags(ps.packet_flags[mat_of[i]])))) {
                    scene.fill_hit(ray[i], h, si[i], scene.has_textures);
                    return;
                }
                full[i] = false;
                a.wox[i] = -ray[i].d.x, a.woy[i] = -ray[i].d.y, a.woz[i] = -ray[i].d.z;
                fetch_hit_vertex(scene, ray[i], h, i, hv);
            };
            // Lanes whose rays escaped end their paths here and, when they are at least
            // kRestartMinLanes, start the next ones at once, whose camera rays are traced before the
            // packet pass: the pass then shades more hits per packet (bench/dispatch_stats.py;
            // fewer would cost a packet trace for too little). Each path draws its numbers from its
            // own seeding and its estimate goes to its own slot of `done`, so the image is the same
            // bits. Scenes with media or subsurface scattering, whose escapes take more steps, do not.
            if (vertex_lanes && next < n_paths) {
                alignas(64) bool esc_b[W];
                int n_esc = 0;
                for (int i = 0; i < W; ++i) {
                    esc_b[i] = active[i] & !hit[i];
                    n_esc += esc_b[i];
                }
                if (n_esc >= kRestartMinLanes) {
                    end_escaped(esc_b);
                    for (int i = 0; i < W; ++i) esc_b[i] = esc_b[i] & active[i];  // the lanes that started a path
                    camera_rays();
                    HitLanes hl2;
                    bool hit2[W];
                    path_services::trace_lanes(scene, W, ray_soa, esc_b, hl2, hit2);
                    if (ps.prefetch_hits) prefetch_index_rows<W>(scene, hl2.geom_id, hl2.prim_id, hit2);
                    for (int i = 0; i < W; ++i) {
                        if (!esc_b[i]) continue;
                        hl.t[i] = hl2.t[i], hl.geom_id[i] = hl2.geom_id[i], hl.prim_id[i] = hl2.prim_id[i];
                        hl.u[i] = hl2.u[i], hl.v[i] = hl2.v[i];
                        hit[i] = hit2[i];
                    }
                }
            }
            // Lanes whose hit is a triangle of the triangle table with a vertex-lane material
            // (PathSetup::tri_table) take their vertices as packets, gathered by triangle; the
            // others record theirs one lane at a time.
            alignas(64) bool vl[W];
            M vl_m(false);
            IntT<F> vl_mat(0);
            if (!ps.tri_base.empty()) {
                using I = IntT<F>;
                const auto hit_i = lane::int_mask(LM(hit));
                const I geom = lane::select(hit_i, lane::load_int_as<I>(reinterpret_cast<const int32_t*>(hl.geom_id)), I(0));
                const I base = lane::gather(ps.tri_base.data(), geom);
                const auto in_table = hit_i && base >= I(0);
                const I prim = lane::load_int_as<I>(reinterpret_cast<const int32_t*>(hl.prim_id));
                const I row = lane::select(in_table, base + prim, I(0)) * I(PathSetup::kTriStride);
                const float* tab = ps.tri_table.data();
                vl_mat = lane::as_int(lane::gather(tab, row + I(21)));
                const auto vl_i = in_table && vl_mat >= I(0);
                vl_m = lane::float_mask(vl_i);
                vl_mat = lane::select(vl_i, vl_mat, I(0));
            }
            M svl_m(false);  // the sphere table's lanes
            alignas(64) float sl[3][W];  // their hits' directions from the centre in object space (tex_lanes)
            F sph[15];       // their rows: centre, radius, rotation, flip, material (PathSetup::sphere_table)
            if (!ps.sphere_row.empty()) {
                using I = IntT<F>;
                const auto hit_i = lane::int_mask(LM(hit));
                const I geom = lane::select(hit_i, lane::load_int_as<I>(reinterpret_cast<const int32_t*>(hl.geom_id)), I(0));
                const I srow = lane::gather(ps.sphere_row.data(), geom);
                const auto in_table = hit_i && srow >= I(0);
                std::fill(sph, sph + 15, F(0.f));
                sph[14] = lane::as_float(I(-1));
                rows_by_lane<F>(ps.sphere_table.data(), PathSetup::kSphereStride, srow, lane::float_mask(in_table), 15, sph);
                const I smat = lane::as_int(sph[14]);
                const auto svl_i = in_table && smat >= I(0);
                svl_m = lane::float_mask(svl_i);
                vl_mat = lane::select(svl_i, smat, vl_mat);
                vl_m = vl_m || svl_m;
            }
            SM(vl, vl_m);
            if (ps.prefetch_hits) {  // (the lanes vl read the shape tables' rows)
                alignas(64) bool take[W];
                for (int i = 0; i < W; ++i) take[i] = hit[i] & !vl[i];
                prefetch_vertices<W>(scene, hl.geom_id, hl.prim_id, take);
            }
            hv.clear();
            for (int i = 0; i < W; ++i) {
                if (vl[i]) {
                    full[i] = false, light_of[i] = -1;
                    continue;
                }
                record_hit(i);
            }
            if (hv.any()) {
                // Lanes with full records overwrite theirs (load_vertex) where their paths go on.
                const HitVertexT<F> v = hit_vertices<F>(hv);
                ST(a.px, v.p.x), ST(a.py, v.p.y), ST(a.pz, v.p.z);
                ST(a.pex, v.p_error.x), ST(a.pey, v.p_error.y), ST(a.pez, v.p_error.z);
                ST(a.ngx, v.ng.x), ST(a.ngy, v.ng.y), ST(a.ngz, v.ng.z);
                ST(a.sx, v.shading.s.x), ST(a.sy, v.shading.s.y), ST(a.sz, v.shading.s.z);
                ST(a.tx, v.shading.t.x), ST(a.ty, v.shading.t.y), ST(a.tz, v.shading.t.z);
                ST(a.nx, v.shading.n.x), ST(a.ny, v.shading.n.y), ST(a.nz, v.shading.n.z);
            }
            if (lane::any(svl_m)) {
                // The sphere table's lanes' vertices (sphere_vertex, as fetch_hit_vertex's lanes).
                auto G = [&](int k) { return sph[k]; };
                auto GV = [&](int k) { return V3<F>(G(k), G(k + 1), G(k + 2)); };
                const V3<F> o(LD(a.ray_soa[0]), LD(a.ray_soa[1]), LD(a.ray_soa[2]));
                const V3<F> d(LD(a.ray_soa[3]), LD(a.ray_soa[4]), LD(a.ray_soa[5]));
                SphereTangentsT<F> tangents;
                const HitVertexT<F> v = sphere_vertex<F>(o, d, LD(hl.t), GV(0), G(3), Mat3T<F>{GV(4), GV(7), GV(10)},
                                                         G(13) != F(0.f), &tangents);
                auto put = [&](float* dst, const F& x) { ST(dst, lane::select(svl_m, x, LD(dst))); };
                put(a.px, v.p.x), put(a.py, v.p.y), put(a.pz, v.p.z);
                put(a.pex, v.p_error.x), put(a.pey, v.p_error.y), put(a.pez, v.p_error.z);
                put(a.ngx, v.ng.x), put(a.ngy, v.ng.y), put(a.ngz, v.ng.z);
                put(a.sx, v.shading.s.x), put(a.sy, v.shading.s.y), put(a.sz, v.shading.s.z);
                put(a.tx, v.shading.t.x), put(a.ty, v.shading.t.y), put(a.tz, v.shading.t.z);
                put(a.nx, v.shading.n.x), put(a.ny, v.shading.n.y), put(a.nz, v.shading.n.z);
                put(a.wox, lane::neg(d.x)), put(a.woy, lane::neg(d.y)), put(a.woz, lane::neg(d.z));
                if (!ps.tex_lanes.empty()) {  // (for the lanes of tex_lanes' materials: fill_sphere's tangents, uv)
                    put(a.dux, tangents.dpdu.x), put(a.duy, tangents.dpdu.y), put(a.duz, tangents.dpdu.z);
                    put(a.dvx, tangents.dpdv.x), put(a.dvy, tangents.dpdv.y), put(a.dvz, tangents.dpdv.z);
                    ST(sl[0], tangents.local.x), ST(sl[1], tangents.local.y), ST(sl[2], tangents.local.z);
                }
            }
            if (lane::any(vl_m && !svl_m)) {
                // The triangle table's lanes' vertices (flat_triangle_vertex, as fetch_hit_vertex's lanes).
                const M tvl_m = vl_m && !svl_m;
                using I = IntT<F>;
                const float* tab = ps.tri_table.data();
                const I geom = lane::select(lane::int_mask(tvl_m), lane::load_int_as<I>(reinterpret_cast<const int32_t*>(hl.geom_id)), I(0));
                const I prim = lane::load_int_as<I>(reinterpret_cast<const int32_t*>(hl.prim_id));
                const I row = (lane::gather(ps.tri_base.data(), geom) + prim) * I(PathSetup::kTriStride);
                const I rows = lane::select(lane::int_mask(tvl_m), row, I(0));
                // Each lane's row as two row reads (16 and 8 floats) transposed into packets, not a
                // gather per entry (lane::gather_rows).
                F rw[PathSetup::kTriStride];
                static_assert(PathSetup::kTriStride == 24, "a triangle row is read as 16 + 8 floats");
                lane::gather_rows<16>(tab, rows, rw);
                lane::gather_rows<8>(tab, rows + I(16), rw + 16);
                auto G = [&](int k) { return rw[k]; };
                auto GV = [&](int k) { return V3<F>(G(k), G(k + 1), G(k + 2)); };
                const HitVertexT<F> v = flat_triangle_vertex<F>(GV(0), GV(3), GV(6), LD(hl.u), LD(hl.v), GV(9),
                                                                FrameT<F>(GV(12), GV(15), GV(18)));
                auto put = [&](float* dst, const F& x) { ST(dst, lane::select(tvl_m, x, LD(dst))); };
                put(a.px, v.p.x), put(a.py, v.p.y), put(a.pz, v.p.z);
                put(a.pex, v.p_error.x), put(a.pey, v.p_error.y), put(a.pez, v.p_error.z);
                put(a.ngx, v.ng.x), put(a.ngy, v.ng.y), put(a.ngz, v.ng.z);
                put(a.sx, v.shading.s.x), put(a.sy, v.shading.s.y), put(a.sz, v.shading.s.z);
                put(a.tx, v.shading.t.x), put(a.ty, v.shading.t.y), put(a.tz, v.shading.t.z);
                put(a.nx, v.shading.n.x), put(a.ny, v.shading.n.y), put(a.nz, v.shading.n.z);
                put(a.wox, lane::neg(LD(a.ray_soa[3]))), put(a.woy, lane::neg(LD(a.ray_soa[4])));
                put(a.woz, lane::neg(LD(a.ray_soa[5])));
            }
            if (ps.subsurface)
                for (int i = 0; i < W; ++i)
                    if (active[i] && pending_exit[i]) si[i] = exit_si[i], hit[i] = true;

            // A vertex's random numbers (path_services::randoms' layout: u0–u2 for NEE, u3–u5 for
            // the BSDF, u6 for roulette). The independent sampler's come straight from the lane's
            // PCG32 stream, in the order randoms() draws them.
            auto draw_randoms = [&](int i, int depth) {
                const bool rr = depth >= ps.rr_depth;
                if (ps.sampler != SamplerType::Independent) {
                    VertexRandoms r;
                    path_services::randoms(sampler[i], depth, a.nee[i], rr, &r);
                    for (int k = 0; k < 7; ++k) a.u[k][i] = r.u[k];
                    return;
                }
                a.draw0[i] = a.nee[i] ? 0 : 3, a.draw1[i] = rr ? 7 : 6;  // drawn below, for all lanes at once
            };
            // The independent sampler's numbers u[draw0, draw1) of every lane, drawn from the lanes'
            // PCG32 streams side by side (Arrays::rs, ri): each step for all lanes (lanes outside
            // their range keep theirs), eight streams at a time (PCG32x8).
            auto draw_independent = [&]() {
                uint64_t* const st = a.rs;
                const uint64_t* const inc = a.ri;
                if constexpr (W % 8 == 0) {  // eight streams at a time (PCG32x8: the same bits)
                    using X = PCG32x8;
                    using X4 = PCG32x4;
                    for (int b = 0; b < W; b += 8) {
                        // Only the numbers some lane of the eight draws: [lo, hi) (none for lanes
                        // that do not go on, u0–u2 only where a lane takes a light sample, u6 only
                        // under roulette).
                        int lo = 7, hi = 0;
                        for (int i = b; i < b + 8; ++i)
                            if (a.draw0[i] < a.draw1[i]) lo = std::min(lo, a.draw0[i]), hi = std::max(hi, a.draw1[i]);
                        if (lo >= hi) continue;
                        X::State s0 = X4::load<X::State>(st + b), s1 = X4::load<X::State>(st + b + 4);
                        const X::State c0 = X4::load<X::State>(inc + b), c1 = X4::load<X::State>(inc + b + 4);
                        const X::I32 d0 = X::load<X::I32>(a.draw0 + b), d1 = X::load<X::I32>(a.draw1 + b);
                        for (int k = lo; k < hi; ++k) {
                            const X::I32 kv = X::I32{} + k;
                            const X::I32 draw = (kv >= d0) & (kv < d1);
                            X::store(a.u[k] + b, draw ? X::to_float(X::output(s0, s1)) : X::load<X::F32>(a.u[k] + b));
                            s0 = X::low_mask(draw) ? X4::step(s0, c0) : s0;
                            s1 = X::high_mask(draw) ? X4::step(s1, c1) : s1;
                        }
                        X4::store(st + b, s0), X4::store(st + b + 4, s1);
                    }
                } else {
                    for (int k = 0; k < 7; ++k) {
                        for (int i = 0; i < W; ++i) {
                            const bool draw = (k >= a.draw0[i]) & (k < a.draw1[i]);
                            const uint64_t old = st[i];
                            const float u = PCG32::to_float(PCG32::output(old));
                            a.u[k][i] = draw ? u : a.u[k][i];
                            st[i] = draw ? PCG32::step(old, inc[i]) : old;
                        }
                    }
                }
            };
            // The lanes `goes` go on from their hit, those of `nee` with next-event estimation: their
            // numbers for this vertex are due (as draw_randoms gives them, lane by lane).
            auto go_on = [&](const M& goes, const M& nee) {
                using I = IntT<F>;
                SM(a.goes_on, goes || LM(a.goes_on));
                SM(a.nee, nee || LM(a.nee));
                if (ps.sampler == SamplerType::Independent) {
                    const auto goes_i = lane::int_mask(goes);
                    lane::store(a.draw0, lane::select(goes_i, lane::select(lane::int_mask(nee), I(0), I(3)),
                                                      lane::load_int_as<I>(a.draw0)));
                    lane::store(a.draw1, lane::select(goes_i, lane::select(lane::int_mask(LD(a.depth) >= F(float(ps.rr_depth))), I(7), I(6)),
                                                      lane::load_int_as<I>(a.draw1)));
                } else {
                    alignas(64) bool g[W];
                    SM(g, goes);
                    for (uint32_t m = lane_bits<F>(g); m; m &= m - 1) {
                        const int i = lowest_lane<F>(m);
                        draw_randoms(i, int(a.depth[i]));
                    }
                }
            };
            // The lanes `in` of material t of PathSetup::tex_lanes (their vertex, uv and tangents in
            // the arrays): what Scene::textured_bsdf builds at each hit, as packets, bit for bit: the
            // Lambertian's reflectance or the plastic's Kd as TexEval gives it (texture_lanes.h,
            // checkerboard_square) and the parameters from it, the bump-mapped
            // normal of BumpModel::Mitsuba from the bilinear luminance gradient (textured.cpp,
            // texture.cpp), the invalid normals mirrored, the frame and the softened terminator;
            // their packet form then shades them.
            auto shade_tex_lanes = [&](const PathSetup::TexLaneMaterial& t, const M& in) {
                SM(a.fast, in || LM(a.fast));
                M goes = in;
                // On the lanes of a FormLanes c (run_on_lanes): the textures' gathers, the bump and
                // the frame on 8 lanes where at most 8 take part.
                run_on_lanes<F>(in, [&](const auto& c) {
                    using L = typename std::decay_t<decltype(c)>::L;
                    using TL = PathSetup::TexLaneMaterial;
                    auto get = [&](const float* p) { return L(c.in(LD(p))); };
                    auto put = [&](float* p, const L& x) {
                        F d = LD(p);
                        c.put(d, x);
                        ST(p, d);
                    };
                    const L u = get(a.tu), v = get(a.tv);
                    // (s, t) = to_uv(u, v), as UVTransform::point.
                    auto st = [&](const float* m, L* s, L* tt) {
                        *s = (L(m[0]) * u + L(m[1]) * v) + L(m[2]);
                        *tt = (L(m[3]) * u + L(m[4]) * v) + L(m[5]);
                    };
                    RGB<L> q(L(t.albedo[0][0]), L(t.albedo[0][1]), L(t.albedo[0][2]));
                    if (t.reflectance == TL::kImage) {
                        L s, tt;
                        st(t.to_uv, &s, &tt);
                        lane_bilinear<L>(t.image, s, tt, &q);
                        auto clamp_t = [&](const L& x) {  // (clamp: v < lo ? lo : (v > hi ? hi : v))
                            return lane::select(x < L(t.lo), L(t.lo), lane::select(x > L(t.hi), L(t.hi), x));
                        };
                        q = RGB<L>(clamp_t(q.r), clamp_t(q.g), clamp_t(q.b));
                    } else if (t.reflectance == TL::kChecker) {
                        // The colour of the square the hit lies in (w is 0 or 1: one colour's albedo
                        // exactly, or NaN where the uv is not finite, as eval_texture's).
                        const L uv_map[6] = {L(t.to_uv[0]), L(t.to_uv[1]), L(t.to_uv[2]),
                                             L(t.to_uv[3]), L(t.to_uv[4]), L(t.to_uv[5])};
                        const L w = checkerboard_square<L>(uv_map, u, v), w0 = L(1.f) - w;
                        q = RGB<L>(L(t.albedo[0][0]) * w0 + L(t.albedo[1][0]) * w, L(t.albedo[0][1]) * w0 + L(t.albedo[1][1]) * w,
                                   L(t.albedo[0][2]) * w0 + L(t.albedo[1][2]) * w);
                    }
                    put(a.kind, L(float(t.kind)));
                    if (t.kind == kPacketLambertian) {
                        put(a.q[0], q.r), put(a.q[1], q.g), put(a.q[2], q.b);
                        c.put(goes, c.in(in) && !is_black(q));  // (Lambertian::flags: none for a black albedo, the path ends)
                    } else {
                        // A rough plastic: the material's parameters with Kd's (PlasticBase, plastic_packet_params).
                        for (int k = 0; k < kPlasticParams; ++k) {
                            L x(t.q[k]);
                            if (k >= 1 && k <= 3) x = plastic_diffuse_scale<L>(k == 1 ? q.r : k == 2 ? q.g : q.b, t.eta, t.rbar, t.variant);
                            if (k == 8) x = (q.r + q.g + q.b) * L(1.f / 3.f);  // (Spectrum::average)
                            put(a.q[k], x);
                        }
                    }
                    if (t.bump) {
                        // mitsuba_height_gradient: the luminance of the bilinear gradient through to_uv
                        // (∂f/∂u = a00·∂f/∂s + a10·∂f/∂t, ∂f/∂v = a01·∂f/∂s + a11·∂f/∂t); 0 for a constant.
                        L gu(0.f), gv(0.f);
                        if (t.bump_image) {
                            L s, tt;
                            st(t.height_uv, &s, &tt);
                            RGB<L> h, ds, dt;
                            lane_bilinear<L>(t.height, s, tt, &h, &ds, &dt);
                            const float* m = t.height_uv;
                            const RGB<L> du = ds * L(m[0]) + dt * L(m[3]), dv = ds * L(m[1]) + dt * L(m[4]);
                            gu = L(0.2126f) * du.r + L(0.7152f) * du.g + L(0.0722f) * du.b;  // (Spectrum::luminance)
                            gv = L(0.2126f) * dv.r + L(0.7152f) * dv.g + L(0.0722f) * dv.b;
                        }
                        auto get3 = [&](const float* x, const float* y, const float* z) { return V3<L>(get(x), get(y), get(z)); };
                        const FrameT<L> shading(get3(a.sx, a.sy, a.sz), get3(a.tx, a.ty, a.tz), get3(a.nx, a.ny, a.nz));
                        const V3<L> dpdu = get3(a.dux, a.duy, a.duz), dpdv = get3(a.dvx, a.dvy, a.dvz);
                        const V3<L> ng = get3(a.ngx, a.ngy, a.ngz), wo = get3(a.wox, a.woy, a.woz);
                        V3<L> n = bump_normal_mitsuba_lanes<L>(dpdu, dpdv, ng, shading.n, L(t.bump_scale), gu, gv);
                        if (t.mirror) n = mirror_invalid_normal<L>(shading, wo, n);
                        const FrameT<L> f = FrameT<L>::from_xz(shading.s, n);
                        put(a.sx, f.s.x), put(a.sy, f.s.y), put(a.sz, f.s.z);
                        put(a.tx, f.t.x), put(a.ty, f.t.y), put(a.tz, f.t.z);
                        put(a.nx, f.n.x), put(a.ny, f.n.y), put(a.nz, f.n.z);
                        // (about the unperturbed shading normal, BSDF::soften_terminator)
                        if (t.soften) put(a.n0x, shading.n.x), put(a.n0y, shading.n.y), put(a.n0z, shading.n.z);
                    }
                });
                if (t.bump && t.soften) {
                    SM(a.soft, in || LM(a.soft));
                    SM(a.est, lane::select(in, M(t.estevez), LM(a.est)));
                }
                go_on(goes, goes && M(ps.use_nee));  // (diffuse or glossy: with NEE)
            };
            // One lane at a time: what has no packet form yet.
            for (bool* f : {a.fast, a.goes_on, a.nee, a.nee_ok, a.s_ok, a.delta, a.plight, a.in_medium, a.crossing, a.at_exit,
                            a.to_exit, a.esc, a.soft, a.tl})
                SM(f, M(false));
            for (float* f : {a.Ler, a.Leg, a.Leb, a.le_pdf, a.kind}) ST(f, F(0.f));
            lane::store(a.draw0, IntT<F>(0)), lane::store(a.draw1, IntT<F>(0));
            // The distance sampling of the lanes in homogeneous media, as packets: each draws its
            // two numbers from its medium stream, as medium_sample would in the loop below (nothing
            // else draws from it in between), and the loop takes the event from hm_*.
            alignas(64) bool hm[W]{};
            alignas(64) float hm_t[W], hm_w[3][W], hm_e[3][W];
            alignas(64) bool hm_scat[W];
            if (ps.media && ps.any_homogeneous) {
                bool any_hm = false;
                for (int i = 0; i < W; ++i) {  // (no branch a lane: selects and bitwise operators)
                    const bool in = active[i] & !vl[i] & !pending_exit[i] & (medium[i] >= 0);
                    hm[i] = in & (ps.homogeneous_media[size_t(in ? medium[i] : 0)] != 0);
                    any_hm |= hm[i];
                }
                if (any_hm) {
                    alignas(64) float u_c[W], u_t[W], tmax[W];
                    alignas(64) int32_t mrow[W];
                    for (int i = 0; i < W; ++i) {
                        // (All lanes, so that the loop vectorises; the others keep their states.)
                        const uint64_t s0 = medium_rng[i].state(), inc = medium_rng[i].increment();
                        const uint64_t s1 = PCG32::step(s0, inc);
                        u_c[i] = PCG32::to_float(PCG32::output(s0)), u_t[i] = PCG32::to_float(PCG32::output(s1));
                        medium_rng[i].set_state(hm[i] ? PCG32::step(s1, inc) : s0);
                        tmax[i] = hit[i] ? hl.t[i] : kInfinity;  // (its record deferred: fill_hit's si.t is hl.t)
                        mrow[i] = hm[i] ? medium[i] * PathSetup::kMediumStride : 0;
                    }
                    using I = IntT<F>;
                    F row[PathSetup::kMediumStride];
                    lane::gather_rows<PathSetup::kMediumStride>(ps.medium_rows.data(), lane::load_int_as<I>(mrow), row);
                    const V3<F> d(LD(a.ray_soa[3]), LD(a.ray_soa[4]), LD(a.ray_soa[5]));
                    const F len = length(d);
                    const F st[3] = {row[0] * len, row[1] * len, row[2] * len};
                    const F ss[3] = {row[3] * len, row[4] * len, row[5] * len};
                    // (medium_sample's channel choice: by the throughput, or uniform.)
                    const F one(1.f);
                    const F beta[3] = {ps.uniform_channels ? one : LD(a.br), ps.uniform_channels ? one : LD(a.bg),
                                       ps.uniform_channels ? one : LD(a.bb)};
                    const HomogeneousStepT<F> h = homogeneous_step<F>(st, ss, row + 6, beta, LD(u_c), LD(u_t), LD(tmax));
                    SM(hm_scat, h.scattered);
                    ST(hm_t, h.t);
                    for (int c = 0; c < 3; ++c) ST(hm_w[c], h.weight[c]), ST(hm_e[c], h.emitted[c]);
                }
            }
            for (uint32_t m = lane_bits<F>(active) & ~lane_bits<F>(vl); m; m &= m - 1) {
                const int i = lowest_lane<F>(m);  // (not the table lanes: below, as packets)
                lane_ray(i);
                const LightSampleContext prev{Vec3f(a.ppx[i], a.ppy[i], a.ppz[i]), Vec3f(a.pnx[i], a.pny[i], a.pnz[i])};
                if (pending_exit[i]) {
                    // A BSSRDF's exit point: its exit lobe scatters, with NEE (no emission is
                    // found here, and the entry already passed the depth check).
                    pending_exit[i] = false;
                    a.at_exit[i] = true;
                    const SurfaceInteraction& h = si[i];
                    load_vertex(i, h);
                    a.goes_on[i] = true;
                    a.nee[i] = ps.use_nee;
                    const int depth = int(a.depth[i]);
                    draw_randoms(i, depth);
                    continue;
                }
                if (ps.media) {
                    // The segment up to the surface (or to infinity) runs through the lane's medium:
                    // distance sampling either finds a collision there or passes, reweighting the
                    // throughput either way (medium/medium.h).
                    if (medium[i] >= 0) {
                        Ray seg = ray[i];
                        seg.tmax = hit[i] ? (deferred[i] ? hl.t[i] : si[i].t) : kInfinity;  // (fill_hit's si.t is hl.t)
                        const Spectrum beta(a.br[i], a.bg[i], a.bb[i]);
                        MediumEvent e;
                        if (hm[i]) {
                            e.scattered = hm_scat[i];
                            e.t = hm_scat[i] ? hm_t[i] : 0.f;
                            e.weight = Spectrum(hm_w[0][i], hm_w[1][i], hm_w[2][i]);
                            e.emitted = Spectrum(hm_e[0][i], hm_e[1][i], hm_e[2][i]);
                        } else {
                            e = path_services::medium_sample(ps, medium[i], seg, beta, medium_rng[i]);
                        }
                        a.Lr[i] += beta.r * e.emitted.r, a.Lg[i] += beta.g * e.emitted.g, a.Lb[i] += beta.b * e.emitted.b;
                        a.br[i] *= e.weight.r, a.bg[i] *= e.weight.g, a.bb[i] *= e.weight.b;
                        if (e.scattered) {
                            a.in_medium[i] = true;
                            path_services::medium_vertex(ray[i], e.t, &si[i]);
                            const int depth = int(a.depth[i]);
                            if (depth >= ps.max_depth) continue;
                            if (a.br[i] == 0.f && a.bg[i] == 0.f && a.bb[i] == 0.f) continue;
                            const SurfaceInteraction& h = si[i];
                            load_vertex(i, h);  // no surface: zero normal and error bound
                            a.goes_on[i] = true;
                            a.nee[i] = ps.use_nee && ps.medium_nee;
                            draw_randoms(i, depth);
                            continue;
                        }
                    }
                    if (deferred[i]) scene.fill_hit(ray[i], hl.lane(i), si[i], scene.has_textures);
                    // A null boundary: the path goes on in the same direction, in the medium on
                    // its other side (bounded, so rays cannot cross forever).
                    if (hit[i] && path_services::is_null_surface(ps, si[i])) {
                        if (++crossings[i] > 1024) continue;
                        medium[i] = path_services::medium_after(ps, si[i], ray[i].d, medium[i]);
                        ray[i] = path_services::cross_boundary(si[i], ray[i].d);
                        set_ray_soa(i);
                        a.crossing[i] = true;
                        continue;
                    }
                }
                if (!hit[i] && !ps.lights.infinite.empty()) {  // escaped: the lights at infinity, below
                    a.esc[i] = true;
                    a.edx[i] = ray[i].d.x, a.edy[i] = ray[i].d.y, a.edz[i] = ray[i].d.z;
                    a.le_pdf[i] = -1.f;  // weighted already
                    continue;
                }
                if (!hit[i]) {  // escaped: the lights at infinity
                    const Spectrum Le = path_services::escaped(ps, prev, ray[i].d, a.specular[i], a.prev_pdf[i]);
                    a.Ler[i] = Le.r;
                    a.Leg[i] = Le.g;
                    a.Leb[i] = Le.b;
                    a.le_pdf[i] = -1.f;  // weighted already
                    continue;
                }
                const SurfaceInteraction& h = si[i];
                if (light_of[i] >= 0) {  // (a full record)
                    const Spectrum Le = path_services::emitted(ps, h, prev, ray[i].d, a.specular[i], &a.le_pdf[i]);
                    a.Ler[i] = Le.r;
                    a.Leg[i] = Le.g;
                    a.Leb[i] = Le.b;
                }
                const int depth = int(a.depth[i]);
                if (depth >= ps.max_depth) continue;
                if (full[i]) load_vertex(i, h);
                BxDFFlags flags;
                if (const int32_t kind = ps.packet_kind[mat_of[i]]; kind != kBSDFLane) {
                    a.fast[i] = true;
                    a.kind[i] = float(kind);
                    const float* q = &ps.packet_params[kPacketParams * size_t(mat_of[i])];
                    for (int k = 0, n = ps.packet_count[mat_of[i]]; k < n; ++k) a.q[k][i] = q[k];
                    flags = BxDFFlags(ps.packet_flags[mat_of[i]]);
                    // Delta bounces carry ray differentials on from the hit's footprint.
                    if (scene.needs_footprints && full[i]) path_services::footprint(ps, si[i], ray[i]);
                } else if (ps.tex_lane[mat_of[i]] >= 0) {
                    // Its textures and parameters below, for all such lanes at once (shade_tex_lanes).
                    a.tl[i] = true;
                    a.tu[i] = h.uv.x, a.tv[i] = h.uv.y;
                    a.dux[i] = h.dpdu.x, a.duy[i] = h.dpdu.y, a.duz[i] = h.dpdu.z;
                    a.dvx[i] = h.dpdv.x, a.dvy[i] = h.dpdv.y, a.dvz[i] = h.dpdv.z;
                    continue;
                } else {
                    flags = path_services::bsdf_begin(ps, si[i], ray[i], &bsdf(i));
                    // A textured (or bump- or normal-mapped) material whose BSDF here has a packet
                    // form: its parameters and shading frame go to the packet pass.
                    float q[kPacketParams];
                    int32_t form;
                    if (ps.textured_packet[mat_of[i]] && (form = path_services::packet_form(ps, mat_of[i], bsdf(i), q)) != kBSDFLane) {
                        a.fast[i] = true;
                        a.kind[i] = float(form);
                        for (int k = 0, n = packet_param_count(form); k < n; ++k) a.q[k][i] = q[k];
                        const Frame& f = bsdf(i).frame();
                        a.sx[i] = f.s.x, a.sy[i] = f.s.y, a.sz[i] = f.s.z;
                        a.tx[i] = f.t.x, a.ty[i] = f.t.y, a.tz[i] = f.t.z;
                        a.nx[i] = f.n.x, a.ny[i] = f.n.y, a.nz[i] = f.n.z;
                        if (bsdf(i).softens()) {
                            a.soft[i] = true;
                            a.est[i] = bsdf(i).terminator_model() == TerminatorModel::Estevez;
                            const Normal3f& n0 = bsdf(i).terminator_normal();
                            a.n0x[i] = n0.x, a.n0y[i] = n0.y, a.n0z[i] = n0.z;
                        }
                    }
                }
                if (flags == BxDFFlags::None) continue;
                a.goes_on[i] = true;
                a.nee[i] = ps.use_nee && is_non_specular(flags);
                draw_randoms(i, depth);
            }
            if (lane::any(vl_m)) {
                // The table lanes: a hit with a packet form, no emission and a full vertex, as the
                // loop above takes such a lane, for all of them at once.
                using I = IntT<F>;
                const F depth = LD(a.depth);
                const M fast = vl_m && depth < F(float(ps.max_depth));
                const I kind = lane::gather(ps.packet_kind.data(), vl_mat);
                const I flags = lane::gather(reinterpret_cast<const int32_t*>(ps.packet_flags.data()), vl_mat);
                SM(a.fast, fast || LM(a.fast));
                ST(a.kind, lane::select(fast, lane::to_float(kind), LD(a.kind)));
                const I qrow = vl_mat * I(kPacketParams);
                const int nq = ps.max_packet_count;
                if (nq <= 4) {
                    for (int k = 0; k < nq; ++k)
                        ST(a.q[k], lane::select(fast, lane::gather(ps.packet_params.data(), qrow + I(k)), LD(a.q[k])));
                } else {
                    // Each lane's row read as a row (8, 16 or 16 + 8 floats) and transposed into
                    // packets, not a gather per parameter (lane::gather_rows; the rows end in
                    // PathSetup::kPacketParamsPad zeros).
                    static_assert(kPacketParams <= 24 && PathSetup::kPacketParamsPad >= 24 - kPacketParams, "a row is read as 16 + 8 floats");
                    F qv[24];
                    if (nq <= 8) {
                        lane::gather_rows<8>(ps.packet_params.data(), qrow, qv);
                    } else {
                        lane::gather_rows<16>(ps.packet_params.data(), qrow, qv);
                        if (nq > 16) lane::gather_rows<8>(ps.packet_params.data(), qrow + I(16), qv + 16);
                    }
                    for (int k = 0; k < nq; ++k) ST(a.q[k], lane::select(fast, qv[k], LD(a.q[k])));
                }
                if (!ps.tex_lanes.empty()) {
                    // Table lanes of PathSetup::tex_lanes' materials: their uv and tangents for
                    // shade_tex_lanes below (a triangle's from tri_uv; a sphere's tangents are in
                    // the arrays already, its uv one lane at a time, as fill_hit computes it).
                    const M tx = fast && lane::float_mask(lane::gather(ps.tex_lane.data(), vl_mat) >= I(0));
                    if (lane::any(tx)) {
                        SM(a.tl, tx || LM(a.tl));
                        lane::store(reinterpret_cast<int32_t*>(mat_of),
                                    lane::select(lane::int_mask(tx), vl_mat, lane::load_int_as<I>(reinterpret_cast<const int32_t*>(mat_of))));
                        const M ttx = tx && !svl_m;
                        if (lane::any(ttx)) {
                            // The triangle's row of tri_uv, and the uv as fill_hit interpolates it.
                            const auto ti = lane::int_mask(ttx);
                            const I geom = lane::select(ti, lane::load_int_as<I>(reinterpret_cast<const int32_t*>(hl.geom_id)), I(0));
                            const I prim = lane::load_int_as<I>(reinterpret_cast<const int32_t*>(hl.prim_id));
                            const I tri = lane::select(ti, lane::gather(ps.tri_base.data(), geom) + prim, I(0));
                            F row[PathSetup::kTriUVStride];
                            static_assert(PathSetup::kTriUVStride == 16, "a triangle's uvs (8 floats) and tangents are one row");
                            if (ps.tex_tangents) lane::gather_rows<16>(ps.tri_uv.data(), tri * I(PathSetup::kTriUVStride), row);
                            else lane::gather_rows<8>(ps.tri_uv.data(), tri * I(PathSetup::kTriUVStride), row);
                            const F b1 = LD(hl.u), b2 = LD(hl.v), b0 = F(1.f) - b1 - b2;
                            const F u = b0 * row[0] + b1 * row[2] + b2 * row[4], v = b0 * row[1] + b1 * row[3] + b2 * row[5];
                            auto put = [&](float* p, const F& x) { ST(p, lane::select(ttx, x, LD(p))); };
                            put(a.tu, u), put(a.tv, v);
                            if (ps.tex_tangents) {
                                put(a.dux, row[8]), put(a.duy, row[9]), put(a.duz, row[10]);
                                put(a.dvx, row[11]), put(a.dvy, row[12]), put(a.dvz, row[13]);
                            }
                        }
                        alignas(64) bool stx[W];
                        SM(stx, tx && svl_m);
                        for (uint32_t m = lane_bits<F>(stx); m; m &= m - 1) {
                            const int i = lowest_lane<F>(m);
                            const Vec2f uv = sphere_uv(Vec3f(sl[0][i], sl[1][i], sl[2][i]));
                            a.tu[i] = uv.x, a.tv[i] = uv.y;
                        }
                    }
                }
                const M goes = fast && lane::float_mask(flags != I(0));
                const M nee = goes && M(ps.use_nee) &&
                              lane::float_mask((flags & I(int32_t(BxDFFlags::Diffuse | BxDFFlags::Glossy))) != I(0));
                go_on(goes, nee);
            }
            if (!ps.tex_lanes.empty()) {
                // The lanes of PathSetup::tex_lanes' materials, one material at a time: its
                // textures, bump map and parameters as packets, then their packet form.
                alignas(64) bool tl[W];
                for (int i = 0; i < W; ++i) tl[i] = a.tl[i];
                for (uint32_t m = lane_bits<F>(tl); m; m = lane_bits<F>(tl)) {
                    const uint32_t mat = mat_of[lowest_lane<F>(m)];
                    alignas(64) bool in[W];
                    for (int i = 0; i < W; ++i) in[i] = tl[i] & (mat_of[i] == mat), tl[i] = tl[i] & !in[i];
                    shade_tex_lanes(ps.tex_lanes[size_t(ps.tex_lane[mat])], LM(in));
                }
            }
            if (ps.sampler == SamplerType::Independent) draw_independent();

            // Escaped rays: the radiance of the lights at infinity (light table), MIS-weighted, for
            // all lanes at once.
            if (!ps.lights.infinite.empty()) {
                const M esc = LM(a.esc);
                if (lane::any(esc)) {
                    const RGB<F> Le = escaped_radiance<F>(ps.lights, V3<F>(LD(a.edx), LD(a.edy), LD(a.edz)), ps.use_mis,
                                                          ps.use_nee, LM(a.specular), LD(a.prev_pdf));
                    ST(a.Ler, lane::select(esc, Le.r, LD(a.Ler)));
                    ST(a.Leg, lane::select(esc, Le.g, LD(a.Leg)));
                    ST(a.Leb, lane::select(esc, Le.b, LD(a.Leb)));
                }
            }

            // Next-event estimation on the emitter table, for all lanes at once: a point on an
            // emitting triangle and the shadow ray toward it (SurfaceInteraction::spawn_ray_to:
            // both ends offset off their surfaces).
            // (Either runs only when some lane takes a light sample: a vertex starts with no lane's
            // nee or nee_ok set.)
            if (!ps.emitters.empty() && lane::any(LM(a.nee))) {
                const M nee = LM(a.nee);
                const V3<F> p(LD(a.px), LD(a.py), LD(a.pz)), ng(LD(a.ngx), LD(a.ngy), LD(a.ngz));
                const EmitterSample<F> es = sample_emitter<F>(ps.emitters, LD(a.u[0]), V2<F>{LD(a.u[1]), LD(a.u[2])}, p);
                SM(a.nee_ok, nee && es.valid);
                ST(a.lwx, es.wi.x), ST(a.lwy, es.wi.y), ST(a.lwz, es.wi.z);
                ST(a.lLr, es.L.r), ST(a.lLg, es.L.g), ST(a.lLb, es.L.b);
                ST(a.lpdf, es.pdf);
                const V3<F> o = offset_ray_origin<F>(p, V3<F>(LD(a.pex), LD(a.pey), LD(a.pez)), ng, es.p - p);
                const V3<F> e = offset_ray_origin<F>(es.p, es.err, es.n, o - es.p);
                const V3<F> d = e - o;
                ST(a.sh[0], o.x), ST(a.sh[1], o.y), ST(a.sh[2], o.z), ST(a.sh[3], d.x), ST(a.sh[4], d.y), ST(a.sh[5], d.z);
                ST(a.sh[6], F(1.f - 1e-4f));
            } else if (ps.lights.any && lane::any(LM(a.nee))) {
                // Next-event estimation on the packet lights: each lane picks its light as
                // path_services::sample_light does, and the lanes whose light has a row in the
                // light table (light_table.h) sample it together; the shadow ray ends at the
                // light's point (spawn_ray_to) or leaves toward infinity (spawn_ray).
                {  // the pick, for every lane at once (pick_light_lanes; lanes without NEE ignore it)
                    F sel;
                    const IntT<F> li = pick_light_lanes<F>(ps.lights, LD(a.u[0]), &sel);
                    lane::store(a.light, li);
                    ST(a.lsel, sel);
                }
                bool any_packet = false;
                for (int i = 0; i < W; ++i) {
                    if (!a.goes_on[i] || !a.nee[i]) continue;
                    a.plight[i] = ps.lights.kind[size_t(a.light[i])] != LightTable::kNone;
                    any_packet = any_packet || a.plight[i];
                }
                if (any_packet) {
                    const V3<F> p(LD(a.px), LD(a.py), LD(a.pz)), ng(LD(a.ngx), LD(a.ngy), LD(a.ngz));
                    const LightTableSample<F> ls = sample_light_table<F>(
                        ps.lights, lane::load_int_as<IntT<F>>(a.light), p, V2<F>{LD(a.u[1]), LD(a.u[2])}, LM(a.plight));
                    SM(a.nee_ok, LM(a.plight) && ls.valid);
                    SM(a.delta, LM(a.plight) && ls.delta);  // delta lights: no MIS
                    ST(a.lwx, ls.wi.x), ST(a.lwy, ls.wi.y), ST(a.lwz, ls.wi.z);
                    ST(a.lLr, ls.L.r), ST(a.lLg, ls.L.g), ST(a.lLb, ls.L.b);
                    ST(a.lpdf, LD(a.lsel) * ls.pdf);
                    const V3<F> o = offset_ray_origin<F>(p, V3<F>(LD(a.pex), LD(a.pey), LD(a.pez)), ng,
                                                         lane::select(ls.infinite, ls.wi, ls.p - p));
                    const V3<F> e = offset_ray_origin<F>(ls.p, ls.err, ls.n, o - ls.p);
                    const V3<F> d = lane::select(ls.infinite, ls.wi, e - o);
                    ST(a.sh[0], o.x), ST(a.sh[1], o.y), ST(a.sh[2], o.z), ST(a.sh[3], d.x), ST(a.sh[4], d.y), ST(a.sh[5], d.z);
                    ST(a.sh[6], lane::select(ls.infinite, F(kInfinity), F(1.f - 1e-4f)));
                }
            }

            // One lane at a time again: lights without a table, and the BSDF lanes.
            for (uint32_t m = lane_bits<F>(a.goes_on); m; m &= m - 1) {
                const int i = lowest_lane<F>(m);
                SurfaceInteraction& h = si[i];
                if (a.nee[i] && ps.emitters.empty() && !a.plight[i]) {
                    if (!full[i]) {  // what light sampling reads of the vertex
                        h.p = Vec3f(a.px[i], a.py[i], a.pz[i]);
                        h.p_error = Vec3f(a.pex[i], a.pey[i], a.pez[i]);
                        h.ng = Vec3f(a.ngx[i], a.ngy[i], a.ngz[i]);
                    }
                    LightLiSample ls;
                    const Vec2f u(a.u[1][i], a.u[2][i]);
                    a.nee_ok[i] = ps.lights.any ? path_services::sample_picked_light(ps, h, a.light[i], a.lsel[i], u, &ls,
                                                                                     &a.lpdf[i], &shadow[i])
                                                : path_services::sample_light(ps, h, a.u[0][i], u, &ls, &a.lpdf[i], &shadow[i]);
                    if (a.nee_ok[i]) {
                        a.lwx[i] = ls.wi.x, a.lwy[i] = ls.wi.y, a.lwz[i] = ls.wi.z;
                        a.lLr[i] = ls.L.r, a.lLg[i] = ls.L.g, a.lLb[i] = ls.L.b;
                        a.delta[i] = ls.delta;
                        const Ray& r = shadow[i];
                        a.sh[0][i] = r.o.x, a.sh[1][i] = r.o.y, a.sh[2][i] = r.o.z;
                        a.sh[3][i] = r.d.x, a.sh[4][i] = r.d.y, a.sh[5][i] = r.d.z, a.sh[6][i] = r.tmax;
                    }
                }
                if (a.fast[i]) continue;
                BxDFSample s;
                if (a.in_medium[i]) {  // the phase function in place of the BSDF
                    if (a.nee_ok[i]) {
                        const Spectrum f =
                            path_services::phase_eval(ps, medium[i], h.wo, Vec3f(a.lwx[i], a.lwy[i], a.lwz[i]), &a.gpdf[i]);
                        a.gfr[i] = f.r, a.gfg[i] = f.g, a.gfb[i] = f.b;
                    }
                    a.s_ok[i] = path_services::phase_sample(ps, medium[i], h.wo, Vec2f(a.u[4][i], a.u[5][i]), &s);
                    // Without NEE here, light found by this direction is not MIS-weighted: the
                    // vertex counts as a delta bounce for that.
                    if (!a.nee[i]) s.lobe |= BxDFFlags::Specular;
                } else if (a.at_exit[i]) {  // a BSSRDF's exit lobe
                    if (a.nee_ok[i]) {
                        const Spectrum f = path_services::subsurface_exit_eval(
                            ps, exit_ss[i], h, Vec3f(a.lwx[i], a.lwy[i], a.lwz[i]), &a.gpdf[i]);
                        a.gfr[i] = f.r, a.gfg[i] = f.g, a.gfb[i] = f.b;
                    }
                    a.s_ok[i] = path_services::subsurface_exit_sample(ps, exit_ss[i], h, Vec2f(a.u[4][i], a.u[5][i]), &s);
                    if (!a.nee[i]) s.lobe |= BxDFFlags::Specular;
                } else {
                    if (a.nee_ok[i]) {
                        const Spectrum f =
                            path_services::bsdf_eval(bsdf(i), h.wo, Vec3f(a.lwx[i], a.lwy[i], a.lwz[i]), &a.gpdf[i]);
                        a.gfr[i] = f.r, a.gfg[i] = f.g, a.gfb[i] = f.b;
                    }
                    a.s_ok[i] = path_services::bsdf_sample(bsdf(i), h.wo, a.u[3][i], Vec2f(a.u[4][i], a.u[5][i]), &s);
                    // Refracting into an object rendered by a diffusion BSSRDF: the path goes on
                    // from the exit point a probe finds (bssrdf/separable.h).
                    if (ps.subsurface && a.s_ok[i]) {
                        const int32_t ss = path_services::subsurface_entry(ps, h, s);
                        if (ss >= 0) {
                            exit_ss[i] = ss;
                            a.s_ok[i] = a.to_exit[i] = path_services::subsurface_probe(ps, ss, h, medium_rng[i], &s, &exit_si[i]);
                        }
                    }
                }
                if (a.s_ok[i]) {
                    a.swx[i] = s.wi.x, a.swy[i] = s.wi.y, a.swz[i] = s.wi.z;
                    a.swr[i] = s.weight.r, a.swg[i] = s.weight.g, a.swb[i] = s.weight.b;
                    a.spdf[i] = s.pdf;
                    a.seta[i] = s.eta;
                    a.slobe[i] = int32_t(s.lobe);
                }
            }

            // The packet pass over every lane.
            {
#if PELLUCID_DISPATCH_STATS
                const uint64_t pass_t0 = dispatch_clock();
#endif
                const M on = LM(active), is_hit = LM(hit);
                const RGB<F> beta0(LD(a.br), LD(a.bg), LD(a.bb));
                RGB<F> L(LD(a.Lr), LD(a.Lg), LD(a.Lb));
                // Emission found by the last bounce, MIS-weighted against light sampling.
                {
                    const RGB<F> Le(LD(a.Ler), LD(a.Leg), LD(a.Leb));
                    const F le_pdf = LD(a.le_pdf);
                    const F w = lane::select(le_pdf < F(0.f), F(1.f),
                                             bsdf_hit_weight<F>(ps.use_mis, ps.use_nee, LM(a.specular), LD(a.prev_pdf), le_pdf));
                    L += beta0 * Le * lane::select(on, w, F(0.f));
                }
                const M goes_on = LM(a.goes_on) && on && (is_hit || LM(a.in_medium));
                const M fast = LM(a.fast) && goes_on;
                const V3<F> p(LD(a.px), LD(a.py), LD(a.pz)), ng(LD(a.ngx), LD(a.ngy), LD(a.ngz));
                const V3<F> wo_w(LD(a.wox), LD(a.woy), LD(a.woz));
                const FrameT<F> frame(V3<F>(LD(a.sx), LD(a.sy), LD(a.sz)), V3<F>(LD(a.tx), LD(a.ty), LD(a.tz)),
                                      V3<F>(LD(a.nx), LD(a.ny), LD(a.nz)));
                // The packet forms present, each run once on all lanes; lanes of other kinds ignore
                // its results (masked calls, merged by select).
                const F kind = LD(a.kind);
                const M is_lambert = fast && kind == F(float(kPacketLambertian));
                const M is_dielectric = fast && kind == F(float(kPacketSmoothDielectric));
                const M is_mirror = fast && kind == F(float(kPacketSmoothConductor));
                const M is_rough = fast && kind == F(float(kPacketRoughConductor));
                const M is_beckmann = fast && kind == F(float(kPacketRoughConductorBeckmann));
                // (The mirror's parameters, read only where such lanes exist; the rough conductors
                // build theirs on their own lanes, rough_on and beckmann_on.)
                const SmoothConductorT<F> metal =
                    lane::any(is_mirror) ? SmoothConductorT<F>{RGB<F>(LD(a.q[0]), LD(a.q[1]), LD(a.q[2])),
                                                        RGB<F>(LD(a.q[3]), LD(a.q[4]), LD(a.q[5])),
                                                        RGB<F>(LD(a.q[6]), LD(a.q[7]), LD(a.q[8]))}
                                  : SmoothConductorT<F>{RGB<F>(F(0.f)), RGB<F>(F(0.f)), RGB<F>(F(0.f))};
                // The non-delta forms are built on the lanes of a FormLanes c (X_on(c), defined by
                // PELLUCID_FORM_ON; run_form below), each from the packet parameters of the lanes c
                // takes, read through c.in.
#define PELLUCID_FORM_ON(name, ...)                              \
    auto name = [&](const auto& c) {                             \
        using L = typename std::decay_t<decltype(c)>::L;         \
        auto q = [&](int k) { return L(c.in(LD(a.q[k]))); };     \
        return __VA_ARGS__;                                      \
    }
                PELLUCID_FORM_ON(lambert_on, LambertianT<L>{RGB<L>(q(0), q(1), q(2))});
                PELLUCID_FORM_ON(rough_on, rough_conductor_lanes<GGXT, L>(c.in(is_rough), q));
                PELLUCID_FORM_ON(beckmann_on, rough_conductor_lanes<BeckmannT, L>(c.in(is_beckmann), q));
                // The plastics (smooth, or rough over GGX or Beckmann; other lanes skip their lobes and tables).
                const M is_plastic = fast && kind == F(float(kPacketPlastic));
                PELLUCID_FORM_ON(plastic_on, plastic_lanes<L>(c.in(is_plastic), q, ps.coat_tables.data()));
                const M is_plastic_b = fast && kind == F(float(kPacketPlasticBeckmann));
                PELLUCID_FORM_ON(plastic_b_on, plastic_lanes<L, BeckmannT>(c.in(is_plastic_b), q, ps.coat_tables.data()));
                // The rough dielectrics (GGX or Beckmann), without multiple scattering.
                const M is_rdiel = fast && kind == F(float(kPacketRoughDielectric));
                const M is_rdiel_b = fast && kind == F(float(kPacketRoughDielectricBeckmann));
                const M is_any_rdiel = is_rdiel || is_rdiel_b;
                PELLUCID_FORM_ON(rdiel_on, rough_dielectric_lanes<GGXT, L>(c.in(is_any_rdiel), q));
                PELLUCID_FORM_ON(rdiel_b_on, rough_dielectric_lanes<BeckmannT, L>(c.in(is_any_rdiel), q));
                // Oren–Nayar (classic or EON) and the thin dielectric.
                const M is_on = fast && kind == F(float(kPacketOrenNayar));
                PELLUCID_FORM_ON(oren_on, oren_nayar_lanes<L>(c.in(is_on), q));
                const M is_thin = fast && kind == F(float(kPacketThinDielectric));
                // The opaque solid principled BSDFs.
                const M is_princ = fast && kind == F(float(kPacketPrincipled));
                PELLUCID_FORM_ON(princ_on, principled_lanes<L>(c.in(is_princ), q));
                // The Burley 2012 principled BRDFs.
                const M is_princ12 = fast && kind == F(float(kPacketPrincipled2012));
                PELLUCID_FORM_ON(princ12_on, principled2012_lanes<L>(c.in(is_princ12), q));
                // The thin-sheet principled BSDFs.
                const M is_pthin = fast && kind == F(float(kPacketPrincipledThin));
                PELLUCID_FORM_ON(pthin_on, principled_thin_lanes<L>(c.in(is_pthin), q));
                // The principled solids with a transmission lobe.
                const M is_psolid = fast && kind == F(float(kPacketPrincipledSolid));
                PELLUCID_FORM_ON(psolid_on, principled_solid_lanes<L>(c.in(is_psolid), q));
#undef PELLUCID_FORM_ON
                const BxDFContext ctx{TransportMode::Radiance, BxDFFlags::All};
                const V3<F> wo = frame.to_local(wo_w);
                // The non-delta packet forms, one line each: (PacketKind, its lanes, its form built on a
                // FormLanes c, how NEE and sampling call it: SPLIT eval and pdf, PAIR eval_pdf, both
                // without a mask; MASKED eval_pdf and sample on the lanes that take part).
#define PELLUCID_NON_DELTA_FORMS(X)                                      \
    X(kPacketLambertian, is_lambert, lambert_on, SPLIT)                  \
    X(kPacketOrenNayar, is_on, oren_on, SPLIT)                           \
    X(kPacketRoughConductor, is_rough, rough_on, PAIR)                   \
    X(kPacketRoughConductorBeckmann, is_beckmann, beckmann_on, PAIR)     \
    X(kPacketPlastic, is_plastic, plastic_on, PAIR)                      \
    X(kPacketPlasticBeckmann, is_plastic_b, plastic_b_on, PAIR)          \
    X(kPacketRoughDielectric, is_rdiel, rdiel_on, MASKED)                \
    X(kPacketRoughDielectricBeckmann, is_rdiel_b, rdiel_b_on, MASKED)    \
    X(kPacketPrincipled, is_princ, princ_on, MASKED)                     \
    X(kPacketPrincipled2012, is_princ12, princ12_on, MASKED)             \
    X(kPacketPrincipledThin, is_pthin, pthin_on, MASKED)                 \
    X(kPacketPrincipledSolid, is_psolid, psolid_on, MASKED)
                // A packet form's call on the lanes `where`: body(c) with c a FormLanes (run_on_lanes).
                auto run_form = [&](const M& where, const auto& body) { run_on_lanes<F>(where, body); };
                // Bump- and normal-mapped lanes whose terminator is softened (BSDF::soften_terminator).
                const M soft = LM(a.soft) && fast;
                const bool any_soft = lane::any(soft);
                auto soften = [&](const RGB<F>& f, const V3<F>& wi, const V3<F>& wi_w) {
                    if (!any_soft) return f;
                    const V3<F> n0(LD(a.n0x), LD(a.n0y), LD(a.n0z));
                    return f * lane::select(soft, terminator_factor<F>(LM(a.est), wo, wi, wi_w, n0, frame.n), F(1.f));
                };

                // Next-event estimation: the BSDF toward the sampled light point, the MIS weight, and
                // what the shadow ray carries if it is unoccluded.
                {
                    const M nee = LM(a.nee_ok) && goes_on;
                    const V3<F> wi_w(LD(a.lwx), LD(a.lwy), LD(a.lwz));
                    const V3<F> wi = frame.to_local(wi_w);
                    const M leak = wo.z == F(0.f) || shading_leaks<F>(ng, wo_w, wi_w, wo, wi);
                    // (Of the packet forms the Lambertian, Oren–Nayar, the rough conductors, the
                    // plastics, the rough dielectrics and the principled models have lobes NEE can reach.)
                    const M off = leak || !(is_lambert || is_on || is_rough || is_beckmann || is_plastic || is_plastic_b ||
                                            is_any_rdiel || is_princ || is_princ12 || is_pthin || is_psolid);
                    // Each packet form present evaluates on its own lanes (run_form), which keep the result.
                    RGB<F> f_fast(F(0.f));
                    F pdf_fast(0.f);
                    // The forms run by run_form: eval(c, on) evaluates on c's lanes, `on` those of
                    // `where` that take part. The microfacet conductors and the plastics evaluate f
                    // and pdf together (one half vector, D and Λ(wo) once: ReflectionPairT::
                    // torrance_sparrow_cos_pdf), as do the dielectrics and the principled BSDFs (one
                    // half vector, in double: bxdf/dielectric.h, principled_bsdf.h; on the lanes given).
                    auto nee_form = [&](int kind, const M& where, const auto& eval) {
                        const M on = where && nee;
                        if (!lane::any(on)) return;
                        (void)kind;
                        run_form(on, [&](const auto& c) {
                            PELLUCID_FORM_CALL(kind, on, const auto ep = eval(c, c.in(on)); c.put(f_fast, ep.f);
                                               c.put(pdf_fast, ep.pdf));
                        });
                    };
                    // How each form is called (PELLUCID_NON_DELTA_FORMS): SPLIT eval and pdf apart,
                    // PAIR eval_pdf, MASKED eval_pdf on the lanes that take part. (kind is read by the
                    // diagnostic build's PELLUCID_FORM_CALL only.)
#define PELLUCID_NEE_FORM_SPLIT(kind, where, form)                                                                      \
    nee_form(kind, where, [&](const auto& c, const auto&) {                                                       \
        const auto m = form(c);                                                                                   \
        return EvalPdfT<typename std::decay_t<decltype(c)>::L>{m.eval(ctx, c.in(wo), c.in(wi)), m.pdf(ctx, c.in(wo), c.in(wi))}; \
    })
#define PELLUCID_NEE_FORM_PAIR(kind, where, form) \
    nee_form(kind, where, [&](const auto& c, const auto&) { return form(c).eval_pdf(ctx, c.in(wo), c.in(wi)); })
#define PELLUCID_NEE_FORM_MASKED(kind, where, form) \
    nee_form(kind, where, [&](const auto& c, const auto& on) { return form(c).eval_pdf(ctx, c.in(wo), c.in(wi), on); })
#define PELLUCID_NEE_OF(kind, where, form, how) PELLUCID_NEE_FORM_##how(kind, where, form);
                    PELLUCID_NON_DELTA_FORMS(PELLUCID_NEE_OF)
#undef PELLUCID_NEE_OF
#undef PELLUCID_NEE_FORM_SPLIT
#undef PELLUCID_NEE_FORM_PAIR
#undef PELLUCID_NEE_FORM_MASKED
                    f_fast = lane::select(off, RGB<F>(F(0.f)), soften(f_fast, wi, wi_w));
                    pdf_fast = lane::select(off, F(0.f), pdf_fast);
                    const RGB<F> f = lane::select(fast, f_fast, RGB<F>(LD(a.gfr), LD(a.gfg), LD(a.gfb)));
                    const F bsdf_pdf = lane::select(fast, pdf_fast, LD(a.gpdf));
                    const F light_pdf = lane::select(nee, LD(a.lpdf), F(1.f));
                    const F w = lane::select(LM(a.delta) || M(!ps.use_mis), F(1.f), power_heuristic<F>(light_pdf, bsdf_pdf));
                    const RGB<F> Ld = beta0 * f * RGB<F>(LD(a.lLr), LD(a.lLg), LD(a.lLb)) * (w / light_pdf);
                    SM(a.has_shadow, nee && !is_black(f));
                    ST(a.Ldr, Ld.r), ST(a.Ldg, Ld.g), ST(a.Ldb, Ld.b);
                }

                // Continue the path by sampling the BSDF.
                M sampled;
                RGB<F> weight;
                F pdf, eta;
                M specular, transmission;
                {
                    const F u_lobe = LD(a.u[3]);
                    const V2<F> u2{LD(a.u[4]), LD(a.u[5])};
                    // Each packet form present samples its own lanes (run_form), which keep its result.
                    BxDFSampleT<F> s{M(false), V3<F>(F(0.f), F(0.f), F(1.f)), RGB<F>(F(0.f)), F(0.f), F(1.f), IntT<F>(0)};
#define PELLUCID_SAMPLE_FORM(kind, where, ...) \
    if (lane::any(where)) PELLUCID_FORM_CALL(kind, where, put_sample(FormLanesWhole<F>{where}, s, __VA_ARGS__))
                    PELLUCID_SAMPLE_FORM(kPacketSmoothConductor, is_mirror, metal.sample(ctx, wo, u_lobe, u2));
                    // The forms run by run_form: form(c) samples on c's lanes (with `on`, those of
                    // `where`, where its sample takes a mask).
                    auto sample_form = [&](int kind, const M& where, const auto& draw) {
                        if (!lane::any(where)) return;
                        (void)kind;
                        run_form(where, [&](const auto& c) { PELLUCID_FORM_CALL(kind, where, put_sample(c, s, draw(c, c.in(where)))); });
                    };
#define PELLUCID_SAMPLE_FORM_PAIR(kind, where, form) \
    sample_form(kind, where, [&](const auto& c, const auto&) { return form(c).sample(ctx, c.in(wo), c.in(u_lobe), c.in(u2)); })
#define PELLUCID_SAMPLE_FORM_MASKED(kind, where, form)                                                              \
    sample_form(kind, where,                                                                                        \
                [&](const auto& c, const auto& on) { return form(c).sample(ctx, c.in(wo), c.in(u_lobe), c.in(u2), on); })
#define PELLUCID_SAMPLE_FORM_SPLIT PELLUCID_SAMPLE_FORM_PAIR
#define PELLUCID_SAMPLE_OF(kind, where, form, how) PELLUCID_SAMPLE_FORM_##how(kind, where, form);
                    PELLUCID_NON_DELTA_FORMS(PELLUCID_SAMPLE_OF)
#undef PELLUCID_SAMPLE_OF
#undef PELLUCID_SAMPLE_FORM_SPLIT
#undef PELLUCID_SAMPLE_FORM_PAIR
#undef PELLUCID_SAMPLE_FORM_MASKED
#undef PELLUCID_NON_DELTA_FORMS
                    PELLUCID_SAMPLE_FORM(kPacketSmoothDielectric, is_dielectric,
                                         SmoothDielectricT<F>{LD(a.q[0]), RGB<F>(LD(a.q[1]), LD(a.q[2]), LD(a.q[3])),
                                                              RGB<F>(LD(a.q[4]), LD(a.q[5]), LD(a.q[6]))}
                                             .sample(ctx, wo, u_lobe, u2));
                    PELLUCID_SAMPLE_FORM(kPacketThinDielectric, is_thin,
                                         ThinDielectricT<F>{LD(a.q[0]), RGB<F>(LD(a.q[1]), LD(a.q[2]), LD(a.q[3])),
                                                            RGB<F>(LD(a.q[4]), LD(a.q[5]), LD(a.q[6]))}
                                             .sample(ctx, wo, u_lobe, u2));
#undef PELLUCID_SAMPLE_FORM
                    const V3<F> wi_w = frame.to_world(s.wi);
                    const M ok_fast = s.valid && s.pdf > F(0.f) && !is_black(s.weight) && s.wi.z != F(0.f) &&
                                      !shading_leaks<F>(ng, wo_w, wi_w, wo, s.wi) && wo.z != F(0.f);
                    s.weight = soften(s.weight, s.wi, wi_w);
                    const M ok_gen = LM(a.s_ok);
                    sampled = goes_on && lane::select(fast, ok_fast, ok_gen);
                    weight = lane::select(fast, s.weight, RGB<F>(LD(a.swr), LD(a.swg), LD(a.swb)));
                    pdf = lane::select(fast, s.pdf, LD(a.spdf));
                    eta = lane::select(fast, s.eta, LD(a.seta));
                    const IntT<F> lobe = lane::select(lane::int_mask(fast), s.lobe, lane::load_int_as<IntT<F>>(a.slobe));
                    specular = lane::float_mask((lobe & IntT<F>(int32_t(BxDFFlags::Specular))) != IntT<F>(0));
                    transmission = lane::float_mask((lobe & IntT<F>(int32_t(BxDFFlags::Transmission))) != IntT<F>(0));
                    const V3<F> nw = lane::select(fast, wi_w, V3<F>(LD(a.swx), LD(a.swy), LD(a.swz)));
                    ST(a.nwx, nw.x), ST(a.nwy, nw.y), ST(a.nwz, nw.z);
                }
                RGB<F> beta = lane::select(sampled, beta0 * weight, beta0);
                F eta_scale = lane::select(sampled && transmission, LD(a.eta_scale) * (eta * eta), LD(a.eta_scale));
                const F depth = LD(a.depth);
                // Russian roulette from rr_depth on: survive with q = min(max β·η², 1) (pbrt-v4,
                // §13.4.1), so the weight β·η² never exceeds 1. A cap below 1 (Mitsuba 3's 0.95)
                // multiplies the weight by albedo/cap at every vertex whose albedo exceeds the cap: in
                // a subsurface random walk (albedo 0.997, hundreds of collisions and internal
                // reflections) single samples reached 10⁴. Paths whose weight stays 1 end at
                // max_depth (kUnboundedDepth when unbounded).
                const M rr = sampled && depth >= F(float(ps.rr_depth));
                const F q = lane::min(max_component(beta) * eta_scale, F(1.f));
                const M survives = !rr || LD(a.u[6]) < q;
                beta = lane::select(rr && survives, beta / lane::select(rr, q, F(1.f)), beta);
                SM(a.alive, (sampled && survives && !is_black(beta)) || (LM(a.crossing) && on && !is_black(beta0)));
                SM(a.sampled, sampled);
                ST(a.Lr, L.r), ST(a.Lg, L.g), ST(a.Lb, L.b);
                ST(a.br, beta.r), ST(a.bg, beta.g), ST(a.bb, beta.b);
                ST(a.eta_scale, eta_scale);
                ST(a.prev_pdf, lane::select(sampled, pdf, LD(a.prev_pdf)));
                SM(a.specular, lane::select(sampled, specular, LM(a.specular)));
                ST(a.ppx, lane::select(sampled, p.x, LD(a.ppx))), ST(a.ppy, lane::select(sampled, p.y, LD(a.ppy)));
                ST(a.ppz, lane::select(sampled, p.z, LD(a.ppz)));
                ST(a.pnx, lane::select(sampled, ng.x, LD(a.pnx))), ST(a.pny, lane::select(sampled, ng.y, LD(a.pny)));
                ST(a.pnz, lane::select(sampled, ng.z, LD(a.pnz)));
                ST(a.depth, lane::select(sampled, depth + F(1.f), depth));
                // The next rays leave from the hit, offset off its surface (SurfaceInteraction::
                // spawn_ray); a delta bounce that carries ray differentials for textures goes through
                // the scene one lane at a time.
                const V3<F> nw(LD(a.nwx), LD(a.nwy), LD(a.nwz));
                const V3<F> o = offset_ray_origin<F>(p, V3<F>(LD(a.pex), LD(a.pey), LD(a.pez)), ng, nw);
                alignas(64) bool spec_b[W], trans_b[W];
                alignas(64) float eta_b[W], ob[3][W];
                SM(spec_b, specular), SM(trans_b, transmission), ST(eta_b, eta);
                ST(ob[0], o.x), ST(ob[1], o.y), ST(ob[2], o.z);
                {  // the arrays the trace reads, for the lanes whose next ray is (o, nw) (the loop
                   // below updates those whose next ray differs)
                    const M next = LM(a.alive) && !LM(a.crossing) && !LM(a.to_exit);
                    ST(a.ray_soa[0], lane::select(next, o.x, LD(a.ray_soa[0])));
                    ST(a.ray_soa[1], lane::select(next, o.y, LD(a.ray_soa[1])));
                    ST(a.ray_soa[2], lane::select(next, o.z, LD(a.ray_soa[2])));
                    ST(a.ray_soa[3], lane::select(next, nw.x, LD(a.ray_soa[3])));
                    ST(a.ray_soa[4], lane::select(next, nw.y, LD(a.ray_soa[4])));
                    ST(a.ray_soa[5], lane::select(next, nw.z, LD(a.ray_soa[5])));
                    ST(a.ray_soa[6], lane::select(next, F(kInfinity), LD(a.ray_soa[6])));
                }
                const uint32_t goes = (ps.media || ps.subsurface || scene.needs_footprints)
                                          ? lane_bits<F>(a.alive) & ~lane_bits<F>(a.crossing)
                                          : 0u;
                for (uint32_t m = goes; m; m &= m - 1) {
                    const int i = lowest_lane<F>(m);
                    if (a.to_exit[i]) {  // no ray: the next vertex is the exit point
                        pending_exit[i] = true;
                        continue;
                    }
                    const Vec3f wi(a.nwx[i], a.nwy[i], a.nwz[i]);
                    if (ps.media && !a.in_medium[i]) medium[i] = path_services::medium_after(ps, si[i], wi, medium[i]);
                    if (scene.needs_footprints && spec_b[i] && !a.in_medium[i] && ray[i].has_differentials) {
                        // (ray[i] is this vertex's incoming ray: loop 1 copied it, as these lanes
                        // are not table lanes.)
                        ray[i] = path_services::next_ray(ps, si[i], ray[i], wi, true, trans_b[i], eta_b[i]);
                        set_ray_soa(i);
                    } else {
                        ray[i].has_differentials = false;  // (the arrays hold the ray: (o, wi) above)
                    }
                }
#if PELLUCID_DISPATCH_STATS
                dispatch_record(-2, dispatch_lane_count(goes_on, W), W, dispatch_clock() - pass_t0);
#endif
            }

            // The shadow rays NEE left, as one packet.
            bool any_shadow = false;
            for (int i = 0; i < W; ++i) any_shadow |= a.has_shadow[i];
            if (any_shadow && ps.media) {
                // Through media and null boundaries: each shadow ray carries a transmittance. Their
                // first segments are traced as one packet. A lane whose ray reaches its end in one
                // homogeneous medium, or in none, takes its Beer–Lambert transmittance in the packet
                // below (transmittance(HomogeneousMedium) as packets: detail::beer_channel); a lane
                // goes on alone only past a null boundary or in a grid (shadow_transmittance).
                const float* const soa[7] = {a.sh[0], a.sh[1], a.sh[2], a.sh[3], a.sh[4], a.sh[5], a.sh[6]};
                alignas(64) bool sh_hit[W], sh_hm[W]{};
                alignas(64) int32_t sh_row[W]{};
                path_services::trace_lanes(scene, W, soa, a.has_shadow, sh_hl, sh_hit);
                for (uint32_t sb = lane_bits<F>(a.has_shadow); sb; sb &= sb - 1) {
                    const int i = lowest_lane<F>(sb);
                    if (sh_hit[i] && !scene.shapes[sh_hl.geom_id[i]].null_surface) continue;  // blocked
                    const Ray sray{Vec3f(a.sh[0][i], a.sh[1][i], a.sh[2][i]), Vec3f(a.sh[3][i], a.sh[4][i], a.sh[5][i]),
                                   a.sh[6][i]};
                    const int32_t m = a.in_medium[i] ? medium[i] : path_services::medium_after(ps, si[i], sray.d, medium[i]);
                    if (!sh_hit[i] && (m < 0 || ps.homogeneous_media[size_t(m)])) {
                        sh_hm[i] = true;
                        sh_row[i] = m < 0 ? -1 : m * PathSetup::kMediumStride;
                        continue;
                    }
                    const RayHit first = sh_hl.lane(i);
                    const Spectrum tr = path_services::shadow_transmittance(ps, m, sray, Spectrum(a.br[i], a.bg[i], a.bb[i]),
                                                                            medium_rng[i], &first);
                    a.Lr[i] += a.Ldr[i] * tr.r;
                    a.Lg[i] += a.Ldg[i] * tr.g;
                    a.Lb[i] += a.Ldb[i] * tr.b;
                }
                const M hm = LM(sh_hm);
                if (lane::any(hm)) {
                    // exp(−σt·|d|·tmax) per channel, σt = 0 outside media (the medium's row, as
                    // transmittance(HomogeneousMedium) multiplies it out).
                    using I = IntT<F>;
                    const I row_i = lane::load_int_as<I>(sh_row);
                    const auto in_m = lane::int_mask(hm) && row_i >= I(0);
                    F row[PathSetup::kMediumStride];
                    std::fill(row, row + PathSetup::kMediumStride, F(0.f));
                    if (!ps.medium_rows.empty())  // (none in a scene of null boundaries only)
                        lane::gather_rows<PathSetup::kMediumStride>(ps.medium_rows.data(), lane::select(in_m, row_i, I(0)), row);
                    const F len = length(V3<F>(LD(a.sh[3]), LD(a.sh[4]), LD(a.sh[5])));
                    const F t = LD(a.sh[6]);
                    const M in_mf = lane::float_mask(in_m);
                    float* const Ls[3] = {a.Lr, a.Lg, a.Lb};
                    const float* const Lds[3] = {a.Ldr, a.Ldg, a.Ldb};
                    for (int c = 0; c < 3; ++c) {
                        const F tr = detail::beer_channel<F>(lane::select(in_mf, row[c], F(0.f)) * len, t);
                        ST(Ls[c], lane::select(hm, LD(Ls[c]) + LD(Lds[c]) * tr, LD(Ls[c])));
                    }
                }
            } else if (any_shadow) {
                const float* const soa[7] = {a.sh[0], a.sh[1], a.sh[2], a.sh[3], a.sh[4], a.sh[5], a.sh[6]};
                path_services::occluded_lanes(scene, W, soa, a.has_shadow, blocked);
                // Unblocked lanes add what their shadow rays carry (the others add +0, which leaves
                // L as it is: L starts at +0 and never becomes −0).
                const M lit = LM(a.has_shadow) && !LM(blocked);
                ST(a.Lr, LD(a.Lr) + lane::select(lit, LD(a.Ldr), F(0.f)));
                ST(a.Lg, LD(a.Lg) + lane::select(lit, LD(a.Ldg), F(0.f)));
                ST(a.Lb, LD(a.Lb) + lane::select(lit, LD(a.Ldb), F(0.f)));
            }
            // Finished paths hand their estimate over; their lanes start the next ones.
            {
                alignas(64) bool ended[W];
                for (int i = 0; i < W; ++i) ended[i] = active[i] & !a.alive[i];
                for (uint32_t m = lane_bits<F>(ended); m; m &= m - 1) {
                    const int i = lowest_lane<F>(m);
                    done[size_t(path_of[i])].L = Spectrum(a.Lr[i], a.Lg[i], a.Lb[i]);
                }
                start_lanes(ended);
            }
            camera_rays();
        }
        for (int64_t k = 0; k < n_paths; k += n_samples) {
            int x, y;
            pixel_xy(k, &x, &y);
            bad += path_services::film_add_pixel(film, x, y, &done[size_t(k)], n_samples);
        }
    }
    return bad;
}
}  // namespace pellucid
