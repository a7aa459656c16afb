// The Mitsuba 3 plugins and parameters that the XML importer (scene/mitsuba_xml.cpp) accepts, and
// what each becomes in our scene tree. The importer converts by this table, so it is the list of
// what is imported; tests read it (pellucid._core.mitsuba_import_table) to check that the parity
// matrix exercises every mapping (tests/python/test_parity_matrix.py).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <string>
#include <vector>

namespace pellucid {

/// How the importer carries a parameter over.
enum class MitsubaParamUse {
    copy,       ///< copied unchanged under `ours`
    converted,  ///< the plugin's conversion code computes `ours` from it (e.g. roughdiffuse alpha -> sigma)
    ignored,    ///< accepted and dropped (logged at info level); `ours` is "ignored"
};

struct MitsubaParam {
    const char* mitsuba;  ///< Mitsuba's parameter name (a property or a named nested texture)
    const char* ours;     ///< our key, or "ignored"
    MitsubaParamUse use = MitsubaParamUse::copy;
};

struct MitsubaPlugin {
    const char* kind;    ///< bsdf, texture, shape, emitter, sensor, film, rfilter, sampler, integrator,
                         ///< medium or phase
    const char* plugin;  ///< Mitsuba's plugin name
    const char* ours;    ///< our type; for bumpmap/normalmap the key added to the nested material, for
                         ///< twosided "" (it unwraps to its nested bsdf)
    std::vector<MitsubaParam> params;
};

/// Every accepted (kind, plugin), in a fixed order.
const std::vector<MitsubaPlugin>& mitsuba_import_table();

/// The entry for (kind, plugin), or nullptr when the importer does not accept it.
const MitsubaPlugin* find_mitsuba_plugin(const std::string& kind, const std::string& plugin);

/// The accepted plugin names of one kind, comma-separated (for "(known: ...)" in messages).
std::string mitsuba_known_plugins(const std::string& kind);
}  // namespace pellucid
