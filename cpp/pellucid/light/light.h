// The closed list of light types, and the queries that treat the lights at infinity alike.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <type_traits>
#include <variant>

#include "pellucid/light/area.h"
#include "pellucid/light/constant.h"
#include "pellucid/light/envmap.h"
#include "pellucid/light/point.h"

namespace pellucid {
using Light = std::variant<AreaLight, ConstantLight, PointLight, SpotLight, DirectionalLight, EnvmapLight>;
inline std::string to_string(const Light& l) {
    return std::visit([](const auto& x) { return x.to_string(); }, l);
}

/// Lights at infinity that a ray escaping the scene sees (they have Le(dir) and pdf_li(ctx, dir)).
/// The directional light is at infinity too, but a delta: no escaping ray reaches it.
template <class T>
inline constexpr bool is_infinite_area_light_v =
    std::is_same_v<T, ConstantLight> || std::is_same_v<T, EnvmapLight>;

/// Radiance and light-sampling density (solid angle, before light selection) that an escaping ray
/// with direction dir picks up from light l; zero for lights that are not infinite area lights.
struct InfiniteHit {
    Spectrum Le{0.f};
    float pdf = 0.f;
};
inline InfiniteHit infinite_hit(const Light& l, const LightSampleContext& ctx, const Vec3f& dir) {
    return std::visit([&](const auto& x) {
        using T = std::decay_t<decltype(x)>;
        if constexpr (is_infinite_area_light_v<T>) return InfiniteHit{x.Le(dir), x.pdf_li(ctx, dir)};
        else return InfiniteHit{};
    }, l);
}

/// Emitted power (W) used for light selection; lights at infinity count the power crossing a disk
/// of the scene's bounding radius (pbrt-v4's convention).
inline float light_power(const Light& l, float scene_radius) {
    return std::visit([&](const auto& x) {
        using T = std::decay_t<decltype(x)>;
        if constexpr (is_infinite_area_light_v<T>) return x.power(scene_radius);
        else return x.power();
    }, l);
}
}  // namespace pellucid
