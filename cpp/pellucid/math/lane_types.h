// Vectors and colours over a lane type F (simd/lane.h). For F = float they are the library's own
// Vec2f/Vec3f (GLM) and Spectrum, so templated code instantiated on float is plain scalar code
// with the scalar types; for a packet they are structures of packets (one packet per component).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <type_traits>

#include "pellucid/math/spectrum.h"
#include "pellucid/math/vec.h"
#include "pellucid/simd/lane.h"

namespace pellucid {

/// Three packets: x, y and z of kLaneWidth<F> vectors.
template <class F>
struct Vec3P {
    F x, y, z;
    Vec3P() = default;
    Vec3P(const F& x_, const F& y_, const F& z_) : x(x_), y(y_), z(z_) {}
    explicit Vec3P(const F& v) : x(v), y(v), z(v) {}
    Vec3P operator+(const Vec3P& o) const { return {x + o.x, y + o.y, z + o.z}; }
    Vec3P operator-(const Vec3P& o) const { return {x - o.x, y - o.y, z - o.z}; }
    Vec3P operator*(const F& s) const { return {x * s, y * s, z * s}; }
    Vec3P operator/(const F& s) const { return {x / s, y / s, z / s}; }
    Vec3P operator-() const { return {lane::neg(x), lane::neg(y), lane::neg(z)}; }
    Vec3P& operator+=(const Vec3P& o) { return *this = *this + o; }
};
template <class F>
inline Vec3P<F> operator*(const F& s, const Vec3P<F>& v) { return v * s; }
template <class F>
inline F dot(const Vec3P<F>& a, const Vec3P<F>& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
template <class F>
inline Vec3P<F> cross(const Vec3P<F>& a, const Vec3P<F>& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class F>
inline F length2(const Vec3P<F>& a) { return dot(a, a); }
template <class F>
inline F length(const Vec3P<F>& a) { return lane::sqrt(dot(a, a)); }
template <class F>
inline Vec3P<F> normalize(const Vec3P<F>& a) { return a * (F(1.f) / length(a)); }  // as glm::normalize
template <class F>
inline Vec3P<F> abs(const Vec3P<F>& a) { return {lane::abs(a.x), lane::abs(a.y), lane::abs(a.z)}; }

/// Two packets (points on the unit square).
template <class F>
struct Vec2P {
    F x, y;
};

/// RGB of kLaneWidth<F> colours.
template <class F>
struct SpectrumP {
    F r, g, b;
    SpectrumP() = default;
    SpectrumP(const F& r_, const F& g_, const F& b_) : r(r_), g(g_), b(b_) {}
    explicit SpectrumP(const F& v) : r(v), g(v), b(v) {}
    SpectrumP operator+(const SpectrumP& o) const { return {r + o.r, g + o.g, b + o.b}; }
    SpectrumP operator*(const SpectrumP& o) const { return {r * o.r, g * o.g, b * o.b}; }
    SpectrumP operator*(const F& s) const { return {r * s, g * s, b * s}; }
    SpectrumP operator/(const F& s) const { return {r / s, g / s, b / s}; }
    SpectrumP& operator+=(const SpectrumP& o) { return *this = *this + o; }
    SpectrumP& operator*=(const SpectrumP& o) { return *this = *this * o; }
    SpectrumP& operator*=(const F& s) { return *this = *this * s; }
};
template <class F>
inline SpectrumP<F> operator*(const F& s, const SpectrumP<F>& c) { return c * s; }

namespace detail {
template <class F>
struct LaneTypes {
    using V2 = Vec2P<F>;
    using V3 = Vec3P<F>;
    using RGB = SpectrumP<F>;
};
template <>
struct LaneTypes<float> {
    using V2 = Vec2f;
    using V3 = Vec3f;
    using RGB = Spectrum;
};
}  // namespace detail
template <class F>
using V2 = typename detail::LaneTypes<F>::V2;
template <class F>
using V3 = typename detail::LaneTypes<F>::V3;
template <class F>
using RGB = typename detail::LaneTypes<F>::RGB;

// The colour queries as free functions, for both forms.
inline float max_component(const Spectrum& s) { return s.max_component(); }
inline bool is_black(const Spectrum& s) { return s.is_black(); }
template <class F>
inline F max_component(const SpectrumP<F>& s) { return lane::max(s.r, lane::max(s.g, s.b)); }
template <class F>
inline MaskT<F> is_black(const SpectrumP<F>& s) { return (s.r == F(0.f)) && (s.g == F(0.f)) && (s.b == F(0.f)); }

// Per-lane choice between two values of any of these types.
namespace lane {
inline Vec3f select(bool m, const Vec3f& a, const Vec3f& b) { return m ? a : b; }
inline Spectrum select(bool m, const Spectrum& a, const Spectrum& b) { return m ? a : b; }
template <class M, class F>
inline Vec3P<F> select(const M& m, const Vec3P<F>& a, const Vec3P<F>& b) {
    return {select(m, a.x, b.x), select(m, a.y, b.y), select(m, a.z, b.z)};
}
template <class M, class F>
inline SpectrumP<F> select(const M& m, const SpectrumP<F>& a, const SpectrumP<F>& b) {
    return {select(m, a.r, b.r), select(m, a.g, b.g), select(m, a.b, b.b)};
}
}  // namespace lane
}  // namespace pellucid
