// BSDFProbe construction (see bsdf_probe.h).
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/material/bsdf_probe.h"

#include "pellucid/material/builders.h"
#include "pellucid/scene/scene_desc.h"
#include "pellucid/util/error.h"

namespace pellucid {
namespace {
BxDFContext context_for(const std::string& mode) {
    BxDFContext c;
    if (mode == "radiance") c.mode = TransportMode::Radiance;
    else if (mode == "importance") c.mode = TransportMode::Importance;
    else throw Error("mode: unknown transport mode '" + mode + "' (known: radiance, importance)");
    return c;
}
}  // namespace

BSDFProbe BSDFProbe::from_desc(const Node& node, const std::string& mode, const std::string& source) {
    BxDFContext ctx = context_for(mode);
    Material m = build_material(node, source, "");
    BxDF b = make_bxdf(m);
    return BSDFProbe{std::move(m), std::move(b), ctx};
}

std::string BSDFProbe::to_string() const {
    return "bsdf(" + pellucid::to_string(material) + " -> " + pellucid::to_string(bxdf) +
           (ctx.mode == TransportMode::Importance ? ", mode=importance)" : ")");
}
}  // namespace pellucid
