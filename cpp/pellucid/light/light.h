// The closed list of light types, and the queries that treat the lights at infinity alike.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <algorithm>
#include <cmath>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

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

/// Whether a light is at infinity (an environment, a constant or a directional light).
inline bool is_at_infinity(const Light& l) {
    return std::visit([](const auto& x) {
        using T = std::decay_t<decltype(x)>;
        return is_infinite_area_light_v<T> || std::is_same_v<T, DirectionalLight>;
    }, l);
}

/// Whether next-event estimation samples light l when the integrator weighs light and BSDF samples
/// by MIS. A constant environment is not: NEE would pick its directions uniformly over the sphere
/// (density 1/4π), half of them below the surface and the rest without regard to the BSDF, while
/// the BSDF sample's direction escapes to the same radiance with a density shaped like the
/// integrand; so the BSDF sample alone estimates it (MIS weight 1, as the light's density is then
/// 0), and the NEE sample goes to the other lights. The estimate stays unbiased as long as a
/// BSDF's sampling reaches every direction its BSDF scatters into: tests/python/test_constant_env_mis.py
/// renders a sphere of every model under a constant environment and under an environment map of the
/// same radiance (which NEE samples) and compares them pixel by pixel. pbrt-v4 does the same for its uniform
/// infinite light (Pharr et al. 2023, pbrt-v4 §12.5.1, allowIncompletePDF; Karlík et al. 2019, "MIS
/// Compensation", EGSR).
inline bool nee_under_mis(const Light& l) { return !std::holds_alternative<ConstantLight>(l); }

/// Unnormalised probabilities with which next-event estimation picks each light.
///  - "uniform": every light alike (Mitsuba 3's emitter sampling).
///  - "power": in proportion to light_power. A light at infinity counts the power crossing a disk
///    of the scene's radius, which a large ground plane makes large, so a small light beside an
///    environment is then rarely picked.
///  - "balanced" (the default): each light at infinity is picked as often as all finite lights
///    together, and the finite lights share their part in proportion to their power. This is the
///    top level of pbrt-v4's BVH light sampler (Pharr et al., pbrt-v4 §12.6.3), which gives the
///    infinite lights the probability n_inf / (n_inf + 1), without its spatial bounds below.
/// Under "power" and "balanced", a power that is not finite and positive gives weight 0.
inline std::vector<float> light_selection_weights(const std::vector<Light>& lights, const std::string& mode,
                                                  float scene_radius) {
    std::vector<float> w(lights.size(), 0.f);
    auto valid = [](float x) { return std::isfinite(x) && x > 0.f ? x : 0.f; };
    if (mode == "uniform") {
        std::fill(w.begin(), w.end(), 1.f);
        return w;
    }
    if (mode == "power") {
        for (size_t i = 0; i < lights.size(); ++i) w[i] = valid(light_power(lights[i], scene_radius));
        return w;
    }
    double finite_power = 0.0;
    for (size_t i = 0; i < lights.size(); ++i)
        if (!is_at_infinity(lights[i])) finite_power += valid(light_power(lights[i], scene_radius));
    for (size_t i = 0; i < lights.size(); ++i) {
        const float p = valid(light_power(lights[i], scene_radius));
        if (p == 0.f) continue;
        w[i] = is_at_infinity(lights[i]) ? 1.f : float(double(p) / finite_power);
    }
    return w;
}
}  // namespace pellucid
