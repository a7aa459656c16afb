// pellucid::Error -> pellucid.Error; log sink -> a Python callable.
// SPDX-License-Identifier: Apache-2.0
#include "bind.h"
#include "pellucid/api.h"
#include "pellucid/util/error.h"
#include "pellucid/util/log.h"

#include <pybind11/functional.h>

namespace pellucid::bind {
void bind_util(py::module_& m) {
    py::register_exception<Error>(m, "Error", PyExc_RuntimeError);
    m.attr("__version__") = version();
    m.def("set_log_sink",
          [](py::object fn) {
              if (fn.is_none()) return set_log_sink(nullptr);
              set_log_sink([fn](LogLevel lvl, const std::string& msg) {
                  py::gil_scoped_acquire gil;
                  fn(int(lvl), msg);
              });
          },
          py::arg("fn"), "Route log messages to fn(level: int, message: str); None restores stderr.");
    // Drop the Python sink while the interpreter is still alive: destroyed later, among the C++
    // static destructors, its decref would run without the GIL and abort the process at exit.
    py::module_::import("atexit").attr("register")(py::cpp_function([] { set_log_sink(nullptr); }));
}
}  // namespace pellucid::bind
