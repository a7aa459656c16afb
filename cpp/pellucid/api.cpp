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

SceneDesc load_desc_file(const std::string& path, bool lenient, const std::map<std::string, std::string>& params) {
    std::string ext = std::filesystem::path(path).extension().string();
    if (ext == ".json") {
        if (!params.empty())
            throw Error(path + ": parameter '" + params.begin()->first +
                        "': JSON scenes have no $parameters (only Mitsuba XML scenes do)");
        return read_json_file(path);
    }
    if (ext == ".xml") return read_mitsuba_xml_file(path, lenient, params);
    throw Error(path + ": unsupported scene format '" + ext + "' (expected .json or Mitsuba 3 .xml)");
}

std::shared_ptr<const Scene> load_file(const std::string& path, bool lenient,
                                       const std::map<std::string, std::string>& params) {
    return load_desc(load_desc_file(path, lenient, params));
}

std::shared_ptr<const Scene> load_desc(const SceneDesc& desc) { return build_scene(desc); }
std::shared_ptr<const Scene> load_desc(SceneDesc&& desc) { return build_scene(std::move(desc)); }

std::vector<ParameterRecord> record_parameters(const SceneDesc& desc) {
    std::vector<ParameterRecord> records;
    struct Stop {  // stop recording on every exit, errors included
        ~Stop() { set_parameter_recorder(nullptr); }
    } stop;
    set_parameter_recorder(&records);
    build_scene(desc);
    return records;
}

namespace {
/// The integrator's render, refusing a film state of another integrator and recording its own.
RenderResult render_recorded(const Integrator& integrator, const Scene& scene, const RenderOptions& opts) {
    const std::string name = integrator.to_string();
    if (opts.resume && !opts.resume->integrator.empty() && opts.resume->integrator != name)
        throw Error("resume: the film state was rendered by " + opts.resume->integrator + ", this scene renders with " +
                    name);
    RenderResult r = integrator.render(scene, opts);
    if (r.state) r.state->integrator = name;
    return r;
}
}  // namespace

RenderResult render(const Scene& scene, const RenderOptions& opts) {
    if (opts.spp == 0) throw Error("spp: value 0 must be >= 1");
    if (opts.spp < -1) throw Error("spp: value " + std::to_string(opts.spp) + " must be >= 1");
    if (opts.threads < 0) throw Error("threads: value " + std::to_string(opts.threads) + " must be >= 0");
    if (opts.time_budget < 0.0) throw Error("time_budget: must be >= 0");
    if (opts.target_rel_error < 0.0) throw Error("target_rel_error: must be >= 0");
    auto integrator = make_integrator(scene);
    return render_recorded(*integrator, scene, opts);
}

RenderResult render_aov(const Scene& scene, const std::string& aov, const RenderOptions& opts) {
    AovIntegrator integrator(AovIntegrator::parse(aov));
    if (opts.spp < -1 || opts.spp == 0) throw Error("spp: value " + std::to_string(opts.spp) + " must be >= 1");
    if (opts.threads < 0) throw Error("threads: value " + std::to_string(opts.threads) + " must be >= 0");
    return render_recorded(integrator, scene, opts);
}

std::vector<ImageAttribute> render_attributes(const RenderResult& r) {
    std::vector<ImageAttribute> a = {
        {"pellucid:spp", int64_t(r.stats.spp)},
        {"pellucid:invalid_samples", int64_t(r.stats.invalid_samples)},
        {"pellucid:interrupted", int64_t(r.stats.cancelled ? 1 : 0)},
        {"pellucid:seconds", r.stats.seconds},
        {"pellucid:version", std::string(PELLUCID_VERSION)},
    };
    if (r.state) {
        a.push_back({"pellucid:seed", std::to_string(r.state->seed)});
        a.push_back({"pellucid:sampler", r.state->sampler});
    }
    return a;
}

void write_image(const std::string& path, const Image& img, const std::vector<ImageAttribute>& attributes) {
    pellucid::write_image_file(path, img, attributes);
}
Image read_image(const std::string& path) { return pellucid::read_image_file(path); }
const char* version() { return PELLUCID_VERSION; }
}  // namespace pellucid
