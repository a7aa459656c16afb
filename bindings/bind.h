// Registration functions of the binding files, called in dependency order by module.cpp.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "pellucid/image/image.h"
#include "pellucid/scene/scene_desc.h"

namespace py = pybind11;

namespace pellucid::bind {
void bind_util(py::module_& m);
void bind_image(py::module_& m);
void bind_bxdf(py::module_& m);
void bind_bssrdf(py::module_& m);
void bind_scene(py::module_& m);
void bind_render(py::module_& m);

/// Move an image into a numpy array of shape (H, W, C) that views its memory (no copy).
py::array image_to_array(Image&& img);
/// A numpy array's shape as Python prints it: "(4, 3)", "(5,)", "()".
std::string shape_text(const py::array& a);
/// Copy a (H, W, 3) / (H, W) float array into an Image.
Image array_to_image(const py::array_t<float, py::array::c_style | py::array::forcecast>& a);
/// Python object (dict, list, number, str, bool, None) -> SceneDesc node. Errors carry the key path.
/// A Python dict/list/number/string as a scene Node; depth counts the containers above obj.
Node to_node(const py::handle& obj, const std::string& path, int depth = 0);
}  // namespace pellucid::bind
