// Named conductors: the generated RGB (η, k) table (tools/conductor_rgb.py) and its names.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <string>

#include "pellucid/bxdf/ior.h"
#include "pellucid/util/error.h"

namespace pellucid {
namespace {

// An independent replica of Mitsuba 3.9.1's reduction (its 5 nm CIE table and its rounded XYZ → sRGB
// matrix, printed to 4 decimals). Ours uses the CIE's 1 nm table and the matrix derived from the
// sRGB chromaticities; on these twelve numbers the two differ by at most 7e-4 (Au k_r), hence 1e-3.
// The 650/550/450 nm point samples used before differ from them by up to 0.38 (Au k_r).
struct Replica {
    const char* name;
    float eta[3], k[3];
};
constexpr Replica kReplica[] = {
    {"Au", {0.1431f, 0.3753f, 1.4420f}, {3.9831f, 2.3856f, 1.6034f}},
    {"Cu", {0.2010f, 0.9237f, 1.1022f}, {3.9133f, 2.4530f, 2.1421f}},
};
constexpr float kReplicaTol = 1e-3f;

TEST(ConductorIor, AuAndCuMatchTheSpectralReplica) {
    for (const Replica& r : kReplica) {
        ConductorIOR c = conductor_ior(r.name);
        for (int ch = 0; ch < 3; ++ch) {
            EXPECT_NEAR(c.eta[ch], r.eta[ch], kReplicaTol) << r.name << " eta ch " << ch;
            EXPECT_NEAR(c.k[ch], r.k[ch], kReplicaTol) << r.name << " k ch " << ch;
        }
    }
}

// Every NAME of a NAME.eta.spd in Mitsuba 3.9.1's data/ior/ (what its conductor's `material` accepts;
// tests/data/mitsuba/conductor_rgb.py lists them from the package), and "none".
constexpr const char* kMitsubaNames[] = {
    "a-C",       "Ag",         "Al",        "AlAs",         "AlAs_palik", "AlSb",       "AlSb_palik", "Au",
    "Be",        "Be_palik",   "Cr",        "CsI",          "CsI_palik",  "Cu",         "Cu2O",       "Cu2O_palik",
    "Cu_palik",  "CuO",        "CuO_palik", "d-C",          "d-C_palik",  "Hg",         "Hg_palik",   "HgTe",
    "HgTe_palik", "Ir",        "Ir_palik",  "K",            "K_palik",    "Li",         "Li_palik",   "MgO",
    "MgO_palik", "Mo",         "Mo_palik",  "Na_palik",     "Nb",         "Nb_palik",   "Ni_palik",   "Rh",
    "Rh_palik",  "Se",         "Se-e",      "Se-e_palik",   "Se_palik",   "SiC",        "SiC_palik",  "SnTe",
    "SnTe_palik", "Ta",        "Ta_palik",  "Te",           "Te-e",       "Te-e_palik", "Te_palik",   "ThF4",
    "ThF4_palik", "TiC",       "TiC_palik", "TiN",          "TiN_palik",  "TiO2",       "TiO2-e",     "TiO2-e_palik",
    "TiO2_palik", "V_palik",   "VC",        "VC_palik",     "VN",         "VN_palik",   "W",          "none",
};

TEST(ConductorIor, AcceptsEveryMitsubaName) {
    EXPECT_EQ(std::size(kMitsubaNames), 72u);
    for (const char* n : kMitsubaNames) EXPECT_NO_THROW(conductor_ior(n)) << n;
    // Our own additions (Johnson & Christy 1974), and case sensitivity.
    for (const char* n : {"Fe", "Ti", "Ni"}) EXPECT_NO_THROW(conductor_ior(n)) << n;
    EXPECT_EQ(conductor_names().size(), std::size(kMitsubaNames) + 3);
    EXPECT_THROW(conductor_ior("au"), Error);
    EXPECT_THROW(conductor_ior("Cu "), Error);
}

TEST(ConductorIor, TableIsPhysical) {
    for (const std::string& n : conductor_names()) {
        ConductorIOR c = conductor_ior(n);
        EXPECT_TRUE(c.eta.is_finite() && c.k.is_finite()) << n;
        EXPECT_GE(c.eta.min_component(), 0.f) << n;
        EXPECT_GE(c.k.min_component(), 0.f) << n;
    }
    // A name and its "_palik" twin share one file's data where Mitsuba's files are identical.
    ConductorIOR a = conductor_ior("Ir"), b = conductor_ior("Ir_palik");
    for (int ch = 0; ch < 3; ++ch) EXPECT_EQ(a.k[ch], b.k[ch]);
    ConductorIOR none = conductor_ior("none");
    EXPECT_EQ(none.eta.max_component(), 0.f);
    EXPECT_EQ(none.k.min_component(), 1.f);
}
}  // namespace
}  // namespace pellucid
