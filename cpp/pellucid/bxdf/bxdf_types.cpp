// BxDF flag printing.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/bxdf/bxdf_types.h"

namespace pellucid {
std::string to_string(BxDFFlags f) {
    if (f == BxDFFlags::None) return "none";
    std::string s;
    auto add = [&](BxDFFlags bit, const char* name) {
        if (has_flag(f, bit)) s += (s.empty() ? "" : "|") + std::string(name);
    };
    add(BxDFFlags::Reflection, "reflection");
    add(BxDFFlags::Transmission, "transmission");
    add(BxDFFlags::Diffuse, "diffuse");
    add(BxDFFlags::Glossy, "glossy");
    add(BxDFFlags::Specular, "specular");
    return s;
}
}  // namespace pellucid
