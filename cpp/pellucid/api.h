// THE facade used by the executable, the Python bindings and the tests, so the three front ends
// cannot diverge.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "pellucid/image/image.h"
#include "pellucid/integrator/render_loop.h"
#include "pellucid/scene/properties.h"
#include "pellucid/scene/scene.h"
#include "pellucid/scene/scene_desc.h"

namespace pellucid {
/// Parse a scene file (by extension: .json, or Mitsuba 3 .xml) into the IR. With `lenient`,
/// unsupported Mitsuba XML elements are logged as warnings (naming element and line) and skipped
/// instead of raising; JSON scenes ignore it.
SceneDesc load_desc_file(const std::string& path, bool lenient = false);
/// Parse and build a scene file.
std::shared_ptr<const Scene> load_file(const std::string& path, bool lenient = false);
/// Build a scene from an already parsed description (e.g. a Python dict).
std::shared_ptr<const Scene> load_desc(const SceneDesc& desc);
/// Build `desc` (errors as load_desc) and return, for every object built, the keys its builder
/// looked up (see ParameterRecord): what the documentation check compares with the docs.
std::vector<ParameterRecord> record_parameters(const SceneDesc& desc);
/// Render with the scene's integrator.
RenderResult render(const Scene& scene, const RenderOptions& opts);
/// Render one AOV ("albedo", "normal", "depth"; integrator/aov.h) instead of the scene's integrator.
RenderResult render_aov(const Scene& scene, const std::string& aov, const RenderOptions& opts);
/// Write / read images (see image/image_io.h).
void write_image(const std::string& path, const Image& img);
Image read_image(const std::string& path);
const char* version();
}  // namespace pellucid
