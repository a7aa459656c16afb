// Tables of named conductor and dielectric IORs.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/bxdf/ior.h"

#include "pellucid/util/error.h"

namespace pellucid {
namespace {

struct NamedConductor {
    const char* name;
    ConductorIOR ior;
    const char* source;
};

// (η, k) at 650 / 550 / 450 nm, linearly interpolated between tabulated points.
// JC72 = P. B. Johnson, R. W. Christy, "Optical constants of the noble metals",
//        Phys. Rev. B 6, 4370 (1972).
// JC74 = P. B. Johnson, R. W. Christy, "Optical constants of transition metals: Ti, V, Cr, Mn, Fe,
//        Co, Ni, and Pd", Phys. Rev. B 9, 5056 (1974).
// R95  = A. D. Rakić, "Algorithm for the determination of intrinsic optical constants of metal
//        films: application to aluminum", Appl. Opt. 34, 4755 (1995).
// All three via the refractiveindex.info database (main/<metal>/{Johnson,Rakic}.yml, CC0).
const NamedConductor kConductors[] = {
    {"Au", {{0.1556f, 0.4241f, 1.383f}, {3.602f, 2.472f, 1.915f}}, "JC72"},
    {"Ag", {{0.05222f, 0.05958f, 0.04f}, {4.409f, 3.597f, 2.648f}}, "JC72"},
    {"Cu", {{0.2378f, 1.007f, 1.24f}, {3.626f, 2.582f, 2.393f}}, "JC72"},
    {"Al", {{1.558f, 1.015f, 0.6332f}, {7.712f, 6.627f, 5.454f}}, "R95"},
    {"Cr", {{3.107f, 3.181f, 2.323f}, {3.331f, 3.329f, 3.135f}}, "JC74"},
    {"Fe", {{2.911f, 2.95f, 2.584f}, {3.089f, 2.932f, 2.767f}}, "JC74"},
    {"Ti", {{2.741f, 2.542f, 2.267f}, {3.814f, 3.435f, 3.038f}}, "JC74"},
    {"Ni", {{1.99f, 1.921f, 1.729f}, {4.209f, 3.616f, 2.944f}}, "JC74"},
    {"none", {{0.f, 0.f, 0.f}, {1.f, 1.f, 1.f}}, "ideal mirror"},
};

struct NamedDielectric {
    const char* name;
    float eta;
};
// Real IORs near 589 nm (sodium D line). Sources: water 1.333 and diamond 2.419 (Hecht, "Optics",
// 5th ed., Table 4.1); BK7 1.5046 at 550 nm (Schott datasheet N-BK7, also the Mitsuba 0.6 table);
// fused silica 1.458 (Malitson 1965); acrylic/PMMA 1.49; polypropylene 1.49; sapphire 1.77;
// ethanol 1.361; air 1.000277 (Ciddor 1996).
const NamedDielectric kDielectrics[] = {
    {"vacuum", 1.0f},     {"air", 1.000277f},    {"water", 1.333f},       {"ethanol", 1.361f},
    {"glass", 1.5046f},   {"bk7", 1.5046f},      {"fused-quartz", 1.458f}, {"acrylic", 1.49f},
    {"polypropylene", 1.49f}, {"sapphire", 1.77f}, {"diamond", 2.419f},
};

template <class Table>
std::string known_list(const Table& t) {
    std::string s;
    for (const auto& e : t) s += (s.empty() ? "" : ", ") + std::string(e.name);
    return s;
}
}  // namespace

ConductorIOR conductor_ior(const std::string& name) {
    for (const auto& c : kConductors)
        if (name == c.name) return c.ior;
    throw Error("unknown metal '" + name + "'; known: " + known_list(kConductors));
}
std::vector<std::string> conductor_names() {
    std::vector<std::string> v;
    for (const auto& c : kConductors) v.emplace_back(c.name);
    return v;
}
float dielectric_ior(const std::string& name) {
    for (const auto& d : kDielectrics)
        if (name == d.name) return d.eta;
    throw Error("unknown dielectric '" + name + "'; known: " + known_list(kDielectrics));
}
std::vector<std::string> dielectric_names() {
    std::vector<std::string> v;
    for (const auto& d : kDielectrics) v.emplace_back(d.name);
    return v;
}
}  // namespace pellucid
