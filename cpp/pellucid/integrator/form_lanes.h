// How the path tracer's packet forms reach the lanes of a packet that take part in a call: on the
// packet itself, masked, or moved into the low lanes of its half-width packet (lane::HalfT).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <type_traits>

#include "pellucid/bxdf/bxdf_types.h"
#include "pellucid/math/lane_types.h"

namespace pellucid {

/// How a packet form's call reaches the lanes `where` it runs on (run_form in render_tile_kernel):
/// a form built and called over the lane type L of its `FormLanes`, whose `in` takes each input
/// from the packet and whose `put` merges each result into the packet's lanes `where`.
/// FormLanesWhole: the packet itself, masked (L = F). FormLanesHalf: the half-width packet
/// (lane::HalfT<F>) into whose low lanes `where`'s lanes are moved, in order: on a 16-lane packet
/// with at most 8 lanes taking part, the form runs on 8 lanes instead of 16, which costs fewer
/// cycles where a 512-bit operation costs two 256-bit ones (AMD Zen 4; bench/README.md has the
/// render times). Each lane computes exactly what it computes on the whole packet, so the image is
/// the same bit for bit (tests/cpp/integrator/test_form_lanes.cpp).
template <class F>
struct FormLanesWhole {
    using L = F;
    MaskT<F> where;
    template <class T>
    const T& in(const T& x) const { return x; }
    void put(F& dst, const F& v) const { dst = lane::select(where, v, dst); }
    void put(MaskT<F>& dst, const MaskT<F>& v) const { dst = lane::select(where, v, dst); }
    void put(IntT<F>& dst, const IntT<F>& v) const { dst = lane::select(lane::int_mask(where), v, dst); }
    void put(RGB<F>& dst, const RGB<F>& v) const { dst = lane::select(where, v, dst); }
    void put(V3<F>& dst, const V3<F>& v) const { dst = lane::select(where, v, dst); }
};
template <class F, class Move = typename lane::HalfOf<F>::Move>
struct FormLanesHalf {
    using L = lane::HalfT<F>;
    Move move;
    explicit FormLanesHalf(const MaskT<F>& where) : move(where) {}
    L in(const F& x) const { return move.in(x); }
    MaskT<L> in(const MaskT<F>& m) const { return move.in(m); }
    IntT<L> in(const IntT<F>& x) const { return move.in(x); }
    V2<L> in(const V2<F>& v) const { return V2<L>{in(v.x), in(v.y)}; }
    V3<L> in(const V3<F>& v) const { return V3<L>(in(v.x), in(v.y), in(v.z)); }
    RGB<L> in(const RGB<F>& v) const { return RGB<L>(in(v.r), in(v.g), in(v.b)); }
    void put(F& dst, const L& v) const { move.out(dst, v); }
    void put(MaskT<F>& dst, const MaskT<L>& v) const { move.out(dst, v); }
    void put(IntT<F>& dst, const IntT<L>& v) const { move.out(dst, v); }
    void put(RGB<F>& dst, const RGB<L>& v) const { put(dst.r, v.r), put(dst.g, v.g), put(dst.b, v.b); }
    void put(V3<F>& dst, const V3<L>& v) const { put(dst.x, v.x), put(dst.y, v.y), put(dst.z, v.z); }
};
/// body(c) with c the FormLanes of the lanes `where`: FormLanesHalf where F has a half-width packet
/// and at most half its lanes take part, else FormLanesWhole.
template <class F, class Body>
inline void run_on_lanes(const MaskT<F>& where, const Body& body) {
    if constexpr (lane::kHasHalf<F>) {
        const FormLanesHalf<F> half(where);
        if (half.move.count() <= kLaneWidth<F> / 2) return body(half);
    }
    body(FormLanesWhole<F>{where});
}
/// A sample's fields, through c.put.
template <class C, class F, class L>
inline void put_sample(const C& c, BxDFSampleT<F>& dst, const BxDFSampleT<L>& v) {
    c.put(dst.valid, v.valid), c.put(dst.wi, v.wi), c.put(dst.weight, v.weight);
    c.put(dst.pdf, v.pdf), c.put(dst.eta, v.eta), c.put(dst.lobe, v.lobe);
}

}  // namespace pellucid
