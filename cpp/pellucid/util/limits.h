// Documented input limits, each with the way to raise it (docs/scene-format.md, "Limits").
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cfloat>
#include <cmath>

namespace pellucid {

/// Deepest nesting of objects and arrays a scene description may have (JSON files, dicts passed to
/// load_dict). Real scenes nest fewer than ten levels; the limit keeps a malformed or
/// self-referencing input from exhausting the stack. Raised with the environment variable
/// PELLUCID_MAX_SCENE_DEPTH (read once per process).
constexpr int kDefaultMaxSceneDepth = 256;
int max_scene_depth();

/// True when a parameter given in double precision survives conversion to the 32-bit float it is
/// stored in: finite, and no larger in magnitude than FLT_MAX (1e39 is finite as a double, infinite
/// as a float).
inline bool fits_float(double v) { return std::isfinite(v) && std::fabs(v) <= double(FLT_MAX); }
}  // namespace pellucid
