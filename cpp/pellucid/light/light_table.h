// The lights next-event estimation samples as packets when the scene has no emitter table
// (area.h): sphere area lights, constant environments, environment maps and the delta lights
// (point, spot, directional), one row each, read by the light's index with gathers. Each lane
// picks its light from the table's float running sums of the light probabilities
// (pick_light_lanes; path_services::pick_light is its float instantiation); lanes whose light has
// no row here (mesh area lights) are sampled one at a time (path_services::sample_picked_light).
// The scalar sample_li of these lights is the float instantiation of the same code
// (sample_sphere, square_to_uniform_sphere_lanes<F>, envmap_sample, point_light_sample,
// spot_light_sample, directional_light_sample).
// An environment map's row holds its rotation, and its integer row the offsets of its CDFs and
// texels in one buffer (LightTable::env) that packets gather from, so lanes of different maps mix.
// The table also lists the lights at infinity, for the radiance of escaping rays (escaped_radiance).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <vector>

#include <memory>

#include "pellucid/light/area.h"
#include "pellucid/light/constant.h"
#include "pellucid/light/envmap.h"
#include "pellucid/light/point.h"
#include "pellucid/sampling/mis.h"

namespace pellucid {

/// Per light, kStride floats: kind (LightTable::Kind as a float), then for a sphere its centre (3),
/// radius, flip (1 or 0), two-sided (1 or 0), radiance (3); for a constant environment its radiance
/// at 7..9; for an environment map its rotation (9, column-major) at 1..9; for a point light its
/// position (3) and intensity at 7..9; for a spot light its position (3), unit axis (3), intensity
/// (3), then the cosine of its cutoff, its cutoff and its beam angle (radians) at 10..12; for a
/// directional light the unit direction it travels (3) and its irradiance at 7..9; for an area light
/// on a mesh its first triangle in mesh_rows, its CDF's offset in mesh_cdf and its triangle count
/// (whole numbers below 2²³, as floats) at 1..3, its area, two-sided (1 or 0) at 6 and its radiance
/// at 7..9.
/// Per light, kIntStride integers: for an environment map the offsets in env of its marginal
/// CDF, its conditional CDFs and its texels, its width and height; for other lights offsets 0 and
/// the size 2 × 3, which keep their lanes' (unused) reads inside any map's buffer.
struct LightTable {
    enum Kind : int { kNone = 0, kSphere = 1, kConstant = 2, kEnvmap = 3, kPoint = 4, kSpot = 5, kDirectional = 6, kMesh = 7 };
    static constexpr int kStride = 13;
    static constexpr int kPad = 3;  ///< zeros after the last row: a row is read as 16 floats (sample_light_table)
    static constexpr int kIntStride = 5;
    std::vector<float> data;
    std::vector<int32_t> idata;
    std::vector<int32_t> kind;  ///< per light: Kind
    bool any = false;           ///< some light has a packet form
    /// The mesh area lights' triangles and area CDFs (AreaLight::sampling_rows, sampling_cdf), one
    /// light after another, and the largest sampling_top among them (sample_mesh_light).
    std::vector<float> mesh_rows, mesh_cdf;
    int mesh_top = 0;
    /// The environment maps' buffer: the one map's own, or their copies one after another.
    std::shared_ptr<const std::vector<float>> env;
    int32_t sole_envmap = -1;  ///< the row of the table's one environment map, −1 without or with several
    const float* env_base() const { return env ? env->data() : nullptr; }
    /// The lights at infinity (constant environments, environment maps) in index order, with the
    /// probability with which NEE picks each.
    std::vector<int32_t> infinite;
    std::vector<float> infinite_pmf;
    /// NEE's choice of a light (pick_light_lanes), by the probabilities `pmf` the table was made with:
    /// pick_cdf their running sums in float (n + 1 entries, the last 1), pick_pmf the probabilities,
    /// pick_nonempty[i] the last light at or before i with a nonzero probability.
    std::vector<float> pick_cdf, pick_pmf;
    std::vector<int32_t> pick_nonempty;
};

/// The light NEE samples, for each lane, from u ∈ [0, 1): the largest i with pick_cdf[i] ≤ u (a
/// branch-free binary search of ⌈log2(n + 1)⌉ gathers; the comparisons of random u are
/// unpredictable), moved back to a light of nonzero probability where u rounds past the last
/// one; *pmf receives its probability. Every light's row is in t, lights without a packet form
/// included; t must have at least one light.
template <class F>
inline IntT<F> pick_light_lanes(const LightTable& t, const F& u, F* pmf) {
    using I = IntT<F>;
    const int n = int(t.pick_pmf.size());
    const float* c = t.pick_cdf.data();
    I base(0);
    for (int len = n + 1; len > 1;) {
        const int half = len / 2;
        const I probe = base + I(half);
        base = lane::select(lane::int_mask(lane::gather(c, probe) <= u), probe, base);
        len -= half;
    }
    const I i = lane::gather(t.pick_nonempty.data(), lane::min(base, I(n - 1)));
    *pmf = lane::gather(t.pick_pmf.data(), i);
    return i;
}

namespace light_table_detail {
/// An environment map's lanes from its row's integers N(k) (idata) and floats R(k) (data), read
/// per lane or once for all lanes (envmap_lanes, envmap_row_lanes).
template <class F, class N, class R>
inline EnvmapLanes<F> envmap_from_row(const LightTable& t, N n, R r) {
    EnvmapLanes<F> e;
    e.w = n(3), e.h = n(4);
    e.dist = Piecewise2DLanes<F>{t.env_base(), n(0), n(1), e.w, e.h - IntT<F>(1)};
    e.texels = n(2);
    for (int k = 0; k < 9; ++k) e.rot[k] = r(1 + k);
    return e;
}
}  // namespace light_table_detail

/// The environment map of row(s) `light` as lanes read it (light_table's rows for kEnvmap).
template <class F>
inline EnvmapLanes<F> envmap_lanes(const LightTable& t, const IntT<F>& light) {
    using I = IntT<F>;
    const I base = light * I(LightTable::kStride), ibase = light * I(LightTable::kIntStride);
    return light_table_detail::envmap_from_row<F>(
        t, [&](int k) { return lane::gather(t.idata.data() + k, ibase); },
        [&](int k) { return lane::gather(t.data.data() + k, base); });
}
/// The map of row `light` on every lane (the same values as the per-lane form, without gathers).
template <class F>
inline EnvmapLanes<F> envmap_row_lanes(const LightTable& t, int32_t light) {
    const int32_t* n = t.idata.data() + size_t(LightTable::kIntStride) * size_t(light);
    const float* r = t.data.data() + size_t(LightTable::kStride) * size_t(light);
    return light_table_detail::envmap_from_row<F>(t, [&](int k) { return IntT<F>(n[k]); },
                                                  [&](int k) { return F(r[k]); });
}

/// A light sample in kLaneWidth<F> lanes: the point (for a sphere, a point or a spot light; the
/// latter two with zero normal and error bound, so the shadow ray ends at the point exactly, as
/// SurfaceInteraction::spawn_ray_to does for their sample_li) and what NEE needs of it.
/// infinite: a light at infinity, a constant environment, a map or a directional light (the shadow
/// ray has no end). delta: a delta light (point, spot, directional; pdf 1, no MIS).
template <class F>
struct LightTableSample {
    MaskT<F> valid, infinite, delta;
    V3<F> p, n, err, wi;
    RGB<F> L;
    F pdf;  ///< solid-angle density at p_ref, light selection not included
};

/// Sample light `light` (an index with a row in t, per lane) as seen from p_ref with u: a sphere by
/// sample_sphere, a constant environment uniformly over the sphere of directions, an environment
/// map by envmap_sample, the delta lights by their own templates (point.h; u unused). Each lane's
/// results depend on its own inputs only; lanes of other lights, and lanes outside `active`, come
/// back invalid and zero (and cost no per-lane work, such as the spot falloff's acos).
template <class F>
inline LightTableSample<F> sample_light_table(const LightTable& t, const IntT<F>& light, const V3<F>& p_ref,
                                              const V2<F>& u, const MaskT<F>& active = MaskT<F>(true)) {
    using I = IntT<F>;
    using M = MaskT<F>;
    const I base = light * I(LightTable::kStride);
    // Each lane's row as one row read of 16 floats (the table is padded past its last row),
    // transposed into packets (lane::gather_rows), not a gather per entry.
    F row[16];
    lane::gather_rows<16>(t.data.data(), base, row);
    auto E = [&](int k) { return row[k]; };
    const F kind = lane::select(active, E(0), F(float(LightTable::kNone)));
    const M sphere = kind == F(float(LightTable::kSphere)), constant = kind == F(float(LightTable::kConstant));
    const M envmap = kind == F(float(LightTable::kEnvmap));
    const M point = kind == F(float(LightTable::kPoint)), spot = kind == F(float(LightTable::kSpot));
    const M directional = kind == F(float(LightTable::kDirectional));
    const M mesh = kind == F(float(LightTable::kMesh));
    const RGB<F> radiance(E(7), E(8), E(9));
    LightTableSample<F> s;
    s.valid = M(false);
    s.infinite = constant || directional;
    s.delta = point || spot || directional;
    s.p = s.n = s.err = s.wi = V3<F>(F(0.f));
    s.L = RGB<F>(F(0.f));
    s.pdf = F(0.f);
    if (lane::any(sphere)) {
        const SphereSample<F> ss = sample_sphere<F>(V3<F>(E(1), E(2), E(3)), E(4), E(5) > F(0.f), p_ref, u);
        const M faces = E(6) > F(0.f) || dot(ss.n, -ss.wi) > F(0.f);  // AreaLight::L
        const V3<F> zero(F(0.f));
        s.p = lane::select(sphere, ss.p, zero), s.n = lane::select(sphere, ss.n, zero);
        s.err = lane::select(sphere, ss.err, zero), s.wi = lane::select(sphere, ss.wi, zero);
        s.pdf = lane::select(sphere, ss.pdf, F(0.f));
        s.L = lane::select(sphere && faces, radiance, RGB<F>(F(0.f)));
        s.valid = sphere && ss.valid && !is_black(s.L);
    }
    if (lane::any(mesh)) {
        // (Other lanes read the first light's first triangle: their entries 1..4 are not offsets.)
        const auto mi = lane::int_mask(mesh);
        auto whole = [&](int k, int32_t other) { return lane::select(mi, detail::whole_to_int<F>(E(k)), I(other)); };
        const MeshLightSample<F> ms = sample_mesh_light<F>(t.mesh_rows.data(), t.mesh_cdf.data(), whole(1, 0), whole(2, 0),
                                                           whole(3, 1), t.mesh_top, lane::select(mesh, E(4), F(1.f)), p_ref, u);
        const M faces = E(6) > F(0.f) || dot(ms.n, -ms.wi) > F(0.f);  // AreaLight::L
        s.p = lane::select(mesh, ms.p, s.p), s.n = lane::select(mesh, ms.n, s.n);
        s.err = lane::select(mesh, ms.err, s.err), s.wi = lane::select(mesh, ms.wi, s.wi);
        s.pdf = lane::select(mesh, ms.pdf, s.pdf);
        s.L = lane::select(mesh && faces, radiance, s.L);
        s.valid = s.valid || (mesh && ms.valid && !is_black(s.L));
    }
    if (lane::any(constant)) {
        s.wi = lane::select(constant, square_to_uniform_sphere_lanes<F>(u), s.wi);
        s.pdf = lane::select(constant, F(kInv4Pi), s.pdf);
        s.L = lane::select(constant, radiance, s.L);
        s.valid = s.valid || constant;
    }
    if (lane::any(envmap)) {
        // (Every envmap lane reads the same row when the table has one map: its values without gathers.)
        const EnvmapSampleT<F> es = envmap_sample<F>(
            t.sole_envmap >= 0 ? envmap_row_lanes<F>(t, t.sole_envmap) : envmap_lanes<F>(t, light), u);
        s.wi = lane::select(envmap, es.wi, s.wi);
        s.pdf = lane::select(envmap, es.pdf, s.pdf);
        s.L = lane::select(envmap, es.L, s.L);
        s.valid = s.valid || (envmap && es.valid);
        s.infinite = s.infinite || envmap;
    }
    const M at_point = point || spot;
    if (lane::any(at_point)) {
        const V3<F> pl(E(1), E(2), E(3));
        DeltaLightSample<F> ds = point_light_sample<F>(pl, radiance, p_ref);  // spot_light_sample's first step
        if (lane::any(spot)) apply_spot_falloff<F>(ds, spot, V3<F>(E(4), E(5), E(6)), E(10), E(11), E(12));
        s.p = lane::select(at_point, pl, s.p);
        s.wi = lane::select(at_point, ds.wi, s.wi);
        s.pdf = lane::select(at_point, F(1.f), s.pdf);
        s.L = lane::select(at_point, ds.L, s.L);
        s.valid = s.valid || (at_point && ds.valid);
    }
    if (lane::any(directional)) {
        const DeltaLightSample<F> ds = directional_light_sample<F>(V3<F>(E(1), E(2), E(3)), radiance);
        s.wi = lane::select(directional, ds.wi, s.wi);
        s.pdf = lane::select(directional, F(1.f), s.pdf);
        s.L = lane::select(directional, ds.L, s.L);
        s.valid = s.valid || directional;
    }
    return s;
}

/// Radiance that rays escaping the scene along d (unit) pick up from the lights at infinity, each
/// MIS-weighted against NEE's density for it (bsdf_hit_weight: the previous vertex's BSDF density
/// prev_pdf, `specular` after a delta bounce), summed in index order as path_services::escaped does.
template <class F>
inline RGB<F> escaped_radiance(const LightTable& t, const V3<F>& d, bool use_mis, bool use_nee,
                               const MaskT<F>& specular, const F& prev_pdf) {
    RGB<F> L(F(0.f));
    for (size_t k = 0; k < t.infinite.size(); ++k) {
        const int32_t li = t.infinite[k];
        const float* row = &t.data[size_t(LightTable::kStride) * size_t(li)];
        RGB<F> Le;
        F pdf;
        if (t.kind[size_t(li)] == LightTable::kEnvmap) {
            Le = envmap_Le_pdf<F>(envmap_row_lanes<F>(t, li), d, &pdf);
        } else {
            Le = RGB<F>(F(row[7]), F(row[8]), F(row[9]));
            pdf = F(kInv4Pi);
        }
        L += Le * bsdf_hit_weight<F>(use_mis, use_nee, specular, prev_pdf, F(t.infinite_pmf[k]) * pdf);
    }
    return L;
}

/// The rows of `lights` (a Light variant list, light.h); pmf: NEE's probability of each light
/// (empty: all 0).
template <class LightT>
LightTable make_light_table(const std::vector<LightT>& lights, const std::vector<float>& pmf = {});
}  // namespace pellucid
