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

Image array_to_image(const py::array_t<float, py::array::c_style | py::array::forcecast>& a) {
    if (a.ndim() != 3 && a.ndim() != 2) throw Error("image array must have shape (H, W, 3) or (H, W)");
    int h = int(a.shape(0)), w = int(a.shape(1)), c = a.ndim() == 3 ? int(a.shape(2)) : 1;
    if (c != 1 && c != 3 && c != 4) throw Error("image array must have 1, 3 or 4 channels, got " + std::to_string(c));
    Image img(w, h, c);
    std::copy(a.data(), a.data() + img.data.size(), img.data.begin());
    return img;
}

void bind_image(py::module_& m) {
    m.def("write_image", [](const std::string& path, const py::array_t<float, py::array::c_style | py::array::forcecast>& a) {
        write_image(path, array_to_image(a));
    }, py::arg("path"), py::arg("array"), "Write an (H, W, 3) float array (.exr linear, .png sRGB).");
    m.def("read_image", [](const std::string& path) { return image_to_array(read_image(path)); },
          py::arg("path"), "Read an image as a linear float32 (H, W, 3) array.");
}
}  // namespace pellucid::bind
