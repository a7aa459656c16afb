// Integrator: the one virtual interface (called once per render, never per ray).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <memory>
#include <string>

#include "pellucid/integrator/render_loop.h"

namespace pellucid {
class Scene;

class Integrator {
public:
    virtual ~Integrator() = default;
    virtual RenderResult render(const Scene& scene, const RenderOptions& opts) const = 0;
    virtual std::string to_string() const = 0;
};

/// The integrator the scene asks for.
std::unique_ptr<Integrator> make_integrator(const Scene& scene);
}  // namespace pellucid
