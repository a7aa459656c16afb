// The lights next-event estimation samples as packets when the scene has no emitter table
// (area.h): sphere area lights and constant environments, one row each, read by the light's index
// with gathers. The light is still picked one lane at a time (Scene::sample_light, whose
// double-precision CDF stays the one choice); lanes whose light has no row here are sampled one at
// a time (path_services::sample_light). The scalar sample_li of these lights is the float
// instantiation of the same code (sample_sphere, square_to_uniform_sphere_lanes<F>).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <vector>

#include "pellucid/light/area.h"
#include "pellucid/light/constant.h"

namespace pellucid {

/// Per light, kStride floats: kind (LightTable::Kind as a float), centre (3), radius, flip (1 or
/// 0), two-sided (1 or 0), radiance (3), one float of padding.
struct LightTable {
    enum Kind : int { kNone = 0, kSphere = 1, kConstant = 2 };
    static constexpr int kStride = 11;
    std::vector<float> data;
    std::vector<int32_t> kind;  ///< per light: Kind
    bool any = false;           ///< some light has a packet form
};

/// A light sample in kLaneWidth<F> lanes: the point (for a sphere) and what NEE needs of it.
/// infinite: the constant environment (the shadow ray has no end).
template <class F>
struct LightTableSample {
    MaskT<F> valid, infinite;
    V3<F> p, n, err, wi;
    RGB<F> L;
    F pdf;  ///< solid-angle density at p_ref, light selection not included
};

/// Sample light `light` (an index with a row in t, per lane) as seen from p_ref with u: a sphere by
/// sample_sphere, a constant environment uniformly over the sphere of directions. Each lane's
/// results depend on its own inputs only; lanes of other lights come back invalid and zero.
template <class F>
inline LightTableSample<F> sample_light_table(const LightTable& t, const IntT<F>& light, const V3<F>& p_ref,
                                              const V2<F>& u) {
    using I = IntT<F>;
    using M = MaskT<F>;
    const I base = light * I(LightTable::kStride);
    const float* d = t.data.data();
    auto E = [&](int k) { return lane::gather(d + k, base); };
    const F kind = E(0);
    const M sphere = kind == F(float(LightTable::kSphere)), constant = kind == F(float(LightTable::kConstant));
    const RGB<F> radiance(E(7), E(8), E(9));
    LightTableSample<F> s;
    s.valid = M(false);
    s.infinite = constant;
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
    if (lane::any(constant)) {
        s.wi = lane::select(constant, square_to_uniform_sphere_lanes<F>(u), s.wi);
        s.pdf = lane::select(constant, F(kInv4Pi), s.pdf);
        s.L = lane::select(constant, radiance, s.L);
        s.valid = s.valid || constant;
    }
    return s;
}

/// The rows of `lights` (a Light variant list, light.h).
template <class LightT>
LightTable make_light_table(const std::vector<LightT>& lights);
}  // namespace pellucid
