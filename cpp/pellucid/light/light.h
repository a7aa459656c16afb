// The closed list of light types.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <variant>

#include "pellucid/light/area.h"
#include "pellucid/light/constant.h"
#include "pellucid/light/point.h"

namespace pellucid {
using Light = std::variant<AreaLight, ConstantLight, PointLight, SpotLight, DirectionalLight>;
inline std::string to_string(const Light& l) {
    return std::visit([](const auto& x) { return x.to_string(); }, l);
}
}  // namespace pellucid
