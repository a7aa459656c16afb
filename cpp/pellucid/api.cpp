// The API facade.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/api.h"

#include <filesystem>

#include "pellucid/image/image_io.h"
#include "pellucid/integrator/aov.h"
#include "pellucid/integrator/integrator.h"
#include "pellucid/pellucid.h"
#include "pellucid/scene/build.h"
#include "pellucid/scene/json_io.h"
#include "pellucid/scene/mitsuba_xml.h"
#include "pellucid/util/error.h"

namespace pellucid {

SceneDesc load_desc_file(const std::string& path, bool lenient) {
    std::string ext = std::filesystem::path(path).extension().string();
    if (ext == ".json") return read_json_file(path);
    if (ext == ".xml") return read_mitsuba_xml_file(path, lenient);
    throw Error(path + ": unsupported scene format '" + ext + "' (expected .json or Mitsuba 3 .xml)");
}

std::shared_ptr<const Scene> load_file(const std::string& path, bool lenient) {
    return load_desc(load_desc_file(path, lenient));
}

std::shared_ptr<const Scene> load_desc(const SceneDesc& desc) { return build_scene(desc); }

std::vector<ParameterRecord> record_parameters(const SceneDesc& desc) {
    std::vector<ParameterRecord> records;
    struct Stop {  // stop recording on every exit, errors included
        ~Stop() { set_parameter_recorder(nullptr); }
    } stop;
    set_parameter_recorder(&records);
    build_scene(desc);
    return records;
}

RenderResult render(const Scene& scene, const RenderOptions& opts) {
    if (opts.spp == 0) throw Error("spp: value 0 must be >= 1");
    if (opts.spp < -1) throw Error("spp: value " + std::to_string(opts.spp) + " must be >= 1");
    if (opts.threads < 0) throw Error("threads: value " + std::to_string(opts.threads) + " must be >= 0");
    if (opts.time_budget < 0.0) throw Error("time_budget: must be >= 0");
    if (opts.target_rel_error < 0.0) throw Error("target_rel_error: must be >= 0");
    return make_integrator(scene)->render(scene, opts);
}

RenderResult render_aov(const Scene& scene, const std::string& aov, const RenderOptions& opts) {
    AovIntegrator integrator(AovIntegrator::parse(aov));
    if (opts.spp < -1 || opts.spp == 0) throw Error("spp: value " + std::to_string(opts.spp) + " must be >= 1");
    if (opts.threads < 0) throw Error("threads: value " + std::to_string(opts.threads) + " must be >= 0");
    return integrator.render(scene, opts);
}

void write_image(const std::string& path, const Image& img) { pellucid::write_image_file(path, img); }
Image read_image(const std::string& path) { return pellucid::read_image_file(path); }
const char* version() { return PELLUCID_VERSION; }
}  // namespace pellucid
