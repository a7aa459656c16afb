// Builders of every material type from a scene-description object (Properties), used by the
// explicit table in scene/registry.cpp, and a helper that builds one material from a bare node
// (the Python `pellucid.bsdf(dict)` testing surface).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <string>

#include "pellucid/material/material.h"

namespace pellucid {

class Properties;
class Node;
struct BuildContext;

Material build_lambertian(Properties& p, const BuildContext& ctx);
Material build_oren_nayar(Properties& p, const BuildContext& ctx);
Material build_conductor(Properties& p, const BuildContext& ctx);
Material build_rough_conductor(Properties& p, const BuildContext& ctx);
Material build_dielectric(Properties& p, const BuildContext& ctx);
Material build_rough_dielectric(Properties& p, const BuildContext& ctx);
Material build_thin_dielectric(Properties& p, const BuildContext& ctx);
Material build_plastic(Properties& p, const BuildContext& ctx);
Material build_rough_plastic(Properties& p, const BuildContext& ctx);
Material build_principled(Properties& p, const BuildContext& ctx);
Material build_subsurface(Properties& p, const BuildContext& ctx);

/// Build one material object (`{"type": ..., params}`) through the registry, with the same checks
/// as a scene's `materials` entry (unknown type or key → Error "source: path.key: ...").
Material build_material(const Node& node, const std::string& source, const std::string& path);
/// The same, resolving files against ctx.base_dir (used by scene building).
Material build_material(const Node& node, const BuildContext& ctx, const std::string& path);
}  // namespace pellucid
