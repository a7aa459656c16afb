// Images cross the boundary as buffers: numpy arrays that view C++ memory, no copies.
// SPDX-License-Identifier: Apache-2.0
#include <pybind11/stl.h>

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
    if ((a.ndim() != 3 && a.ndim() != 2) || c < 1 || a.shape(0) < 1 || a.shape(1) < 1)
        throw Error("image array: expected shape (H, W) or (H, W, C) with H, W, C >= 1, got " + shape_text(a));
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
    }, py::arg("path"), py::arg("array"),
       "Write an (H, W) or (H, W, C) float array (.exr linear, any C; .png sRGB, C from 1 to 4).");
    m.def("read_image", [](const std::string& path) {
        Image img;
        {
            py::gil_scoped_release nogil;
            img = read_image_channels(path);
        }
        return image_to_array(std::move(img));
    }, py::arg("path"),
          "Read every channel of an image as a linear float32 (H, W, C) array.");
    m.def("write_layers", [](const std::string& path, const py::list& layers, const py::dict& attributes) {
        // layers: [(name, [channel names], array)], the unnamed layer's name "".
        std::vector<ImageLayer> ls;
        for (const py::handle& item : layers) {
            auto t = item.cast<py::tuple>();
            ImageLayer l;
            l.name = t[0].cast<std::string>();
            l.channels = t[1].cast<std::vector<std::string>>();
            try {
                l.image = array_to_image(t[2].cast<py::array_t<float, py::array::c_style | py::array::forcecast>>());
            } catch (const Error& e) {
                throw Error(path + ": layer '" + l.name + "': " + e.what());
            }
            ls.push_back(std::move(l));
        }
        std::vector<ImageAttribute> attrs;
        for (auto a : attributes) {
            const py::handle v = a.second;
            const std::string name = py::str(a.first);
            if (py::isinstance<py::bool_>(v)) attrs.push_back({name, int64_t(v.cast<bool>() ? 1 : 0)});
            else if (py::isinstance<py::int_>(v)) attrs.push_back({name, v.cast<int64_t>()});
            else if (py::isinstance<py::float_>(v)) attrs.push_back({name, v.cast<double>()});
            else attrs.push_back({name, std::string(py::str(v))});
        }
        py::gil_scoped_release nogil;
        write_layers_file(path, ls, attrs);
    }, py::arg("path"), py::arg("layers"), py::arg("attributes"),
       "Write [(name, channel names, array)] as one multi-layer EXR. Use pellucid.write_layers.");
    m.def("read_layers", [](const std::string& path) {
        std::vector<ImageLayer> ls;
        {
            py::gil_scoped_release nogil;
            ls = read_layers_file(path);
        }
        py::list out;
        for (ImageLayer& l : ls) out.append(py::make_tuple(l.name, l.channels, image_to_array(std::move(l.image))));
        return out;
    }, py::arg("path"), "An image file's layers as [(name, channel names, array)]. Use pellucid.read_layers.");
}
}  // namespace pellucid::bind
