// Documented input limits, each with the way to raise it (docs/scene-format.md, "Limits").
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cfloat>
#include <cmath>
#include <string>

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
/// Largest coordinate magnitude of scene geometry, the camera and positional lights, in scene
/// units. Embree rejects (and asserts on) ray origins of magnitude 1.844e18 or more; rays leave
/// surfaces and lights, so positions stay below 1e18. Not configurable: past it float spacing
/// exceeds 1e11 units and nothing can be rendered meaningfully.
constexpr float kMaxCoordinate = 1e18f;
inline bool within_coordinate_limit(float x, float y, float z) {
    return std::fabs(x) <= kMaxCoordinate && std::fabs(y) <= kMaxCoordinate && std::fabs(z) <= kMaxCoordinate;
}

/// "[x, y, z]" with 6 significant digits, for messages about coordinates.
std::string point_text(float x, float y, float z);

inline bool fits_float(double v) { return std::isfinite(v) && std::fabs(v) <= double(FLT_MAX); }
}  // namespace pellucid
