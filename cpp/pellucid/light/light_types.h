// Records shared by all light types.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include "pellucid/math/spectrum.h"
#include "pellucid/math/vec.h"

namespace pellucid {

/// The receiving point of a light query. n = 0 for points not on a surface.
struct LightSampleContext {
    Point3f p{0.f};
    Normal3f n{0.f};
};

/// A sampled light path vertex as seen from the receiver.
struct LightLiSample {
    Spectrum L{0.f};    ///< emitted radiance arriving along -wi (unoccluded)
    Vec3f wi{0.f};      ///< unit direction from the receiver toward the light
    float pdf = 0.f;    ///< solid-angle density at the receiver (or 1 for delta lights)
    Point3f p_light{0.f};
    Normal3f n_light{0.f};
    Vec3f p_error{0.f};     ///< conservative error bound of p_light (for the shadow ray's end)
    bool infinite = false;  ///< at infinity: the shadow ray has no end point
    bool delta = false;     ///< a delta light (no MIS possible)
};
}  // namespace pellucid
