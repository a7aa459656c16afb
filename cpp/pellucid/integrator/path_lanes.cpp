// The lane kernel (path_lanes.h): path tracing with NEE and MIS (Veach 1997, ch. 9; power heuristic,
// eq. 9.13) on 64 paths at a time, in structure-of-arrays form.
// SPDX-License-Identifier: Apache-2.0
//
// A round of the kernel: trace the 64 rays (4 Embree packets), draw the random numbers of every
// path that hit something (a scalar loop: each path keeps its own Sampler, with path.cpp's sample
// dimensions), shade all 64 vertices in one branch-free loop that the compiler vectorises
// (shade_lanes), trace the shadow rays NEE left, then hand finished paths to the film and start new
// ones in their lanes. Nothing is allocated per round, and nothing is dispatched per hit: the
// per-triangle table holds each hit's corners, normal, albedo and emission.
#include "pellucid/integrator/path_lanes.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>
#ifdef __AVX512F__
#include <immintrin.h>
#endif

#include "pellucid/light/area.h"
#include "pellucid/math/constants.h"
#include "pellucid/sampling/warp.h"

namespace pellucid {
namespace {
constexpr int kLanes = 64, kGroup = EmbreeScene::kPacketSize, kGroups = kLanes / kGroup;
static_assert(kLanes % kGroup == 0, "whole packets of lanes");

/// A triangle as a hit needs it (96 bytes): corners, unit normal (the shading normal too), the
/// material's reflectance, and its emission (zero unless it belongs to an area light).
struct alignas(32) LaneTriangle {
    float p[9];      ///< corners 0, 1, 2 (x, y, z each)
    float n[3];      ///< unit geometric normal, on the side the hit record's ng takes
    float albedo[3];
    float Le[3];     ///< radiance of its light, 0 if it emits nothing
    float two_sided; ///< 1 if its light emits on both sides
    float le_pdf;    ///< pmf(its light) / area(its light): NEE's density per unit area of the light
    float pad[2];
};
static_assert(sizeof(LaneTriangle) == 96, "three 32-byte lines");

/// An emitting triangle as next-event estimation samples it.
struct alignas(32) LaneEmitter {
    float v[9];       ///< corners
    float n[3];       ///< emitting side (AreaLight::triangle_normals)
    float err[3];     ///< error bound of a sampled point (AreaLight::triangle_errors)
    float Le[3];
    float two_sided;
    float pdf_area;   ///< pmf(its light) / area(its light)
    float pad[2];
};
static_assert(sizeof(LaneEmitter) == 96, "three 32-byte lines");
}  // namespace

struct LaneScene {
    std::vector<int32_t> tri_base;  ///< per Embree geometry id: its first triangle in `tris`
    std::vector<LaneTriangle> tris;
    std::vector<LaneEmitter> emitters;
    /// Emitter selection: cdf[j] = Σ_{i<j} pmf(light of i)·area(i)/area(light of i); cdf[m] = 1.
    std::vector<float> cdf;
    int search_top = 0;  ///< largest power of two < emitters.size() (0 for one emitter)
};

std::shared_ptr<const LaneScene> make_lane_scene(const Scene& scene, const IntegratorSettings& settings,
                                                 std::string* why) {
    auto no = [&](const std::string& reason) {
        if (why) *why = reason;
        return std::shared_ptr<const LaneScene>();
    };
    if (settings.type != "path") return no("integrator type " + settings.type);
    if (scene.has_textures) return no("textures");
    if (scene.has_one_sided) return no("a one-sided material");
    for (size_t m = 0; m < scene.material_bxdfs.size(); ++m)
        if (!std::holds_alternative<Lambertian>(scene.material_bxdfs[m]))
            return no("material '" + scene.material_names[m] + "' is not lambertian");
    if (scene.lights.empty()) return no("no lights");
    if (!scene.infinite_lights.empty()) return no("an infinite light");
    for (const Light& l : scene.lights) {
        const AreaLight* al = std::get_if<AreaLight>(&l);
        if (!al) return no("a light other than an area light");
        if (al->is_sphere()) return no("a spherical area light");
    }

    auto out = std::make_shared<LaneScene>();
    out->tri_base.resize(scene.shapes.size(), 0);
    size_t total = 0;
    for (size_t g = 0; g < scene.shapes.size(); ++g) {
        const ShapeRecord& s = scene.shapes[g];
        if (s.kind != ShapeRecord::Kind::Mesh) return no("shape '" + s.name + "' is a sphere");
        const TriangleMesh& mesh = scene.meshes[s.mesh_index];
        if (mesh.triangle_count() > 0 && mesh.flat.empty()) return no("shape '" + s.name + "' has smooth normals");
        out->tri_base[g] = int32_t(total);
        total += mesh.triangle_count();
    }
    if (total >= (1ull << 31) || scene.shapes.size() >= (1ull << 31)) return no("more than 2^31 triangles");
    out->tris.resize(total);
    for (size_t g = 0; g < scene.shapes.size(); ++g) {
        const ShapeRecord& s = scene.shapes[g];
        const TriangleMesh& mesh = scene.meshes[s.mesh_index];
        const AreaLight* light = s.light >= 0 ? &std::get<AreaLight>(scene.lights[size_t(s.light)]) : nullptr;
        for (size_t t = 0; t < mesh.triangle_count(); ++t) {
            const FlatTriangle& f = mesh.flat[t];
            // Vertex normals equal per face (precompute_flat) may still differ from the geometric
            // normal in their last bits; beyond that, the triangle needs a shading frame.
            if (length(f.shading.n - f.ng) > 1e-5f) return no("shape '" + s.name + "' has tilted shading normals");
            LaneTriangle& r = out->tris[out->tri_base[g] + t];
            for (int k = 0; k < 3; ++k) {
                const Point3f& p = mesh.positions[mesh.indices[3 * t + size_t(k)]];
                for (int c = 0; c < 3; ++c) r.p[3 * k + c] = p[c];
                r.n[k] = f.ng[k];
            }
            const uint32_t mat = s.face_materials.empty() ? s.material : s.face_materials[t];
            const Spectrum a = std::get<Lambertian>(scene.material_bxdfs[mat]).albedo();
            for (int c = 0; c < 3; ++c) {
                r.albedo[c] = a[c];
                r.Le[c] = light ? light->radiance()[c] : 0.f;
            }
            r.two_sided = light && light->two_sided() ? 1.f : 0.f;
            r.le_pdf = light && light->area() > 0.f ? scene.light_pmf(size_t(s.light)) / light->area() : 0.f;
            r.pad[0] = r.pad[1] = 0.f;
        }
    }

    std::vector<double> weights;
    for (size_t li = 0; li < scene.lights.size(); ++li) {
        const AreaLight& al = std::get<AreaLight>(scene.lights[li]);
        const float pmf = scene.light_pmf(li);
        if (!(pmf > 0.f) || !(al.area() > 0.f)) continue;
        const std::vector<Point3f>& v = al.triangles();
        for (size_t t = 0; 3 * t + 2 < v.size(); ++t) {
            const double area = 0.5 * double(length(cross(v[3 * t + 1] - v[3 * t], v[3 * t + 2] - v[3 * t])));
            if (!(area > 0.0)) continue;
            LaneEmitter e{};
            for (int k = 0; k < 3; ++k)
                for (int c = 0; c < 3; ++c) e.v[3 * k + c] = v[3 * t + size_t(k)][c];
            for (int c = 0; c < 3; ++c) {
                e.n[c] = al.triangle_normals()[t][c];
                e.err[c] = al.triangle_errors()[t][c];
                e.Le[c] = al.radiance()[c];
            }
            e.two_sided = al.two_sided() ? 1.f : 0.f;
            e.pdf_area = pmf / al.area();
            out->emitters.push_back(e);
            weights.push_back(double(pmf) * area / double(al.area()));
        }
    }
    if (out->emitters.empty()) return no("no emitting triangle");
    double sum = 0.0;
    for (double w : weights) sum += w;
    out->cdf.resize(weights.size() + 1);
    double acc = 0.0;
    out->cdf[0] = 0.f;
    for (size_t j = 0; j < weights.size(); ++j) {
        acc += weights[j];
        out->cdf[j + 1] = float(acc / sum);
    }
    out->cdf.back() = 1.f;
    while (size_t(out->search_top ? 2 * out->search_top : 1) < out->emitters.size())
        out->search_top = out->search_top ? 2 * out->search_top : 1;
    return out;
}

namespace {
/// The state of 64 paths, one array per quantity (lane i of each is path i). ~14 KB: L1-resident.
struct alignas(64) Lanes {
    // The next ray (origin, direction, tmax).
    alignas(64) float ox[kLanes], oy[kLanes], oz[kLanes], dx[kLanes], dy[kLanes], dz[kLanes], tmax[kLanes];
    // What it hit (geom < 0: nothing, or an idle lane).
    alignas(64) float t[kLanes], bu[kLanes], bv[kLanes];
    alignas(64) int32_t geom[kLanes], prim[kLanes];  ///< geom < 0: no hit
    // Path state.
    alignas(64) float br[kLanes], bg[kLanes], bb[kLanes];  ///< throughput β
    alignas(64) float Lr[kLanes], Lg[kLanes], Lb[kLanes];  ///< radiance so far
    alignas(64) float prev_pdf[kLanes];                    ///< solid-angle pdf of the last bounce
    alignas(64) float px[kLanes], py[kLanes], pz[kLanes];  ///< the last vertex (MIS of emitter hits)
    alignas(64) int32_t depth[kLanes];  ///< segments so far, including the next ray (1: camera ray)
    alignas(64) int32_t active[kLanes]; ///< -1: the lane holds a path
    alignas(64) int32_t alive[kLanes];  ///< -1: the path goes on after this round
    // Random numbers of this round's vertex.
    alignas(64) float u_sel[kLanes], u_l0[kLanes], u_l1[kLanes], u_b0[kLanes], u_b1[kLanes], u_rr[kLanes];
    // The shadow ray NEE left, and what it carries if unoccluded.
    alignas(64) float sox[kLanes], soy[kLanes], soz[kLanes], sdx[kLanes], sdy[kLanes], sdz[kLanes], stmax[kLanes];
    alignas(64) int32_t shadow[kLanes], occluded[kLanes];
    alignas(64) float Ldr[kLanes], Ldg[kLanes], Ldb[kLanes];
};

// 16 lanes in one value: GCC vector extensions, which compile to single AVX-512 instructions
// (or pairs of AVX2 ones, and so on, with narrower registers). Comparisons give masks of -1/0 and
// `mask ? a : b` selects per lane.
// Without AVX-512 GCC notes that 64-byte vectors are passed differently from AVX-512 code; these
// helpers are internal to this file, so no ABI is crossed.
#pragma GCC diagnostic ignored "-Wpsabi"
typedef float vf __attribute__((vector_size(64)));
typedef int32_t vi __attribute__((vector_size(64)));
static_assert(sizeof(vf) == kGroup * sizeof(float), "a vector holds one packet of lanes");

inline vf load(const float* p) {
    vf v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
inline vi load(const int32_t* p) {
    vi v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
inline void store(float* p, vf v) { std::memcpy(p, &v, sizeof v); }
inline void store(int32_t* p, vi v) { std::memcpy(p, &v, sizeof v); }
inline vf splat(float x) { return vf{} + x; }
inline vi splat(int32_t x) { return vi{} + x; }
inline vf vabs(vf x) { return (vf)((vi)x & 0x7fffffff); }
inline vf vmin(vf a, vf b) { return a < b ? a : b; }
inline vf vmax(vf a, vf b) { return a > b ? a : b; }
inline vi vmin(vi a, vi b) { return a < b ? a : b; }
inline vf vsqrt(vf x) {
#ifdef __AVX512F__
    return (vf)_mm512_mask_sqrt_ps((__m512)x, __mmask16(0xFFFF), (__m512)x);
#else
    vf r;
    for (int k = 0; k < kGroup; ++k) r[k] = std::sqrt(x[k]);
    return r;
#endif
}
/// base[idx[k]] for every lane, of 32-bit floats (V = vf) or integers (V = vi); AVX-512: one
/// gather instruction, which moves the bits whatever they mean.
template <class V, class T>
inline V gather(const T* base, vi idx) {
    static_assert(sizeof(T) == 4, "32-bit elements");
#ifdef __AVX512F__
    return (V)_mm512_mask_i32gather_ps(_mm512_setzero_ps(), __mmask16(0xFFFF), (__m512i)idx, base, 4);
#else
    V r;
    for (int k = 0; k < kGroup; ++k) r[k] = base[idx[k]];
    return r;
#endif
}

/// One coordinate of offset_ray_origin (math/ray.h, pbrt-v4 §6.8.6): p + offset, then one ulp
/// further in the offset's direction (next_float_up / next_float_down of math/constants.h, for
/// finite values).
inline vf offset_coord(vf p, vf off) {
    const vf po = p + off;
    const vi b = (vi)po;
    const vi zero = po == 0.f;
    // Up: ±0 goes to the smallest positive number; positives gain an ulp, negatives lose one.
    const vi up = (zero ? splat(0) : b) + ((po >= 0.f) ? splat(1) : splat(-1));
    const vi down = (zero ? splat(int32_t(0x80000000u)) : b) + ((po > 0.f) ? splat(-1) : splat(1));
    return (vf)(off > 0.f ? up : (off < 0.f ? down : b));
}

/// Power heuristic (β = 2) of two finite pdfs.
inline vf power_heuristic(vf a, vf b) {
    const vf a2 = a * a, sum = a2 + b * b;
    return sum > 0.f ? a2 / sum : splat(0.f);
}

/// One vertex of the paths in lanes [o, o + 16) (path.cpp's PathIntegrator::vertex on a Lambertian
/// surface), without a branch on the lanes' data: every quantity is computed in every lane and
/// the results selected by masks.
inline void shade_group(Lanes& s, int o, const LaneScene& ls, const LaneSettings& st) {
    const int max_depth = st.max_depth, rr_depth = st.rr_depth;
    constexpr int kTri = int(sizeof(LaneTriangle) / sizeof(float));
    constexpr int kEm = int(sizeof(LaneEmitter) / sizeof(float));
    const float* tf = reinterpret_cast<const float*>(ls.tris.data());
    const float* ef = reinterpret_cast<const float*>(ls.emitters.data());
    const vi geom = load(s.geom + o);
    const vi hit = (load(s.active + o) != 0) & (geom >= 0);
    const vi ti = (gather<vi>(ls.tri_base.data(), hit ? geom : splat(0)) + (hit ? load(s.prim + o) : splat(0))) * kTri;
    auto T = [&](int field) { return gather<vf>(tf + field, ti); };
    // The hit: barycentric position and its error bound (pbrt-v4 §6.8.5, eq. 6.31), as
    // Scene::fill_hit computes them.
    const vf b1 = load(s.bu + o), b2 = load(s.bv + o), b0 = 1.f - b1 - b2;
    const vf p0x = b0 * T(0), p0y = b0 * T(1), p0z = b0 * T(2);
    const vf p1x = b1 * T(3), p1y = b1 * T(4), p1z = b1 * T(5);
    const vf p2x = b2 * T(6), p2y = b2 * T(7), p2z = b2 * T(8);
    const vf px = p0x + p1x + p2x, py = p0y + p1y + p2y, pz = p0z + p1z + p2z;
    const float g7 = gamma(7);
    const vf ex = g7 * (vabs(p0x) + vabs(p1x) + vabs(p2x));
    const vf ey = g7 * (vabs(p0y) + vabs(p1y) + vabs(p2y));
    const vf ez = g7 * (vabs(p0z) + vabs(p1z) + vabs(p2z));
    const vf nx = T(9), ny = T(10), nz = T(11);
    const vf dx = load(s.dx + o), dy = load(s.dy + o), dz = load(s.dz + o);
    const vf cos_o = -(nx * dx + ny * dy + nz * dz);  // n · wo, wo = -d
    const vi depth = load(s.depth + o);
    vf br = load(s.br + o), bg = load(s.bg + o), bb = load(s.bb + o);
    const vf ar = T(12), ag = T(13), ab = T(14);

    // Emission found by the last bounce, MIS-weighted against light sampling (path.cpp's
    // bsdf_hit_weight: 1 for the camera ray, which nothing else could have found, and without NEE;
    // 0 under "nee", where light sampling alone accounts for it).
    {
        const vf Ler = T(15), Leg = T(16), Leb = T(17);
        const vi emits = hit & ((Ler > 0.f) | (Leg > 0.f) | (Leb > 0.f)) & ((T(18) > 0.f) | (cos_o > 0.f));
        const vf qx = px - load(s.px + o), qy = py - load(s.py + o), qz = pz - load(s.pz + o);
        const vf dist2 = qx * qx + qy * qy + qz * qz;
        const vf lpdf = cos_o != 0.f ? T(19) * dist2 / vabs(cos_o) : splat(0.f);
        const vf w_bsdf = !st.use_nee ? splat(1.f) : (!st.use_mis ? splat(0.f) : power_heuristic(load(s.prev_pdf + o), lpdf));
        const vf w = emits ? (depth == 1 ? splat(1.f) : w_bsdf) : splat(0.f);
        store(s.Lr + o, load(s.Lr + o) + br * Ler * w);
        store(s.Lg + o, load(s.Lg + o) + bg * Leg * w);
        store(s.Lb + o, load(s.Lb + o) + bb * Leb * w);
    }
    const vi goes_on = hit & (max_depth < 0 ? splat(-1) : (depth < max_depth)) &
                       ((ar != 0.f) | (ag != 0.f) | (ab != 0.f));

    // Next-event estimation: an emitting triangle by binary search of the cdf (a fixed number of
    // steps, the same in every lane), then a uniform point on it (Heitz 2019's warp, as
    // square_to_uniform_triangle), and its shadow ray.
    {
        const vf us = load(s.u_sel + o);
        vi j = splat(0);
        const vi last = splat(int32_t(ls.emitters.size()) - 1);
        for (int step = ls.search_top; step > 0; step >>= 1) {
            const vi c = vmin(j + step, last);
            j = gather<vf>(ls.cdf.data(), c) <= us ? c : j;
        }
        const vi ei = j * kEm;
        auto E = [&](int field) { return gather<vf>(ef + field, ei); };
        const vf ua = load(s.u_l0 + o), ub = load(s.u_l1 + o);
        const vi lower = ua < ub;
        const vf h = (lower ? ua : ub) * 0.5f;
        const vf c1 = lower ? h : ua - h, c2 = lower ? ub - h : h, c0 = 1.f - c1 - c2;
        const vf lx = E(0) * c0 + E(3) * c1 + E(6) * c2;
        const vf ly = E(1) * c0 + E(4) * c1 + E(7) * c2;
        const vf lz = E(2) * c0 + E(5) * c1 + E(8) * c2;
        const vf lnx = E(9), lny = E(10), lnz = E(11);
        const vf wx = lx - px, wy = ly - py, wz = lz - pz;
        const vf d2 = wx * wx + wy * wy + wz * wz;
        const vf inv_d = 1.f / vsqrt(d2);
        const vf wix = wx * inv_d, wiy = wy * inv_d, wiz = wz * inv_d;
        const vf cos_lw = lnx * wix + lny * wiy + lnz * wiz;  // n_light · wi
        const vf cos_l = vabs(cos_lw);
        const vf pdf_l = E(19) * d2 / cos_l;
        const vi light_faces = (E(18) > 0.f) | (cos_lw < 0.f);  // emits toward -wi
        const vf cos_i = nx * wix + ny * wiy + nz * wiz;
        const vf abs_cos_i = vabs(cos_i);
        const vf w_l = st.use_mis ? power_heuristic(pdf_l, abs_cos_i * kInvPi) : splat(1.f);
        const vf k = kInvPi * abs_cos_i * w_l / pdf_l;  // f/ρ · w / pdf
        const vi nee = (st.use_nee ? goes_on : splat(0)) & (d2 > 0.f) & (cos_l > 0.f) & light_faces & (cos_i * cos_o > 0.f) & (pdf_l < kInfinity);
        store(s.shadow + o, nee);
        store(s.Ldr + o, br * ar * E(15) * k);
        store(s.Ldg + o, bg * ag * E(16) * k);
        store(s.Ldb + o, bb * ab * E(17) * k);
        // spawn_ray_to (interaction.h): both ends offset off their surfaces.
        const vf od = (vabs(nx) * ex + vabs(ny) * ey + vabs(nz) * ez) *
                      ((wx * nx + wy * ny + wz * nz) < 0.f ? splat(-1.f) : splat(1.f));
        const vf sox = offset_coord(px, od * nx), soy = offset_coord(py, od * ny), soz = offset_coord(pz, od * nz);
        const vf ld = (vabs(lnx) * E(12) + vabs(lny) * E(13) + vabs(lnz) * E(14)) *
                      ((lnx * (sox - lx) + lny * (soy - ly) + lnz * (soz - lz)) < 0.f ? splat(-1.f) : splat(1.f));
        store(s.sox + o, sox);
        store(s.soy + o, soy);
        store(s.soz + o, soz);
        store(s.sdx + o, offset_coord(lx, ld * lnx) - sox);
        store(s.sdy + o, offset_coord(ly, ld * lny) - soy);
        store(s.sdz + o, offset_coord(lz, ld * lnz) - soz);
        store(s.stmax + o, splat(1.f - 1e-4f));
    }

    // The bounce: cosine-weighted about n on wo's side (Malley's method on the concentric disk,
    // square_to_cosine_hemisphere), in Duff et al. 2017's branch-free basis (frame.h).
    const vf a = 2.f * load(s.u_b0 + o) - 1.f, b = 2.f * load(s.u_b1 + o) - 1.f;
    const vi wide = vabs(a) > vabs(b);
    const vf major = wide ? a : b, minor = wide ? b : a;
    const vf ang = major != 0.f ? kPiOver4 * (minor / major) : splat(0.f);
    // sin and cos on [-π/4, π/4] (detail::sincos_quarter_pi's series).
    const vf x2 = ang * ang;
    const vf sn = ang * (1.f + x2 * (-1.f / 6.f + x2 * (1.f / 120.f + x2 * (-1.f / 5040.f + x2 * (1.f / 362880.f)))));
    const vf cs = 1.f + x2 * (-0.5f + x2 * (1.f / 24.f + x2 * (-1.f / 720.f + x2 * (1.f / 40320.f - x2 * (1.f / 3628800.f)))));
    const vf disk_x = major * (wide ? cs : sn), disk_y = major * (wide ? sn : cs);
    const vf z = vsqrt(vmax(splat(0.f), 1.f - disk_x * disk_x - disk_y * disk_y));
    const vf zs = cos_o < 0.f ? -z : z;
    const vf sign = nz >= 0.f ? splat(1.f) : splat(-1.f);
    const vf fa = -1.f / (sign + nz);
    const vf fb = nx * ny * fa;
    const vf sx = 1.f + sign * nx * nx * fa, sy = sign * fb, sz = -sign * nx;
    const vf tx = fb, ty = sign + ny * ny * fa, tz = -ny;
    const vf wbx = sx * disk_x + tx * disk_y + nx * zs;
    const vf wby = sy * disk_x + ty * disk_y + ny * zs;
    const vf wbz = sz * disk_x + tz * disk_y + nz * zs;
    const vf pdf_b = z * kInvPi;
    br *= ar;
    bg *= ag;
    bb *= ab;
    const vf od = (vabs(nx) * ex + vabs(ny) * ey + vabs(nz) * ez) *
                  ((wbx * nx + wby * ny + wbz * nz) < 0.f ? splat(-1.f) : splat(1.f));
    store(s.ox + o, offset_coord(px, od * nx));
    store(s.oy + o, offset_coord(py, od * ny));
    store(s.oz + o, offset_coord(pz, od * nz));
    store(s.dx + o, wbx);
    store(s.dy + o, wby);
    store(s.dz + o, wbz);
    store(s.tmax + o, splat(kInfinity));
    store(s.prev_pdf + o, pdf_b);
    store(s.px + o, px);
    store(s.py + o, py);
    store(s.pz + o, pz);
    store(s.depth + o, depth + 1);

    // Russian roulette (path.cpp): survive with q = min(max β, 0.95) from rr_depth on.
    const vi rr = depth >= rr_depth;
    const vf q = vmin(vmax(br, vmax(bg, bb)), splat(0.95f));
    const vi survives = ~rr | (load(s.u_rr + o) < q);
    const vf inv_q = rr ? 1.f / q : splat(1.f);
    store(s.br + o, br * inv_q);
    store(s.bg + o, bg * inv_q);
    store(s.bb + o, bb * inv_q);
    store(s.alive + o, goes_on & (cos_o != 0.f) & (pdf_b > 0.f) & survives & ((br > 0.f) | (bg > 0.f) | (bb > 0.f)));
}

[[gnu::noinline]] void shade_lanes(Lanes& s, const LaneScene& ls, const LaneSettings& st) {
    for (int o = 0; o < kLanes; o += kGroup) shade_group(s, o, ls, st);
}
}  // namespace

uint64_t render_tile_lanes(const LaneScene& ls, const Scene& scene, const LaneSettings& settings, const TileJob& job,
                           Film& film, SamplerType type) {
    const int rr_depth = settings.rr_depth;
    struct Estimate {
        Spectrum L;
        float fx, fy;
    };
    constexpr int kVertexDims = 7;  // path.cpp's layout: light select, light point (2), lobe, bounce (2), roulette
    const int tile_w = job.x1 - job.x0, n_samples = job.s1 - job.s0;
    const int64_t n_pixels = int64_t(tile_w) * (job.y1 - job.y0);
    constexpr int64_t kChunkPaths = 4096;  // as render_tile_packets: whole pixels, ~4096 paths
    const int64_t chunk_pixels = std::max<int64_t>(1, kChunkPaths / n_samples);
    thread_local std::vector<Estimate> done;
    thread_local std::unique_ptr<Lanes> lanes_buf;
    if (!lanes_buf) lanes_buf = std::make_unique<Lanes>();
    Lanes& s = *lanes_buf;
    Sampler samplers[kLanes];
    int64_t path_of[kLanes];
    const bool splat = film.splats();
    uint64_t bad = 0;
    auto pixel_xy = [&](int64_t px, int* x, int* y) {
        *x = job.x0 + int(px % tile_w);
        *y = job.y0 + int(px / tile_w);
    };
    for (int64_t p0 = 0; p0 < n_pixels; p0 += chunk_pixels) {
        const int64_t n_paths = std::min(chunk_pixels, n_pixels - p0) * n_samples;
        done.resize(size_t(n_paths));
        int64_t next = 0;
        // Path k of the chunk (pixel p0 + k / n_samples, sample k % n_samples) into lane i, or idle it.
        auto start = [&](int i) {
            if (next >= n_paths) {
                s.active[i] = 0;
                return;
            }
            const int64_t k = next++;
            int x, y;
            pixel_xy(p0 + k / n_samples, &x, &y);
            path_of[i] = k;
            samplers[i] = Sampler(type, uint64_t(y) * uint64_t(scene.width) + uint64_t(x),
                                  uint64_t(job.s0 + int(k % n_samples)), job.seed);
            const RayDifferential r = camera_sample(scene, splat, x, y, samplers[i], &done[k].fx, &done[k].fy);
            s.ox[i] = r.o.x;
            s.oy[i] = r.o.y;
            s.oz[i] = r.o.z;
            s.dx[i] = r.d.x;
            s.dy[i] = r.d.y;
            s.dz[i] = r.d.z;
            s.tmax[i] = r.tmax;
            s.br[i] = s.bg[i] = s.bb[i] = 1.f;
            s.Lr[i] = s.Lg[i] = s.Lb[i] = 0.f;
            s.prev_pdf[i] = 0.f;
            s.px[i] = s.py[i] = s.pz[i] = 0.f;
            s.depth[i] = 1;
            s.active[i] = -1;
        };
        for (int i = 0; i < kLanes; ++i) start(i);
        for (;;) {
            bool any = false;
            for (int g = 0; g < kGroups; ++g) {
                const int o = g * kGroup;
                bool on = false;
                for (int i = o; i < o + kGroup; ++i) on = on || s.active[i];
                if (!on) {
                    for (int i = o; i < o + kGroup; ++i) s.geom[i] = -1;
                    continue;
                }
                any = true;
                scene.accel.intersect_soa(s.active + o, {s.ox + o, s.oy + o, s.oz + o, s.dx + o, s.dy + o, s.dz + o, s.tmax + o},
                                          s.t + o, s.bu + o, s.bv + o, reinterpret_cast<uint32_t*>(s.geom + o),
                                          reinterpret_cast<uint32_t*>(s.prim + o));
            }
            if (!any) break;
            // This vertex's random numbers, in path.cpp's dimensions (a miss draws none).
            for (int i = 0; i < kLanes; ++i) {
                if (!s.active[i] || s.geom[i] < 0) continue;
                Sampler& sm = samplers[i];
                const int dim0 = Sampler::kPixelDims + kVertexDims * (s.depth[i] - 1);
                sm.set_dimension(dim0);
                s.u_sel[i] = sm.get_1d();
                const Vec2f ul = sm.get_2d();
                sm.set_dimension(dim0 + 4);
                const Vec2f ub = sm.get_2d();
                s.u_l0[i] = ul.x;
                s.u_l1[i] = ul.y;
                s.u_b0[i] = ub.x;
                s.u_b1[i] = ub.y;
                if (s.depth[i] >= rr_depth) {
                    sm.set_dimension(dim0 + 6);
                    s.u_rr[i] = sm.get_1d();
                } else {
                    s.u_rr[i] = 0.f;
                }
            }
            shade_lanes(s, ls, settings);
            for (int g = 0; g < kGroups; ++g) {
                const int o = g * kGroup;
                bool on = false;
                for (int i = o; i < o + kGroup; ++i) on = on || s.shadow[i];
                if (!on) continue;
                scene.accel.occluded_soa(s.shadow + o, {s.sox + o, s.soy + o, s.soz + o, s.sdx + o, s.sdy + o, s.sdz + o, s.stmax + o},
                                         s.occluded + o);
                for (int i = o; i < o + kGroup; ++i) {
                    const bool add = s.shadow[i] && !s.occluded[i];
                    s.Lr[i] += add ? s.Ldr[i] : 0.f;
                    s.Lg[i] += add ? s.Ldg[i] : 0.f;
                    s.Lb[i] += add ? s.Ldb[i] : 0.f;
                }
            }
            for (int i = 0; i < kLanes; ++i) {
                if (!s.active[i] || s.alive[i]) continue;
                done[size_t(path_of[i])].L = Spectrum(s.Lr[i], s.Lg[i], s.Lb[i]);
                start(i);
            }
        }
        for (int64_t k = 0; k < n_paths; ++k) {
            int x, y;
            pixel_xy(p0 + k / n_samples, &x, &y);
            if (!film_add<SampleValues::NonNegative>(film, x, y, done[k].fx, done[k].fy, done[k].L)) ++bad;
        }
    }
    return bad;
}
}  // namespace pellucid
