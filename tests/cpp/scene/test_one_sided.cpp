// The material key two_sided: a one-sided material seen from the back of its shading normal
// scatters nothing (Scene::bsdf); the Mitsuba importer marks its one-sided plugins so.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <string>

#include "pellucid/material/builders.h"
#include "pellucid/scene/json_io.h"
#include "pellucid/scene/mitsuba_xml.h"
#include "pellucid/util/error.h"
#include "support/scene_util.h"

using namespace pellucid;
using pellucid::test::scene_from;

namespace {

/// A unit rectangle (normal +z) of a Lambertian with albedo 0.6; `extra` adds keys to its material.
std::shared_ptr<const Scene> plane(const std::string& extra) {
    return scene_from(R"({"camera": {"type": "perspective"},
        "materials": {"m": {"type": "lambertian", "reflectance": 0.6)" + extra + R"(}},
        "shapes": [{"type": "rectangle", "material": "m"}]})");
}

/// The hit of a ray along -z (front) or +z (back) through (0.1, 0.2).
SurfaceInteraction hit(const Scene& s, bool front) {
    Ray r{Point3f(0.1f, 0.2f, front ? 1.f : -1.f), Vec3f(0.f, 0.f, front ? -1.f : 1.f)};
    SurfaceInteraction si;
    EXPECT_TRUE(s.intersect(r, si));
    return si;
}

/// Does the BSDF at `si` scatter anything (flags, eval and pdf toward a direction on wo's side, samples)?
bool scatters(const Scene& s, const SurfaceInteraction& si) {
    BSDF b = s.bsdf(si);
    const Vec3f wi = normalize(Vec3f(0.3f, -0.2f, si.wo.z > 0.f ? 1.f : -1.f));
    float pdf = -1.f;
    Spectrum f = b.eval(si.wo, wi, TransportMode::Radiance, &pdf);
    bool any_sample = false;
    for (int i = 0; i < 16; ++i)
        any_sample = any_sample || b.sample(si.wo, (i + 0.5f) / 16.f, Vec2f((i + 0.3f) / 16.f, 0.7f)).has_value();
    const bool any = b.flags() != BxDFFlags::None || !f.is_black() || pdf > 0.f || b.pdf(si.wo, wi) > 0.f || any_sample;
    const bool all = b.flags() != BxDFFlags::None && !f.is_black() && pdf > 0.f && b.pdf(si.wo, wi) > 0.f && any_sample;
    EXPECT_EQ(any, all) << "partly scattering";
    return all;
}

Spectrum front_value(const Scene& s) {
    SurfaceInteraction si = hit(s, true);
    return s.bsdf(si).eval(si.wo, normalize(Vec3f(0.3f, -0.2f, 1.f)));
}
}  // namespace

TEST(OneSided, BlackFromBehindUnchangedInFront) {
    auto one = plane(R"(, "two_sided": false)");
    auto two = plane("");
    EXPECT_TRUE(one->has_one_sided);
    EXPECT_FALSE(two->has_one_sided);
    EXPECT_TRUE(scatters(*one, hit(*one, true)));
    EXPECT_FALSE(scatters(*one, hit(*one, false)));
    EXPECT_TRUE(scatters(*two, hit(*two, true)));
    EXPECT_TRUE(scatters(*two, hit(*two, false)));
    EXPECT_EQ(front_value(*one), front_value(*two));
    EXPECT_GT(front_value(*one).max_component(), 0.f);
}

TEST(OneSided, RendersBlackFromBehind) {
    // Under a constant sky, a one-sided plane filling the view (the filter's reach included) and
    // seen from behind is black where the two-sided one is lit.
    auto make = [](bool two_sided) {
        return scene_from(std::string(R"({"film": {"width": 8, "height": 8}, "sampler": {"sample_count": 4},
            "camera": {"type": "perspective", "fov": 10,
              "to_world": [{"look_at": {"origin": [0, 0, -5], "target": [0, 0, 0], "up": [0, 1, 0]}}]},
            "integrator": {"type": "path", "max_depth": 2},
            "materials": {"m": {"type": "lambertian", "reflectance": 0.5, "two_sided": )") +
                          (two_sided ? "true" : "false") + R"(}},
            "shapes": [{"type": "rectangle", "material": "m"}],
            "lights": [{"type": "constant", "radiance": 1}]})");
    };
    auto mean = [](const std::shared_ptr<const Scene>& s) {
        RenderResult r = render(*s, RenderOptions{});
        double sum = 0.0;
        for (float v : r.image.data) sum += v;
        return sum / double(r.image.data.size());
    };
    EXPECT_EQ(mean(make(false)), 0.0);
    EXPECT_GT(mean(make(true)), 0.1);
}

TEST(OneSided, MitsubaOneSidedPluginsAndTwosided) {
    auto load = [](const std::string& bsdf) {
        SceneDesc d = parse_mitsuba_xml(R"(<scene version="3.0.0"><bsdf type="roughconductor" id="rc"/>
            <shape type="rectangle">)" + bsdf + "</shape></scene>",
                                        "scene.xml", ".", false);
        return load_desc(d);
    };
    auto diffuse = load(R"(<bsdf type="diffuse"/>)");
    auto wrapped = load(R"(<bsdf type="twosided"><bsdf type="diffuse"/></bsdf>)");
    auto rc = load(R"(<ref id="rc"/>)");
    auto wrapped_ref = load(R"(<bsdf type="twosided"><ref id="rc"/></bsdf>)");
    EXPECT_FALSE(scatters(*diffuse, hit(*diffuse, false)));
    EXPECT_TRUE(scatters(*diffuse, hit(*diffuse, true)));
    EXPECT_TRUE(scatters(*wrapped, hit(*wrapped, false)));
    EXPECT_FALSE(scatters(*rc, hit(*rc, false)));
    EXPECT_TRUE(scatters(*rc, hit(*rc, true)));
    EXPECT_TRUE(scatters(*wrapped_ref, hit(*wrapped_ref, false)));
    // Mitsuba's dielectrics are two-sided.
    EXPECT_TRUE(load(R"(<bsdf type="roughdielectric"/>)")->material_textures.back().two_sided);
    EXPECT_TRUE(load(R"(<bsdf type="thindielectric"/>)")->material_textures.back().two_sided);
    EXPECT_FALSE(load(R"(<bsdf type="plastic"/>)")->material_textures.back().two_sided);
}

TEST(OneSided, TwoSidedIsASceneLevelKey) {
    // The single-material interface has no scene: the key is an error there, not silently ignored.
    Node n = parse_json(R"({"type": "lambertian", "two_sided": false})", "test");
    try {
        build_material(n, "test", "m");
        ADD_FAILURE() << "expected an error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("scene-level key"), std::string::npos) << e.what();
    }
}
