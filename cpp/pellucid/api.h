// THE facade used by the executable, the Python bindings and the tests, so the three front ends
// cannot diverge.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <memory>
#include <string>

#include "pellucid/image/image.h"
#include "pellucid/integrator/render_loop.h"
#include "pellucid/scene/scene.h"
#include "pellucid/scene/scene_desc.h"

namespace pellucid {
/// Parse a scene file (by extension: .json, or Mitsuba 3 .xml) into the IR.
SceneDesc load_desc_file(const std::string& path);
/// Parse and build a scene file.
std::shared_ptr<const Scene> load_file(const std::string& path);
/// Build a scene from an already parsed description (e.g. a Python dict).
std::shared_ptr<const Scene> load_desc(const SceneDesc& desc);
/// Render with the scene's integrator.
RenderResult render(const Scene& scene, const RenderOptions& opts);
/// Render one AOV ("albedo", "normal", "depth"; integrator/aov.h) instead of the scene's integrator.
RenderResult render_aov(const Scene& scene, const std::string& aov, const RenderOptions& opts);
/// Write / read images (see image/image_io.h).
void write_image(const std::string& path, const Image& img);
Image read_image(const std::string& path);
const char* version();
}  // namespace pellucid
