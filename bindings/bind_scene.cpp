// Scene loading from files and dicts (dicts become the same SceneDesc IR as JSON files).
// SPDX-License-Identifier: Apache-2.0
#include <cmath>

#include <pybind11/stl.h>

#include "bind.h"
#include "pellucid/api.h"
#include "pellucid/scene/mitsuba_table.h"
#include "pellucid/scene/registry.h"
#include "pellucid/scene/scene_update.h"
#include "pellucid/util/error.h"
#include "pellucid/util/limits.h"

namespace pellucid::bind {

namespace {
std::string where(const std::string& path) { return "<dict>: " + (path.empty() ? std::string("<root>") : path); }
/// UTF-8 of a str; a pellucid.Error (not a cast error) for text with lone surrogates.
std::string utf8_of(const py::handle& s, const std::string& path) {
    Py_ssize_t n = 0;
    const char* u = PyUnicode_AsUTF8AndSize(s.ptr(), &n);
    if (!u) {
        PyErr_Clear();
        throw Error(where(path) + ": the text cannot be encoded as UTF-8 (it holds a lone surrogate)");
    }
    return std::string(u, size_t(n));
}
}  // namespace

Node to_node(const py::handle& obj, const std::string& path, int depth) {
    if (depth > max_scene_depth())
        throw Error("<dict>: " + (path.empty() ? std::string("<root>") : path) + ": dicts and lists nested deeper than " +
                    std::to_string(max_scene_depth()) +
                    " levels (the scene depth limit; a container that holds itself? Raise it with "
                    "PELLUCID_MAX_SCENE_DEPTH)");
    if (obj.is_none()) return Node();
    if (py::isinstance<py::bool_>(obj)) return Node::boolean(obj.cast<bool>());
    if (py::isinstance<py::int_>(obj)) {
        const double v = PyLong_AsDouble(obj.ptr());
        if (v == -1.0 && PyErr_Occurred()) {
            PyErr_Clear();
            std::string digits = py::str(obj);
            if (digits.size() > 24) digits = digits.substr(0, 12) + "...(" + std::to_string(digits.size()) + " digits)";
            throw Error(where(path) + ": value " + digits + " overflows a double");
        }
        return Node::number(v, true);
    }
    if (py::isinstance<py::float_>(obj)) return Node::number(obj.cast<double>(), false);
    if (py::isinstance<py::str>(obj)) return Node::string(utf8_of(obj, path));
    if (py::isinstance<py::dict>(obj)) {
        Node o = Node::object();
        for (auto item : obj.cast<py::dict>()) {
            if (!py::isinstance<py::str>(item.first))
                throw Error("<dict>: " + (path.empty() ? std::string("<root>") : path) + ": keys must be strings");
            std::string key = utf8_of(item.first, path);
            o.set(key, to_node(item.second, path_join(path, key), depth + 1));
        }
        return o;
    }
    if (py::isinstance<py::array>(obj)) return to_node(obj.attr("tolist")(), path, depth);
    if (py::isinstance<py::list>(obj) || py::isinstance<py::tuple>(obj)) {
        Node a = Node::array();
        size_t i = 0;
        for (auto item : obj) a.push_back(to_node(item, path_index(path, i++), depth + 1));
        return a;
    }
    if (py::hasattr(obj, "__float__")) return Node::number(obj.cast<double>(), false);
    throw Error("<dict>: " + path + ": unsupported value of type " + std::string(py::str(obj.get_type().attr("__name__"))));
}

namespace {
/// A description value as the dict that describes it holds it (numbers stay int or float).
py::object from_node(const Node& n) {
    switch (n.kind()) {
        case Node::Kind::Null: return py::none();
        case Node::Kind::Bool: return py::bool_(n.as_bool());
        case Node::Kind::Number:
            if (n.is_integer()) return py::int_(int64_t(n.as_number()));
            return py::float_(n.as_number());
        case Node::Kind::String: return py::str(n.as_string());
        case Node::Kind::Array: {
            py::list l;
            for (const Node& v : n.items()) l.append(from_node(v));
            return l;
        }
        case Node::Kind::Object: {
            py::dict d;
            for (const auto& [k, v] : n.members()) d[py::str(k)] = from_node(v);
            return d;
        }
    }
    return py::none();
}
}  // namespace

void bind_scene(py::module_& m) {
    py::class_<Scene, std::shared_ptr<Scene>>(m, "Scene", "A built scene. Rendering reads it; pellucid.parameters(scene).update() changes it in place.")
        .def_property_readonly("width", [](const Scene& s) { return s.width; })
        .def_property_readonly("height", [](const Scene& s) { return s.height; })
        .def_property_readonly("spp", [](const Scene& s) { return s.spp; })
        .def_property_readonly("source", [](const Scene& s) { return s.source; })
        .def_property_readonly("updates", [](const Scene& s) { return s.updates; },
                               "Parameter updates applied (pellucid.parameters).")
        .def_property_readonly("bvh_builds", [](const Scene& s) { return s.bvh_builds; },
                               "Times the BVH was built: 1 when loaded, +1 per parameter update that moved geometry.")
        .def_property_readonly(
            "subsurface_choices",
            [](const Scene& s) {
                py::list out;
                for (const SubsurfaceChoice& c : s.subsurface_choices)
                    out.append(py::dict(py::arg("shape") = s.shapes[c.shape].name, py::arg("model") = to_string(c.model),
                                        py::arg("reason") = c.reason, py::arg("thickness") = c.thickness,
                                        py::arg("diffusion_length") = c.diffusion_length,
                                        py::arg("mean_free_path") = c.mean_free_path, py::arg("footprint") = c.footprint,
                                        py::arg("min_albedo") = c.min_albedo));
                return out;
            },
            "Per object of a subsurface material: the model that renders it and why (docs/subsurface.md).")
        .def("__repr__", &Scene::to_string);
    m.def("load_file", [](const std::string& path, bool lenient, const std::map<std::string, std::string>& params) {
        return std::const_pointer_cast<Scene>(load_file(path, lenient, params));
    }, py::arg("path"), py::arg("lenient") = false, py::arg("params") = std::map<std::string, std::string>{},
       py::call_guard<py::gil_scoped_release>(),
       "Load and build a scene file (.json or Mitsuba 3 .xml; lenient: unsupported XML elements warn; params: "
       "Mitsuba $name values).");
    m.def("mitsuba_import_table", [] {
        std::vector<std::map<std::string, py::object>> out;
        for (const MitsubaPlugin& p : mitsuba_import_table()) {
            py::list params;
            for (const MitsubaParam& q : p.params) params.append(py::make_tuple(q.mitsuba, q.ours));
            out.push_back({{"kind", py::str(p.kind)}, {"plugin", py::str(p.plugin)}, {"type", py::str(p.ours)},
                           {"params", params}});
        }
        return out;
    }, "The Mitsuba XML importer's mappings: [{kind, plugin, type, params: [(mitsuba, ours or 'ignored')]}].");
    m.def("registry_types", &registry_types, "Registered type names per family (materials, shapes, ...).");
    m.def("record_parameters", [](const py::dict& d, const std::string& base_dir) {
        std::vector<py::tuple> out;
        for (auto& r : record_parameters(SceneDesc{to_node(d, ""), "<dict>", base_dir}))
            out.push_back(py::make_tuple(r.path, r.type, r.keys));
        return out;
    }, py::arg("d"), py::arg("base_dir") = ".", "Build d; return (path, type, keys looked up) per object.");
    m.def("scene_parameters", [](const Scene& s) {
        if (!s.desc) throw Error(s.source + ": the scene keeps no description");
        py::dict out;
        for (const SceneParameter& p : scene_parameters(*s.desc)) out[py::str(p.path)] = from_node(*p.value);
        return out;
    }, py::arg("scene"), "Every parameter of the scene's description: key path -> value (pellucid.parameters).");
    m.def("check_parameter_path", [](const Scene& s, const std::string& path, bool allow_new) {
        if (!s.desc) throw Error(s.source + ": the scene keeps no description");
        check_parameter_path(*s.desc, path, allow_new);
    }, py::arg("scene"), py::arg("path"), py::arg("allow_new") = true,
       "Raise pellucid.Error unless path names a parameter of the scene (allow_new: or a key it may add).");
    m.def("update_scene", [](Scene& s, const py::dict& edits) {
        std::vector<std::pair<std::string, Node>> e;
        for (auto item : edits) {
            const std::string path = py::str(item.first);
            e.emplace_back(path, to_node(item.second, path, 1));
        }
        UpdateReport r;
        {
            py::gil_scoped_release nogil;
            r = update_scene(s, e);
        }
        py::dict out;
        out["geometry"] = r.geometry;
        out["full"] = r.full;
        out["shapes_rebuilt"] = r.shapes_rebuilt;
        out["seconds"] = r.seconds;
        return out;
    }, py::arg("scene"), py::arg("edits"),
       "Set key path -> value in the scene's description and rebuild what depends on them, in place; returns "
       "{geometry, full, shapes_rebuilt, seconds}. On error the scene is unchanged.");
    m.def("load_dict", [](const py::dict& d, const std::string& base_dir) {
        SceneDesc desc{to_node(d, ""), "<dict>", base_dir};
        py::gil_scoped_release nogil;
        return std::const_pointer_cast<Scene>(load_desc(std::move(desc)));
    }, py::arg("d"), py::arg("base_dir") = ".", "Build a scene from a dict with the JSON format's structure.");
}
}  // namespace pellucid::bind
