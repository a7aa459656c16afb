// BSDFProbe: one material built from a description node, evaluated at a default hit — the object
// behind the Python testing surface `pellucid.bsdf(dict)` (bindings/bind_bxdf.cpp) and the charts.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <string>

#include "pellucid/bxdf/batch.h"
#include "pellucid/material/material.h"

namespace pellucid {

class Node;

struct BSDFProbe {
    Material material;
    BxDF bxdf;        ///< make_bxdf of its constants (local frame = world frame)
    BxDFContext ctx;  ///< transport mode; all lobes allowed

    /// `node` is one material object (`{"type": "rough_conductor", ...}`); mode is "radiance" or
    /// "importance". Errors are pellucid::Error "<source>: key: message".
    static BSDFProbe from_desc(const Node& node, const std::string& mode = "radiance",
                               const std::string& source = "<dict>");
    std::string to_string() const;
};
}  // namespace pellucid
