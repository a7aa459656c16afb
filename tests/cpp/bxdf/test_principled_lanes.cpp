// Lanes equal scalars for the principled BSDF's three packet forms, the opaque solid
// (PrincipledBSDFT, bxdf/principled_probe.h), the thin sheet (PrincipledThinT,
// bxdf/principled_thin_probe.h) and the solid with a transmission lobe (PrincipledSolidT,
// bxdf/principled_solid_probe.h): on every lane of every SIMD target, eval, pdf and sample give
// exactly the bits the float instantiation gives for that lane's inputs (a bound of 0 ulp: the
// library and the probes are built without contraction; the solids' half vectors with their Fresnel
// and the clear coat's GTR1 normal are the float functions' own, called a lane at a time, and the
// rest of every form uses only IEEE-exact lane operations). The float instantiation, built from
// packet parameters as the path tracer builds it, in turn gives the bits of the scalar BxDF API
// (PrincipledBSDF: has_lanes(), thin(), or neither).
//
// Cases: the property suite's principled BSDFs (bxdf_cases.h: its cases and sweeps over metallic,
// roughness, η, the transmissions and the tints) of each form, and a few more (η = 1, where the
// dielectric Fresnel vanishes; the glossiest clear coat; tinted sheen and specular; a sheet all
// diffuse transmission, one all specular; glass denser and less dense than its outside), one material
// per lane at random so every packet mixes materials; lanes of other models and partially masked
// packets; directions on, near and below the horizon, at the normal, in the mirror direction and
// straight through; u at 0, 1/2 and 1 − 2⁻²⁴; both transport modes and glossy-only, diffuse-only and
// transmission-only contexts.
//
// Renders: bench/suite/principled.json, whose seven materials are all packet forms, gives the scalar
// target's image bit for bit on every SIMD target.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

#include "bxdf/bxdf_cases.h"
#include "bxdf/principled_probe.h"
#include "bxdf/principled_thin_probe.h"
#include "bxdf/principled_solid_probe.h"
#include "pellucid/api.h"
#include "pellucid/integrator/path_services.h"
#include "pellucid/integrator/simd_target.h"
#include "pellucid/scene/json_io.h"
#include "pellucid/sampling/rng.h"
#include "pellucid/sampling/warp.h"
#include "support/probe_outputs.h"

using namespace pellucid;

namespace pellucid::principled_probe {
#ifdef PELLUCID_PRINCIPLED_PROBE_AVX512
void run_avx512(const In& in, Out& out);
#endif
#ifdef PELLUCID_PRINCIPLED_PROBE_AVX2
void run_avx2(const In& in, Out& out);
#endif
#ifdef PELLUCID_PRINCIPLED_PROBE_SSE4
void run_sse4(const In& in, Out& out);
#endif
}  // namespace pellucid::principled_probe
namespace pellucid::principled_thin_probe {
#ifdef PELLUCID_PRINCIPLED_THIN_PROBE_AVX512
void run_avx512(const In& in, Out& out);
#endif
#ifdef PELLUCID_PRINCIPLED_THIN_PROBE_AVX2
void run_avx2(const In& in, Out& out);
#endif
#ifdef PELLUCID_PRINCIPLED_THIN_PROBE_SSE4
void run_sse4(const In& in, Out& out);
#endif
}  // namespace pellucid::principled_thin_probe
namespace pellucid::principled_solid_probe {
#ifdef PELLUCID_PRINCIPLED_SOLID_PROBE_AVX512
void run_avx512(const In& in, Out& out);
#endif
#ifdef PELLUCID_PRINCIPLED_SOLID_PROBE_AVX2
void run_avx2(const In& in, Out& out);
#endif
#ifdef PELLUCID_PRINCIPLED_SOLID_PROBE_SSE4
void run_sse4(const In& in, Out& out);
#endif
}  // namespace pellucid::principled_solid_probe

namespace {
/// The property suite's opaque solid principled BSDFs, and a few more.
std::vector<PrincipledBSDF> solid_materials() {
    std::vector<PrincipledBSDF> m;
    using test::BxDFCases;
    auto add = [&](const PrincipledBSDF& b) {
        if (b.has_lanes()) m.push_back(b);
    };
    for (const auto& c : BxDFCases<PrincipledBSDF>::cases()) add(c.bxdf);
    for (const auto& b : BxDFCases<PrincipledBSDF>::sweep()) add(b);
    PrincipledInputs p;
    p.variant = PrincipledVariant::Burley2015;
    p.base_color = Spectrum(0.2f, 0.5f, 0.9f);
    p.roughness = 0.35f;
    p.anisotropic = 0.6f;
    p.sheen = 0.8f;
    p.sheen_tint = 0.7f;
    p.specular_tint = 0.6f;
    p.metallic = 0.4f;
    p.clearcoat = 0.7f;
    p.clearcoat_gloss = 1.f;  // α_c = 0.001
    add(PrincipledBSDF(p));
    p.eta = 1.f;  // F_η = 0: no specular reflection value, but its lobe is still sampled
    add(PrincipledBSDF(p));
    p.eta = 0.f;
    p.specular = 0.9f;
    p.flatness = 1.f;
    p.metallic = 0.f;
    p.roughness = 0.f;
    add(PrincipledBSDF(p));
    p.specular_transmission = 0.7f;  // metallic 1 leaves no transmission lobe: an opaque solid
    p.metallic = 1.f;
    add(PrincipledBSDF(p));
    return m;
}

/// The property suite's thin principled BSDFs, and a few more.
std::vector<PrincipledBSDF> thin_materials() {
    std::vector<PrincipledBSDF> m;
    using test::BxDFCases;
    auto add = [&](const PrincipledBSDF& b) {
        if (b.thin()) m.push_back(b);
    };
    for (const auto& c : BxDFCases<PrincipledBSDF>::cases()) add(c.bxdf);
    for (const auto& b : BxDFCases<PrincipledBSDF>::sweep()) add(b);
    PrincipledInputs p;
    p.variant = PrincipledVariant::Burley2015;
    p.thin = true;
    p.base_color = Spectrum(0.2f, 0.5f, 0.9f);
    p.roughness = 0.35f;
    p.anisotropic = 0.6f;
    p.sheen = 0.8f;
    p.sheen_tint = 0.7f;
    p.specular_tint = 0.6f;
    p.specular_transmission = 0.4f;
    p.diffuse_transmission = 0.7f;
    add(PrincipledBSDF(p));
    p.eta = 1.f;  // F_η = 0: no specular reflection value, but its lobe is still sampled
    add(PrincipledBSDF(p));
    p.eta = 0.f;
    p.specular_transmission = 0.f;
    p.diffuse_transmission = 2.f;  // all diffuse transmission
    add(PrincipledBSDF(p));
    p.specular_transmission = 1.f;  // all specular
    p.roughness = 0.05f;
    add(PrincipledBSDF(p));
    return m;
}

/// The property suite's principled solids with a transmission lobe, and a few more.
std::vector<PrincipledBSDF> glass_materials() {
    std::vector<PrincipledBSDF> m;
    using test::BxDFCases;
    auto add = [&](const PrincipledBSDF& b) {
        if (!b.thin() && !b.has_lanes()) m.push_back(b);
    };
    for (const auto& c : BxDFCases<PrincipledBSDF>::cases()) add(c.bxdf);
    for (const auto& b : BxDFCases<PrincipledBSDF>::sweep()) add(b);
    PrincipledInputs p;
    p.variant = PrincipledVariant::Burley2015;
    p.base_color = Spectrum(0.2f, 0.5f, 0.9f);
    p.roughness = 0.35f;
    p.anisotropic = 0.6f;
    p.sheen = 0.8f;
    p.sheen_tint = 0.7f;
    p.specular_tint = 0.6f;
    p.metallic = 0.4f;
    p.clearcoat = 0.7f;
    p.clearcoat_gloss = 1.f;
    p.specular_transmission = 0.5f;
    add(PrincipledBSDF(p));
    p.eta = 0.7f;  // the interior the less dense side
    add(PrincipledBSDF(p));
    p.specular_transmission = 1.f;  // clear glass, nearly smooth
    p.metallic = 0.f;
    p.roughness = 0.05f;
    p.eta = 1.5f;
    add(PrincipledBSDF(p));
    return m;
}

/// The three packet forms: their materials, packet parameters, probes and the parameter a test
/// changes in one lane (the opaque solid's clear coat, the sheet's specular transmission, the
/// transmissive solid's w_bsdf).
struct Solid {
    static constexpr int kP = kPrincipledParams, kChanged = 12;
    using In = principled_probe::In;
    static std::vector<PrincipledBSDF> materials() { return solid_materials(); }
    static void params(const PrincipledBSDF& b, float* q) { principled_packet_params(b.lanes(), q); }
    static void run_float(const In& in, form_probe::Out& out) { principled_probe::run<float>(in, out); }
    static bool run_target(SimdTarget t, const In& in, form_probe::Out& out) {
        switch (t) {
#ifdef PELLUCID_PRINCIPLED_PROBE_AVX512
            case SimdTarget::AVX512: principled_probe::run_avx512(in, out); return true;
#endif
#ifdef PELLUCID_PRINCIPLED_PROBE_AVX2
            case SimdTarget::AVX2: principled_probe::run_avx2(in, out); return true;
#endif
#ifdef PELLUCID_PRINCIPLED_PROBE_SSE4
            case SimdTarget::SSE4: principled_probe::run_sse4(in, out); return true;
#endif
            default: return false;
        }
    }
};
struct Thin {
    static constexpr int kP = kPrincipledThinParams, kChanged = 12;
    using In = principled_thin_probe::In;
    static std::vector<PrincipledBSDF> materials() { return thin_materials(); }
    static void params(const PrincipledBSDF& b, float* q) { principled_thin_packet_params(b.thin_lanes(), q); }
    static void run_float(const In& in, form_probe::Out& out) { principled_thin_probe::run<float>(in, out); }
    static bool run_target(SimdTarget t, const In& in, form_probe::Out& out) {
        switch (t) {
#ifdef PELLUCID_PRINCIPLED_THIN_PROBE_AVX512
            case SimdTarget::AVX512: principled_thin_probe::run_avx512(in, out); return true;
#endif
#ifdef PELLUCID_PRINCIPLED_THIN_PROBE_AVX2
            case SimdTarget::AVX2: principled_thin_probe::run_avx2(in, out); return true;
#endif
#ifdef PELLUCID_PRINCIPLED_THIN_PROBE_SSE4
            case SimdTarget::SSE4: principled_thin_probe::run_sse4(in, out); return true;
#endif
            default: return false;
        }
    }
};

struct Glass {
    static constexpr int kP = kPrincipledSolidParams, kChanged = 19;
    using In = principled_solid_probe::In;
    static std::vector<PrincipledBSDF> materials() { return glass_materials(); }
    static void params(const PrincipledBSDF& b, float* q) { principled_solid_packet_params(b.solid_lanes(), q); }
    static void run_float(const In& in, form_probe::Out& out) { principled_solid_probe::run<float>(in, out); }
    static bool run_target(SimdTarget t, const In& in, form_probe::Out& out) {
        switch (t) {
#ifdef PELLUCID_PRINCIPLED_SOLID_PROBE_AVX512
            case SimdTarget::AVX512: principled_solid_probe::run_avx512(in, out); return true;
#endif
#ifdef PELLUCID_PRINCIPLED_SOLID_PROBE_AVX2
            case SimdTarget::AVX2: principled_solid_probe::run_avx2(in, out); return true;
#endif
#ifdef PELLUCID_PRINCIPLED_SOLID_PROBE_SSE4
            case SimdTarget::SSE4: principled_solid_probe::run_sse4(in, out); return true;
#endif
            default: return false;
        }
    }
};

template <class Form>
struct Cases {
    static constexpr int kN = 16384;
    static constexpr int kP = Form::kP;
    std::vector<PrincipledBSDF> mats = Form::materials();
    std::vector<float> params;  // kP per material
    std::vector<float> q[kP], a[9];
    std::vector<int> mat;  // -1: a lane of another model
    std::vector<int32_t> kind;
    std::unique_ptr<bool[]> active{new bool[kN]};
    typename Form::In in;

    Cases() {
        params.resize(mats.size() * kP);
        for (size_t m = 0; m < mats.size(); ++m) Form::params(mats[m], &params[m * kP]);
        PCG32 rng(9, 31);
        for (auto& v : q) v.resize(kN);
        for (auto& v : a) v.resize(kN);
        mat.resize(kN);
        kind.resize(kN);
        auto dir = [&](int i, int at) {
            const Vec3f w = square_to_uniform_sphere(Vec2f(rng.next_float(), rng.next_float()));
            for (int c = 0; c < 3; ++c) a[at + c][size_t(i)] = w[c];
        };
        const float us[] = {0.f, 0.5f, kOneMinusEpsilon, 1e-7f};
        for (int i = 0; i < kN; ++i) {
            const size_t k = size_t(i);
            mat[k] = i % 13 == 5 ? -1 : int(rng.next_u32() % uint32_t(mats.size()));
            dir(i, 0), dir(i, 3);
            float *wo[3] = {&a[0][k], &a[1][k], &a[2][k]}, *wi[3] = {&a[3][k], &a[4][k], &a[5][k]};
            switch (i % 11) {  // edge cases
                case 1: *wo[2] = 0.f; break;                                             // wo on the horizon
                case 2: *wi[2] = 1e-7f; break;                                           // wi grazing
                case 3: *wo[0] = -*wi[0], *wo[1] = -*wi[1], *wo[2] = *wi[2]; break;      // the mirror direction
                case 4: *wo[0] = *wo[1] = 0.f, *wo[2] = 1.f; break;                      // wo at the normal
                case 5: *wi[2] = -std::fabs(*wi[2]), *wo[2] = std::fabs(*wo[2]); break;  // a transmission pair
                case 6: *wo[2] = -std::fabs(*wo[2]), *wi[2] = -std::fabs(*wi[2]); break; // from behind
                case 7: *wo[2] = 1e-7f; break;                                           // wo grazing
                case 8: *wi[0] = -*wo[0], *wi[1] = -*wo[1], *wi[2] = -*wo[2]; break;     // straight through
                case 9: *wo[2] = -1e-6f, *wi[2] = -std::fabs(*wi[2]); break;             // grazing from behind
                default: break;
            }
            for (int c = 0; c < 3; ++c) a[6 + c][k] = i % 7 < 4 ? us[(i / 7 + c) % 4] : rng.next_float();
            for (int p = 0; p < kP; ++p) q[p][k] = mat[k] >= 0 ? params[size_t(mat[k]) * kP + size_t(p)] : 1e6f + float(p);
            kind[k] = mat[k] < 0 ? 0 : 1;
            active[i] = (i / 16) % 3 != 1 || i % 5 != 0;  // every third packet partially masked
        }
        in.n = kN;
        for (int p = 0; p < kP; ++p) in.q[p] = q[p].data();
        for (int c = 0; c < 3; ++c) in.wo[c] = a[c].data(), in.wi[c] = a[3 + c].data(), in.u[c] = a[6 + c].data();
        in.kind = kind.data();
        in.active = active.get();
    }
    Vec3f wo(int i) const { return Vec3f(a[0][size_t(i)], a[1][size_t(i)], a[2][size_t(i)]); }
    Vec3f wi(int i) const { return Vec3f(a[3][size_t(i)], a[4][size_t(i)], a[5][size_t(i)]); }
};

constexpr int kN = Cases<Solid>::kN;
using Outputs = test::ProbeOutputs<form_probe::Out, form_probe::kOutputs, kN>;
using test::same_bits;

void expect_equal(const Outputs& scalar, const Outputs& packet, const char* target) {
    EXPECT_EQ(test::count_differing(scalar, packet, target), 0u) << target;
}
}  // namespace

TEST(PrincipledLanes, TheGridIsCovered) {
    const Cases<Solid> cases;
    EXPECT_GE(cases.mats.size(), 50u);
    // Every lobe of the model is present in some material.
    bool metal = false, coat = false, sheen = false, tint = false;
    for (const auto& m : cases.mats) {
        const PrincipledBSDFT<float> l = m.lanes();
        metal = metal || l.metallic > 0.f;
        coat = coat || l.clearcoat > 0.f;
        sheen = sheen || (l.sheen > 0.f && l.sheen_tint > 0.f);
        tint = tint || l.spec_tint > 0.f;
    }
    EXPECT_TRUE(metal && coat && sheen && tint);
}

TEST(PrincipledThinLanes, TheGridIsCovered) {
    const Cases<Thin> cases;
    EXPECT_GE(cases.mats.size(), 30u);
    // Every lobe of the model is present in some material.
    bool spec = false, diff_t = false, diff_r = false, tint = false, sheen = false;
    for (const auto& m : cases.mats) {
        const PrincipledThinT<float> l = m.thin_lanes();
        spec = spec || l.st > 0.f;
        diff_t = diff_t || (l.st < 1.f && l.dt > 0.f);
        diff_r = diff_r || (l.st < 1.f && l.dt < 1.f);
        tint = tint || l.spec_tint > 0.f;
        sheen = sheen || (l.sheen > 0.f && l.sheen_tint > 0.f);
    }
    EXPECT_TRUE(spec && diff_t && diff_r && tint && sheen);
}

TEST(PrincipledGlassLanes, TheGridIsCovered) {
    const Cases<Glass> cases;
    EXPECT_GE(cases.mats.size(), 30u);
    // Every lobe of the model is present in some material, and both sides of the interface.
    bool metal = false, coat = false, diffuse = false, inside_denser = false, outside_denser = false;
    for (const auto& m : cases.mats) {
        const PrincipledSolidT<float> l = m.solid_lanes();
        EXPECT_GT(l.w_bsdf, 0.f);
        metal = metal || l.o.metallic > 0.f;
        coat = coat || l.o.clearcoat > 0.f;
        diffuse = diffuse || l.o.w_brdf > 0.f;
        inside_denser = inside_denser || l.o.eta > 1.f;
        outside_denser = outside_denser || l.o.eta < 1.f;
    }
    EXPECT_TRUE(metal && coat && diffuse && inside_denser && outside_denser);
}

template <class Form>
class PrincipledFormLanes : public ::testing::Test {};
using PrincipledForms = ::testing::Types<Solid, Thin, Glass>;
TYPED_TEST_SUITE(PrincipledFormLanes, PrincipledForms);

TYPED_TEST(PrincipledFormLanes, FloatInstantiationIsTheScalarBxDF) {
    // The float instantiation from packet parameters gives the scalar API's bits: eval, pdf and
    // sample in each context, case by case; many cases sample each lobe.
    const Cases<TypeParam> cases;
    Outputs scalar;
    TypeParam::run_float(cases.in, scalar.out);
    size_t compared = 0, differ = 0, diffuse = 0, glossy = 0, nonzero = 0;
    auto check = [&](float x, float y, int k, int i) {
        ++compared;
        if (!same_bits(x, y) && ++differ <= 5)
            ADD_FAILURE() << "output " << k << " case " << i << ": packet form " << x << ", BxDF " << y;
    };
    for (int i = 0; i < kN; ++i) {
        if (cases.mat[size_t(i)] < 0 || !cases.active[i]) continue;
        const PrincipledBSDF& b = cases.mats[size_t(cases.mat[size_t(i)])];
        const Vec3f wo = cases.wo(i), wi = cases.wi(i);
        const Vec2f u(cases.a[7][size_t(i)], cases.a[8][size_t(i)]);
        for (int c = 0; c < form_probe::kContexts; ++c) {
            const BxDFContext ctx{form_probe::kMode[c], form_probe::kAllowed[c]};
            const int k0 = c * form_probe::kPerContext;
            const Spectrum f = b.eval(ctx, wo, wi);
            nonzero += !f.is_black();
            for (int ch = 0; ch < 3; ++ch) check(scalar.at(k0 + ch, i), f[ch], k0 + ch, i);
            check(scalar.at(k0 + 3, i), b.pdf(ctx, wo, wi), k0 + 3, i);
            const auto s = b.sample(ctx, wo, cases.a[6][size_t(i)], u);
            check(scalar.at(k0 + 4, i), s ? 1.f : 0.f, k0 + 4, i);
            if (!s) continue;
            (has_flag(s->lobe, BxDFFlags::Diffuse) ? diffuse : glossy) += 1;
            for (int ch = 0; ch < 3; ++ch) check(scalar.at(k0 + 5 + ch, i), s->wi[ch], k0 + 5 + ch, i);
            for (int ch = 0; ch < 3; ++ch) check(scalar.at(k0 + 8 + ch, i), s->weight[ch], k0 + 8 + ch, i);
            check(scalar.at(k0 + 11, i), s->pdf, k0 + 11, i);
            check(scalar.at(k0 + 12, i), s->eta, k0 + 12, i);
            check(scalar.at(k0 + 13, i), float(uint32_t(s->lobe)), k0 + 13, i);
        }
    }
    EXPECT_EQ(differ, 0u) << "of " << compared;
    EXPECT_GT(diffuse, size_t(kN) / 4);
    EXPECT_GT(glossy, size_t(kN));
    EXPECT_GT(nonzero, size_t(kN));
}

TYPED_TEST(PrincipledFormLanes, EveryTargetEveryLane) {
    const Cases<TypeParam> cases;
    Outputs scalar;
    TypeParam::run_float(cases.in, scalar.out);
    int targets = 0;
    for (SimdTarget t : available_simd_targets()) {
        Outputs packet;
        if (!TypeParam::run_target(t, cases.in, packet.out)) continue;
        ++targets;
        expect_equal(scalar, packet, to_string(t).c_str());
    }
    this->RecordProperty("targets", targets);
}

TYPED_TEST(PrincipledFormLanes, ACaseChangedInOneLaneIsSeen) {
    // The comparison itself: another value of one parameter in one lane must change that lane's
    // outputs only.
    Cases<TypeParam> cases;
    Outputs a, b;
    TypeParam::run_float(cases.in, a.out);
    int lane = 0;
    while (!(cases.kind[size_t(lane)] == 1 && cases.active[lane] && cases.wo(lane).z > 0.1f && cases.wi(lane).z > 0.1f &&
             cases.q[TypeParam::kChanged][size_t(lane)] > 0.f))
        ++lane;
    const_cast<float*>(cases.in.q[TypeParam::kChanged])[lane] *= 0.5f;
    TypeParam::run_float(cases.in, b.out);
    const std::vector<int> changed = test::differing_cases(a, b);
    EXPECT_FALSE(changed.empty());
    for (int i : changed) EXPECT_EQ(i, lane);
}

namespace {
std::shared_ptr<const Scene> load_suite_scene(const char* file, int width, int height) {
    SceneDesc desc = read_json_file(std::string(PELLUCID_SOURCE_DIR) + "/bench/suite/" + file);
    Node film = *desc.root.find("film");
    film.set("width", Node::number(width, true));
    film.set("height", Node::number(height, true));
    desc.root.set("film", film);
    return load_desc(desc);
}
}  // namespace

TEST(SimdTargetRenderPrincipled, SuiteSceneOpaqueSolidsArePacketForms) {
    // The opaque solids of the suite's principled scenes run as kPacketPrincipled, the thin sheets as
    // kPacketPrincipledThin and the glass as kPacketPrincipledSolid.
    for (const char* file : {"principled.json", "many_materials.json"}) {
        auto scene = load_suite_scene(file, 16, 16);
        const PathSetup ps = make_path_setup(*scene, 8, 5, true, true, SamplerType::Independent);
        int packet = 0, thin = 0, glass = 0;
        for (size_t m = 0; m < scene->material_bxdfs.size(); ++m) {
            const auto* b = std::get_if<PrincipledBSDF>(&scene->material_bxdfs[m]);
            if (!b) continue;
            const bool solid = ps.packet_kind[m] == int32_t(kPacketPrincipled);
            const bool sheet = ps.packet_kind[m] == int32_t(kPacketPrincipledThin);
            const bool clear = ps.packet_kind[m] == int32_t(kPacketPrincipledSolid);
            EXPECT_EQ(solid, b->has_lanes()) << file << " " << m;
            EXPECT_EQ(sheet, b->thin()) << file << " " << m;
            EXPECT_EQ(clear, !b->has_lanes() && !b->thin()) << file << " " << m;
            (solid ? packet : sheet ? thin : glass) += 1;
        }
        EXPECT_GE(packet, 3) << file;
        if (std::string(file) == "principled.json") {
            EXPECT_EQ(thin, 1);
            EXPECT_EQ(glass, 1);
        }
    }
}

TEST(SimdTargetRenderPrincipled, EveryTargetGivesTheScalarImage) {
    auto scene = load_suite_scene("principled.json", 64, 48);
    for (const char* sampler : {"independent", "sobol"}) {
        RenderOptions o;
        o.spp = 3;
        o.seed = 5;
        o.threads = 2;
        o.sampler = sampler;
        set_simd_target(SimdTarget::Scalar);
        const RenderResult ref = render(*scene, o);
        for (SimdTarget t : available_simd_targets()) {
            if (t == SimdTarget::Scalar) continue;
            set_simd_target(t);
            const RenderResult r = render(*scene, o);
            ASSERT_EQ(r.image.data.size(), ref.image.data.size());
            size_t differ = 0;
            for (size_t i = 0; i < r.image.data.size(); ++i)
                differ += std::memcmp(&r.image.data[i], &ref.image.data[i], sizeof(float)) != 0;
            EXPECT_EQ(differ, 0u) << sampler << " " << to_string(t);
            EXPECT_EQ(r.stats.samples, ref.stats.samples);
        }
        set_simd_target(std::nullopt);
    }
}
