// Images cross the boundary as buffers: numpy arrays that view C++ memory, no copies.
// SPDX-License-Identifier: Apache-2.0
#include "bind.h"
#include "pellucid/api.h"
#include "pellucid/util/error.h"

namespace pellucid::bind {

py::array image_to_array(Image&& img) {
    auto* owner = new Image(std::move(img));
    py::capsule base(owner, [](void* p) { delete static_cast<Image*>(p); });
    std::vector<py::ssize_t> shape{owner->height, owner->width, owner->channels};
    return py::array_t<float>(shape, owner->data.data(), base);
}

std::string shape_text(const py::array& a) {
    std::string s = "(";
    for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
    return s + (a.ndim() == 1 ? ",)" : ")");
}

Image array_to_image(const py::array_t<float, py::array::c_style | py::array::forcecast>& a) {
    const py::ssize_t c = a.ndim() == 3 ? a.shape(2) : 1;
    if ((a.ndim() != 3 && a.ndim() != 2) || (c != 1 && c != 3 && c != 4))
        throw Error("image array: expected shape (H, W), (H, W, 1), (H, W, 3) or (H, W, 4), got " + shape_text(a));
    int h = int(a.shape(0)), w = int(a.shape(1));
    Image img(w, h, c);
    std::copy(a.data(), a.data() + img.data.size(), img.data.begin());
    return img;
}

void bind_image(py::module_& m) {
    m.def("write_image", [](const std::string& path, const py::array_t<float, py::array::c_style | py::array::forcecast>& a) {
        Image img;
        try {
            img = array_to_image(a);
        } catch (const Error& e) {
            throw Error(path + ": " + e.what());
        }
        write_image(path, img);
    }, py::arg("path"), py::arg("array"), "Write an (H, W, 3) float array (.exr linear, .png sRGB).");
    m.def("read_image", [](const std::string& path) { return image_to_array(read_image(path)); },
          py::arg("path"), "Read an image as a linear float32 (H, W, 3) array.");
}
}  // namespace pellucid::bind
