// render(): releases the GIL, returns zero-copy numpy arrays.
// SPDX-License-Identifier: Apache-2.0
#include <atomic>

#include "bind.h"
#include "pellucid/api.h"

namespace pellucid::bind {
namespace {
std::atomic<bool> g_cancel{false};
}

void bind_render(py::module_& m) {
    py::class_<RenderProgress>(m, "RenderProgress", "Progress of a running render, polled from another thread.")
        .def(py::init<>())
        .def_property_readonly("samples", [](const RenderProgress& p) { return p.samples.load(); })
        .def_property_readonly("fraction", [](const RenderProgress& p) { return p.fraction.load(); })
        .def("__repr__", [](const RenderProgress& p) {
            return "RenderProgress(samples=" + std::to_string(p.samples.load()) +
                   ", fraction=" + std::to_string(p.fraction.load()) + ")";
        });
    m.def("render_full", [](const Scene& scene, int spp, int64_t seed, int threads, double time_budget,
                            double target_rel_error, bool progress, RenderProgress* monitor,
                            const std::string& sampler) {
        RenderOptions o{spp, seed, threads, time_budget, target_rel_error, progress, &g_cancel, monitor, sampler};
        g_cancel = false;
        RenderResult r;
        {
            py::gil_scoped_release nogil;
            r = render(scene, o);
        }
        py::dict stats;
        stats["spp"] = r.stats.spp;
        stats["seconds"] = r.stats.seconds;
        stats["samples"] = r.stats.samples;
        stats["invalid_samples"] = r.stats.invalid_samples;
        stats["cancelled"] = r.stats.cancelled;
        return py::make_tuple(image_to_array(std::move(r.image)), image_to_array(std::move(r.variance)), stats);
    }, py::arg("scene"), py::arg("spp") = -1, py::arg("seed") = -1, py::arg("threads") = 0,
       py::arg("time_budget") = 0.0, py::arg("target_rel_error") = 0.0, py::arg("progress") = false,
       py::arg("monitor") = py::none(), py::arg("sampler") = "",
       "Render; returns (image, variance, stats). Use pellucid.render for the documented API.");
    m.def("render_aov", [](const Scene& scene, const std::string& aov, int spp, int64_t seed, int threads,
                           const std::string& sampler) {
        RenderOptions o{spp, seed, threads, 0.0, 0.0, false, &g_cancel, nullptr, sampler};
        g_cancel = false;
        RenderResult r;
        {
            py::gil_scoped_release nogil;
            r = render_aov(scene, aov, o);
        }
        return py::make_tuple(image_to_array(std::move(r.image)), image_to_array(std::move(r.variance)));
    }, py::arg("scene"), py::arg("aov"), py::arg("spp") = -1, py::arg("seed") = -1, py::arg("threads") = 0,
       py::arg("sampler") = "",
       "Render one AOV; returns (image, variance). Use pellucid.aov.render_aov for the documented API.");
    m.def("cancel", [] { g_cancel = true; }, "Ask the running render to stop after its current tiles.");
}
}  // namespace pellucid::bind
