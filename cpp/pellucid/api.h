// THE facade used by the executable, the Python bindings and the tests, so the three front ends
// cannot diverge.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "pellucid/image/image.h"
#include "pellucid/image/image_io.h"
#include "pellucid/integrator/render_loop.h"
#include "pellucid/scene/properties.h"
#include "pellucid/scene/scene.h"
#include "pellucid/scene/scene_desc.h"

namespace pellucid {
/// Parse a scene file (by extension: .json, or Mitsuba 3 .xml) into the IR. With `lenient`,
/// unsupported Mitsuba XML elements are logged as warnings (naming element and line) and skipped
/// instead of raising; JSON scenes ignore it. `params` set Mitsuba XML `$name` values, overriding the
/// file's `<default>`s; JSON scenes have no parameters, so a non-empty `params` is an error there.
SceneDesc load_desc_file(const std::string& path, bool lenient = false,
                         const std::map<std::string, std::string>& params = {});
/// Parse and build a scene file.
std::shared_ptr<const Scene> load_file(const std::string& path, bool lenient = false,
                                       const std::map<std::string, std::string>& params = {});
/// Build a scene from an already parsed description (e.g. a Python dict).
std::shared_ptr<const Scene> load_desc(const SceneDesc& desc);
/// load_desc that moves `desc` into the scene (Scene::desc) instead of copying it.
std::shared_ptr<const Scene> load_desc(SceneDesc&& desc);
/// Build `desc` (errors as load_desc) and return, for every object built, the keys its builder
/// looked up (see ParameterRecord): what the documentation check compares with the docs.
std::vector<ParameterRecord> record_parameters(const SceneDesc& desc);
/// Render with the scene's integrator. With opts.resume, the state must come from the same
/// integrator (FilmState::integrator, when recorded); the result's state records it.
RenderResult render(const Scene& scene, const RenderOptions& opts);
/// Render one AOV ("albedo", "normal", "depth"; integrator/aov.h) instead of the scene's integrator.
RenderResult render_aov(const Scene& scene, const std::string& aov, const RenderOptions& opts);
/// The header attributes every front end writes with a rendered image: pellucid:spp (samples per
/// pixel, every pixel), pellucid:invalid_samples (NaN/Inf/negative samples dropped),
/// pellucid:interrupted (1 if the render was cancelled), pellucid:seconds, pellucid:seed,
/// pellucid:sampler, pellucid:version.
std::vector<ImageAttribute> render_attributes(const RenderResult& r);
/// Write / read images (see image/image_io.h).
void write_image(const std::string& path, const Image& img, const std::vector<ImageAttribute>& attributes = {});
Image read_image(const std::string& path);
const char* version();
}  // namespace pellucid
