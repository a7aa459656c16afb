// The closed list of reflection models and free functions that dispatch over it.
// Adding a model = one type + one entry in `BxDF`; the property suite picks it up automatically.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>

#include "pellucid/bxdf/bxdf_types.h"
#include "pellucid/bxdf/conductor.h"
#include "pellucid/bxdf/dielectric.h"
#include "pellucid/bxdf/lambertian.h"
#include "pellucid/bxdf/oren_nayar.h"
#include "pellucid/bxdf/plastic.h"
#include "pellucid/bxdf/principled.h"
#include "pellucid/bxdf/principled_bsdf.h"

namespace pellucid {

/// Detection trait for the BxDF contract in bxdf_types.h.
template <class T, class = void>
struct is_bxdf : std::false_type {};
template <class T>
struct is_bxdf<T, std::void_t<
    decltype(std::declval<const T&>().eval(std::declval<const BxDFContext&>(), Vec3f(), Vec3f())),
    decltype(std::declval<const T&>().pdf(std::declval<const BxDFContext&>(), Vec3f(), Vec3f())),
    decltype(std::declval<const T&>().sample(std::declval<const BxDFContext&>(), Vec3f(), 0.f, Vec2f())),
    decltype(std::declval<const T&>().flags()), decltype(std::declval<const T&>().to_string())>>
    : std::integral_constant<bool,
          std::is_same_v<decltype(std::declval<const T&>().eval(BxDFContext{}, Vec3f(), Vec3f())), Spectrum> &&
          std::is_same_v<decltype(std::declval<const T&>().pdf(BxDFContext{}, Vec3f(), Vec3f())), float> &&
          std::is_same_v<decltype(std::declval<const T&>().sample(BxDFContext{}, Vec3f(), 0.f, Vec2f())),
                         std::optional<BxDFSample>>> {};
template <class T>
inline constexpr bool is_bxdf_v = is_bxdf<T>::value;

/// The closed list. Every microfacet model is here with both distributions (GGX and Beckmann);
/// Principled (Burley 2012) and PrincipledBSDF (Burley 2015) are GGX by definition.
using BxDF = std::variant<Lambertian, OrenNayar, SmoothConductor<ConductorFresnel>, RoughConductor,
                          RoughConductorBeckmann, SmoothDielectric, RoughDielectric<GGX>,
                          RoughDielectric<Beckmann>, ThinDielectric, SmoothPlastic, RoughPlastic<GGX>,
                          RoughPlastic<Beckmann>, Principled, PrincipledBSDF>;

namespace detail {
template <class V>
struct all_bxdfs;
template <class... Ts>
struct all_bxdfs<std::variant<Ts...>> : std::bool_constant<(is_bxdf_v<Ts> && ...)> {};
}  // namespace detail
static_assert(detail::all_bxdfs<BxDF>::value, "every BxDF alternative must satisfy the contract");

namespace detail {
/// std::visit for one BxDF as a switch over its alternatives: each case calls the alternative's
/// member directly, so the compiler can inline it (std::visit goes through a table of function
/// pointers and returns records through memory on every call; it was ~9 % of a diffuse render).
template <class F, size_t... I>
inline decltype(auto) visit_bxdf(const BxDF& b, F&& f, std::index_sequence<I...>) {
    using R = decltype(f(*std::get_if<0>(&b)));
    R r{};
    (void)((b.index() == I ? (r = f(*std::get_if<I>(&b)), true) : false) || ...);
    return r;
}
}  // namespace detail
template <class F>
inline decltype(auto) visit_bxdf(const BxDF& b, F&& f) {
    return detail::visit_bxdf(b, std::forward<F>(f), std::make_index_sequence<std::variant_size_v<BxDF>>{});
}

inline Spectrum eval(const BxDF& b, const BxDFContext& c, const Vec3f& wo, const Vec3f& wi) {
    return visit_bxdf(b, [&](const auto& x) { return x.eval(c, wo, wi); });
}
inline float pdf(const BxDF& b, const BxDFContext& c, const Vec3f& wo, const Vec3f& wi) {
    return visit_bxdf(b, [&](const auto& x) { return x.pdf(c, wo, wi); });
}
inline std::optional<BxDFSample> sample(const BxDF& b, const BxDFContext& c, const Vec3f& wo,
                                        float u_lobe, const Vec2f& u) {
    return visit_bxdf(b, [&](const auto& x) { return x.sample(c, wo, u_lobe, u); });
}
inline BxDFFlags flags(const BxDF& b) {
    return visit_bxdf(b, [](const auto& x) { return x.flags(); });
}
inline std::string to_string(const BxDF& b) {
    return std::visit([](const auto& x) { return x.to_string(); }, b);
}
}  // namespace pellucid
