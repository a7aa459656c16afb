// Building media from the scene description (the top-level `media` object, shapes' `interior` /
// `exterior`, the camera's `medium`, the `null` material) and the checks on them.
// SPDX-License-Identifier: Apache-2.0
//
// Parameters (docs/media.md has the full description):
// | type          | parameter | type     | default     | meaning                                      |
// |---------------|-----------|----------|-------------|----------------------------------------------|
// | `homogeneous` | sigma_a   | spectrum | 0           | absorption coefficient, 1/scene unit         |
// |               | sigma_s   | spectrum | 0           | scattering coefficient, 1/scene unit         |
// |               | sigma_t   | spectrum | 1           | extinction, with albedo (not with sigma_a/s) |
// |               | albedo    | spectrum | 0.75        | σs/σt in [0, 1] (with sigma_t)               |
// | `grid`        | sigma_t   | spectrum | 1           | extinction at density 1                      |
// |               | albedo    | spectrum | 0.75        | σs/σt in [0, 1]                              |
// |               | density   | object   | —           | {"type": "vol", "filename": ...},            |
// |               |           |          |             | {"type": "smoke", "resolution": 64, "seed": 1} |
// |               |           |          |             | or {"type": "constant", "value": 1, "resolution": 16} |
// |               | to_world  | transform| identity    | places the grid's unit cube [0, 1]³          |
// |               | tracking  | string   | "ratio"     | shadow rays: "ratio" or "delta"              |
// | both          | scale     | float    | 1           | multiplies σa, σs, σt                        |
// |               | phase     | object   | isotropic   | {"type": "hg", "g": 0.7} or {"type": "isotropic"} |
// |               | emission  | spectrum | 0           | Le: source term σt·Le                        |
// JSON: "media": {"fog": {"type": "homogeneous", "sigma_t": 0.5, "albedo": 0.9, "phase": {"type": "hg", "g": 0.7}}}
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "pellucid/geometry/mesh.h"
#include "pellucid/medium/medium.h"
#include "pellucid/scene/properties.h"

namespace pellucid {

struct BuildContext;

/// Every medium type, for "known:" lists and the registry.
const std::vector<std::string>& medium_types();

/// A phase function object ({"type": "hg", "g": 0.7}); `path` is its key path.
PhaseFunction build_phase(const Node& n, const std::string& source, const std::string& path);
/// One medium of the `media` object (p at path "media.<name>").
Medium build_medium(Properties& p, const BuildContext& ctx, const std::string& name);
/// The `media` object: appends each named medium to `out` (names via name_of). Errors name the key.
void build_media(const Node& n, const BuildContext& ctx, std::vector<Medium>& out);

/// The medium named by `key` of p (a string), as an index into media; -1 when the key is absent.
/// An unknown name is an error with a did-you-mean hint.
int32_t resolve_medium(Properties& p, const std::string& key, const std::vector<Medium>& media);

/// Is this material node the `null` material ({"type": "null"}): an index-matched boundary that
/// only bounds media (the path goes through it unchanged)?
bool is_null_material(const Node& n);

/// Edges of the mesh not shared by exactly two triangles, with vertices welded by position: 0 for
/// a closed, edge-manifold surface. A medium bounded by a mesh with such edges leaks.
size_t open_edge_count(const TriangleMesh& mesh);
}  // namespace pellucid
