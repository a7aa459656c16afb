// render(): releases the GIL, returns zero-copy numpy arrays, stops on Python signals (Ctrl-C).
// SPDX-License-Identifier: Apache-2.0
#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>

#include <pybind11/stl.h>

#include "bind.h"
#include "pellucid/api.h"
#include "pellucid/integrator/aov.h"
#include "pellucid/util/error.h"

namespace pellucid::bind {
namespace {
std::atomic<bool> g_cancel{false};

/// Run `fn` (a render) on a worker thread while the calling thread, without the GIL, wakes every
/// 50 ms to run Python's signal handlers (PyErr_CheckSignals; it does so only on the main thread).
/// A handler that raises (KeyboardInterrupt for Ctrl-C, or a SIGTERM handler) cancels the render,
/// which returns its complete passes; the exception is kept in `pending` for the caller to raise.
RenderResult run_interruptible(RenderOptions& o, const std::function<RenderResult(const RenderOptions&)>& fn,
                               py::object& pending) {
    g_cancel = false;
    o.cancel = &g_cancel;
    RenderResult r;
    std::exception_ptr err;
    std::mutex m;
    std::condition_variable cv;
    bool done = false;
    {
        py::gil_scoped_release nogil;
        std::thread worker([&] {
            try {
                r = fn(o);
            } catch (...) {
                err = std::current_exception();
            }
            std::lock_guard<std::mutex> lock(m);
            done = true;
            cv.notify_all();
        });
        std::unique_lock<std::mutex> lock(m);
        while (!done) {
            cv.wait_for(lock, std::chrono::milliseconds(50));
            if (done || pending) continue;
            lock.unlock();
            {
                py::gil_scoped_acquire gil;
                if (PyErr_CheckSignals() != 0) {
                    py::error_already_set e;
                    pending = e.value();
                    g_cancel = true;
                }
            }
            lock.lock();
        }
        lock.unlock();
        worker.join();
    }
    if (err) std::rethrow_exception(err);
    return r;
}

py::dict stats_dict(const RenderResult& r) {
    py::dict stats;
    stats["spp"] = r.stats.spp;
    stats["seconds"] = r.stats.seconds;
    stats["samples"] = r.stats.samples;
    stats["invalid_samples"] = r.stats.invalid_samples;
    stats["cancelled"] = r.stats.cancelled;
    if (r.state) {
        stats["seed"] = r.state->seed;
        stats["sampler"] = r.state->sampler;
    }
    return stats;
}

/// Raise `pending` with the partial result attached as its `partial` attribute.
[[noreturn]] void raise_with_partial(const py::object& pending, const py::object& partial) {
    try {
        pending.attr("partial") = partial;
    } catch (const py::error_already_set&) {
        // An exception type without a __dict__: raised without the partial result.
    }
    PyErr_SetObject(reinterpret_cast<PyObject*>(Py_TYPE(pending.ptr())), pending.ptr());
    throw py::error_already_set();
}

/// "a, b, c" -> {"a", "b", "c"}.
std::vector<std::string> split_names(const std::string& list) {
    std::vector<std::string> out;
    size_t start = 0;
    while (start < list.size()) {
        size_t end = list.find(", ", start);
        if (end == std::string::npos) end = list.size();
        out.push_back(list.substr(start, end - start));
        start = end + 2;
    }
    return out;
}

std::shared_ptr<const FilmState> as_state(const py::object& resume) {
    if (resume.is_none()) return nullptr;
    if (py::isinstance<FilmState>(resume)) return resume.cast<std::shared_ptr<FilmState>>();
    if (py::isinstance<py::str>(resume) || py::hasattr(resume, "__fspath__"))
        return load_film_state(py::str(py::module_::import("os").attr("fspath")(resume)).cast<std::string>());
    throw Error("resume: expected a FilmState or the path of a film state file, got " +
                std::string(py::str(py::type::of(resume).attr("__name__"))));
}

ImageAttribute to_attribute(const std::string& name, const py::handle& v) {
    if (py::isinstance<py::bool_>(v)) return {name, int64_t(v.cast<bool>() ? 1 : 0)};
    if (py::isinstance<py::int_>(v)) {
        try {
            return {name, v.cast<int64_t>()};
        } catch (const py::cast_error&) {
            return {name, std::string(py::str(v))};
        }
    }
    if (py::isinstance<py::float_>(v)) return {name, v.cast<double>()};
    return {name, std::string(py::str(v))};
}
}  // namespace

void bind_render(py::module_& m) {
    py::class_<RenderProgress>(m, "RenderProgress", "Progress of a running render, polled from another thread.")
        .def(py::init<>())
        .def_property_readonly("samples", [](const RenderProgress& p) { return p.samples.load(); })
        .def_property_readonly("fraction", [](const RenderProgress& p) { return p.fraction.load(); })
        .def("__repr__", [](const RenderProgress& p) {
            return "RenderProgress(samples=" + std::to_string(p.samples.load()) +
                   ", fraction=" + std::to_string(p.fraction.load()) + ")";
        });
    py::class_<FilmState, std::shared_ptr<FilmState>>(
        m, "FilmState",
        "The film of a render after `spp` complete passes, with its seed and sampler: pass it as "
        "render(..., resume=state) to continue to more samples, or save() it for --resume.")
        .def_property_readonly("spp", [](const FilmState& s) { return s.spp; })
        .def_property_readonly("width", [](const FilmState& s) { return s.film.width(); })
        .def_property_readonly("height", [](const FilmState& s) { return s.film.height(); })
        .def_property_readonly("seed", [](const FilmState& s) { return s.seed; })
        .def_property_readonly("sampler", [](const FilmState& s) { return s.sampler; })
        .def_property_readonly("integrator", [](const FilmState& s) { return s.integrator; })
        .def_property_readonly("invalid_samples", [](const FilmState& s) { return s.invalid_samples; })
        .def_property_readonly("seconds", [](const FilmState& s) { return s.seconds; })
        .def("save", [](const FilmState& s, const std::string& path) { save_film_state(path, s); }, py::arg("path"),
             py::call_guard<py::gil_scoped_release>(), "Write the film state file (docs/rendering.md).")
        .def("__repr__", [](const FilmState& s) {
            return "FilmState(" + std::to_string(s.film.width()) + "x" + std::to_string(s.film.height()) +
                   ", spp=" + std::to_string(s.spp) + ", seed=" + std::to_string(s.seed) + ", sampler='" + s.sampler +
                   "')";
        });
    m.def("load_film_state", &load_film_state, py::arg("path"), py::call_guard<py::gil_scoped_release>(),
          "Read a film state file written by FilmState.save or pellucid-render --state.");
    m.def("render_full", [](const Scene& scene, int spp, int64_t seed, int threads, double time_budget,
                            double target_rel_error, bool progress, RenderProgress* monitor,
                            const std::string& sampler, const py::object& resume, bool keep_state,
                            const std::string& aov, const std::vector<std::string>& aovs, bool variance) {
        RenderOptions o;
        o.variance = variance;
        o.spp = spp, o.seed = seed, o.threads = threads, o.time_budget = time_budget;
        o.target_rel_error = target_rel_error, o.progress = progress, o.progress_out = monitor, o.sampler = sampler;
        o.resume = as_state(resume);
        std::vector<Aov> aov_list;
        for (const std::string& name : aovs) {
            const Aov a = parse_aov(name);
            if (std::find(aov_list.begin(), aov_list.end(), a) == aov_list.end()) aov_list.push_back(a);
        }
        py::object pending;
        std::vector<ImageLayer> layers;
        double aov_seconds = 0.0;
        RenderResult r = run_interruptible(o, [&](const RenderOptions& opts) {
            RenderResult b = aov.empty() ? render(scene, opts) : render_aov(scene, aov, opts);
            // The AOV pass after a complete beauty render (a cancelled render keeps only the beauty).
            if (!aov_list.empty() && !b.stats.cancelled && b.stats.spp > 0)
                layers = render_aovs(scene, aov_list, b, opts, nullptr, &aov_seconds);
            return b;
        }, pending);
        py::dict stats = stats_dict(r);
        if (keep_state || pending) stats["state"] = std::move(r.state);
        if (!layers.empty()) {
            py::dict named;
            for (ImageLayer& l : layers) named[py::str(l.name)] = image_to_array(std::move(l.image));
            stats["aovs"] = named;
            stats["aov_seconds"] = aov_seconds;
            if (std::count(aov_list.begin(), aov_list.end(), Aov::ShapeId)) {
                py::list names;
                for (const ShapeRecord& s : scene.shapes) names.append(s.name);
                stats["shape_names"] = names;
            }
            if (std::count(aov_list.begin(), aov_list.end(), Aov::MaterialId))
                stats["material_names"] = py::cast(scene.material_names);
        }
        // No variance (the film kept none): None.
        py::object var = r.variance.data.empty() ? py::object(py::none()) : py::object(image_to_array(std::move(r.variance)));
        py::tuple out = py::make_tuple(image_to_array(std::move(r.image)), var, stats);
        if (pending) raise_with_partial(pending, out);
        return out;
    }, py::arg("scene"), py::arg("spp") = -1, py::arg("seed") = -1, py::arg("threads") = 0,
       py::arg("time_budget") = 0.0, py::arg("target_rel_error") = 0.0, py::arg("progress") = false,
       py::arg("monitor") = py::none(), py::arg("sampler") = "", py::arg("resume") = py::none(),
       py::arg("keep_state") = false, py::arg("aov") = "", py::arg("aovs") = std::vector<std::string>{},
       py::arg("variance") = true,
       "Render; returns (image, variance, stats) (variance None when variance is off and the film kept none), "
       "stats['state'] the FilmState if keep_state, stats['aovs'] "
       "{name: array} of the requested AOVs (integrator/aov.h) with stats['aov_seconds']. A Python signal "
       "handler that raises (Ctrl-C) stops it: the exception is raised with .partial = that tuple. Use "
       "pellucid.render for the documented API.");
    m.def("aov_names", [] {
        std::vector<std::string> names;
        for (const std::string& n : split_names(known_aovs())) names.push_back(n);
        return names;
    }, "Every AOV name render_full(aovs=...) accepts.");
    m.def("aov_channels", [](const std::string& name) { return aov_channels(parse_aov(name)); }, py::arg("name"),
          "The channel names of an AOV's layer in a multi-layer EXR (['R', 'G', 'B'], ['Z'], ...).");
    m.def("render_aov", [](const Scene& scene, const std::string& aov, int spp, int64_t seed, int threads,
                           const std::string& sampler) {
        RenderOptions o;
        o.spp = spp, o.seed = seed, o.threads = threads, o.sampler = sampler;
        py::object pending;
        RenderResult r = run_interruptible(o, [&](const RenderOptions& opts) { return render_aov(scene, aov, opts); },
                                           pending);
        py::dict stats = stats_dict(r);
        std::pair<py::array, py::array> out{image_to_array(std::move(r.image)), image_to_array(std::move(r.variance))};
        if (pending) {
            stats["state"] = std::move(r.state);
            raise_with_partial(pending, py::make_tuple(out.first, out.second, stats));
        }
        return out;
    }, py::arg("scene"), py::arg("aov"), py::arg("spp") = -1, py::arg("seed") = -1, py::arg("threads") = 0,
       py::arg("sampler") = "",
       "Render one AOV; returns (image, variance). Use pellucid.aov.render_aov for the documented API.");
    m.def("cancel", [] { g_cancel = true; }, "Ask the running render to stop (it returns its complete passes).");
    m.def("write_image_with_attributes", [](const std::string& path, const py::array_t<float, py::array::c_style | py::array::forcecast>& a,
                                            const py::dict& attributes) {
        std::vector<ImageAttribute> attrs;
        for (auto item : attributes) attrs.push_back(to_attribute(py::str(item.first), item.second));
        Image img = array_to_image(a);
        py::gil_scoped_release nogil;
        write_image(path, img, attrs);
    }, py::arg("path"), py::arg("array"), py::arg("attributes"),
       "write_image with header attributes (EXR attributes; formats without a header drop them).");
    m.def("check_image_output", &check_image_output, py::arg("path"),
          "Check an output image path before rendering: a writable format, missing folders created.");
    m.def("read_image_attributes", [](const std::string& path) {
        py::dict out;
        for (const ImageAttribute& a : read_image_attributes(path))
            std::visit([&](const auto& v) { out[py::str(a.name)] = v; }, a.value);
        return out;
    }, py::arg("path"), "The header attributes of an image file as a dict.");
}
}  // namespace pellucid::bind
