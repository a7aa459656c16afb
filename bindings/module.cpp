// PYBIND11_MODULE(_core): registers the binding files in dependency order.
// SPDX-License-Identifier: Apache-2.0
#include "bind.h"

PYBIND11_MODULE(_core, m) {
    m.doc() = "pellucid's compiled core (use the `pellucid` package, not this module)";
    pellucid::bind::bind_util(m);
    pellucid::bind::bind_image(m);
    pellucid::bind::bind_bxdf(m);
    pellucid::bind::bind_bssrdf(m);
    pellucid::bind::bind_scene(m);
    pellucid::bind::bind_render(m);
}
