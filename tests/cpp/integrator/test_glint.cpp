// Caustic-chain proposals (integrator/glint.h): the chains they find refract twice and leave toward
// the light, the root tables agree with the search, the sampler matches its density (χ² over the
// sphere), and renders with the proposals agree with renders without them (per-pixel two-sample
// z-test) while the caustic through a glossy sphere gets less variance. Fixed seeds throughout.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "pellucid/integrator/glint.h"
#include "pellucid/integrator/integrator.h"
#include "support/chi2.h"
#include "support/scene_util.h"
#include "support/sphere_chi2.h"

using namespace pellucid;
using pellucid::test::scene_from;

namespace {
// Refraction of the travel direction d at normal n (either orientation), relative IOR n_i/n_t.
bool refract_dir(const Vec3f& d, Vec3f n, float eta, Vec3f* t) {
    float c = -dot(d, n);
    if (c < 0.f) n = -n, c = -c;
    const float k = 1.f - eta * eta * (1.f - c * c);
    if (k < 0.f) return false;
    *t = normalize(d * eta + n * (eta * c - std::sqrt(k)));
    return true;
}
// The ray's hit on the sphere: the near one, or the far one from inside.
bool hit_sphere(const Vec3f& o, const Vec3f& d, const Vec3f& c, float r, bool far, float* t) {
    const Vec3f oc = o - c;
    const float b = dot(oc, d), disc = b * b - (dot(oc, oc) - r * r);
    if (disc < 0.f) return false;
    *t = far ? -b + std::sqrt(disc) : -b - std::sqrt(disc);
    return *t > 0.f;
}
// The angle between the direction that leaves the sphere along the chain x → (direction w) and the
// direction toward the light; −1 where the ray misses or is totally reflected.
float exit_error(const GlintPair& g, const Vec3f& x, const Vec3f& w) {
    const Vec3f c(g.cx, g.cy, g.cz);
    float t1, t2;
    if (!hit_sphere(x, w, c, g.r, false, &t1)) return -1.f;
    const Vec3f p1 = x + w * t1;
    Vec3f d1, d2;
    if (!refract_dir(w, normalize(p1 - c), 1.f / g.eta, &d1)) return -1.f;
    if (!hit_sphere(p1 + d1 * (1e-4f * g.r), d1, c, g.r, true, &t2)) return -1.f;
    const Vec3f p2 = p1 + d1 * (t2 + 1e-4f * g.r);
    if (!refract_dir(d1, normalize(p2 - c), g.eta, &d2)) return -1.f;
    const Vec3f l = g.directional ? Vec3f(g.lx, g.ly, g.lz) : normalize(Vec3f(g.lx, g.ly, g.lz) - p2);
    return std::acos(std::min(1.f, dot(d2, l)));
}
// Random pairs (sphere, light) and points x behind the sphere from the light, as the tests draw them.
struct Case {
    GlintPair g;
    Vec3f x;
};
std::vector<Case> cases(bool directional, int n, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> U(-1.f, 1.f);
    std::vector<Case> out;
    for (int i = 0; i < n; ++i) {
        Case k;
        GlintPair& g = k.g;
        g.cx = U(rng), g.cy = U(rng), g.cz = U(rng), g.r = 0.2f + 0.5f * (U(rng) + 1.f), g.alpha = 0.01f, g.eta = 1.5f;
        g.table = 0;
        const Vec3f c(g.cx, g.cy, g.cz), l = normalize(Vec3f(U(rng), U(rng), U(rng)));
        g.directional = directional;
        const Vec3f lp = c + l * (g.r * (3.f + 5.f * (U(rng) + 1.f)));
        if (directional) g.lx = l.x, g.ly = l.y, g.lz = l.z;
        else g.lx = lp.x, g.ly = lp.y, g.lz = lp.z;
        k.x = c + normalize(-l + Vec3f(U(rng), U(rng), U(rng)) * 0.8f) * (g.r * (1.2f + 3.f * (U(rng) + 1.f)));
        out.push_back(k);
    }
    return out;
}
}  // namespace

// The searched roots (point lights, and the search the tables are built from) are chains: the ray
// toward each refracts into the sphere and out of it toward the light, to within 2e-3 rad (float
// rounding of the 20-step bisection and of the re-traced chain). Of 2,000 cases a side, most have a
// chain (x lies behind the sphere), so the test cannot pass on empty results.
TEST(GlintChain, SearchedRootsRefractTowardTheLight) {
    for (bool directional : {true, false}) {
        int found = 0, bad = 0;
        for (const Case& k : cases(directional, 2000, directional ? 7u : 8u)) {
            GlintFrameT<float> f[2];
            glint_frames<float>(k.g, nullptr, k.x, f);
            for (const GlintFrameT<float>& o : f) {
                if (!o.valid) continue;
                ++found;
                const float e = exit_error(k.g, k.x, o.w);
                if (!(e >= 0.f && e < 2e-3f)) ++bad;
            }
        }
        EXPECT_GT(found, 1600) << (directional ? "directional" : "point");
        EXPECT_EQ(bad, 0) << (directional ? "directional" : "point");
    }
}

// A directional pair's table (glint_table) gives the searched roots: of the 2,000 cases' searched
// roots, at least 99 % have a table root within 1.5 widths (σ along the narrower axis), and at most
// 1 % of the table's roots have neither a searched root within that distance nor a chain near them
// (the table's nodes come from a finer scan, which finds roots near the caustic's folds that the
// 24-point search misses). Bilinear interpolation is coarse at the folds, where roots appear and
// vanish between nodes.
TEST(GlintChain, TableRootsAgreeWithTheSearch) {
    std::vector<float> table(size_t(kGlintTableA) * kGlintTableT * kGlintNode);
    glint_table(1.5f, table.data());
    int searched = 0, matched = 0, tabled = 0, unmatched = 0;
    for (const Case& k : cases(true, 2000, 9u)) {
        GlintFrameT<float> ft[2], fs[2];
        glint_frames<float>(k.g, table.data(), k.x, ft);
        glint_frames<float>(k.g, nullptr, k.x, fs);
        auto near = [](const GlintFrameT<float>& a, const GlintFrameT<float>& b) {
            const float angle = std::acos(std::min(1.f, dot(a.w, b.w)));
            return angle <= 1.5f * std::min(b.sigma, b.sigma2);
        };
        for (const auto& s : fs) {
            if (!s.valid) continue;
            ++searched;
            matched += (ft[0].valid && near(ft[0], s)) || (ft[1].valid && near(ft[1], s));
        }
        for (const auto& t : ft) {
            if (!t.valid) continue;
            ++tabled;
            // A table root the coarser search missed still has to be near a chain: its ray leaves
            // the sphere within 3 α_eff (0.06 rad) of the light's direction.
            const float e = exit_error(k.g, k.x, t.w);
            unmatched += !((fs[0].valid && near(t, fs[0])) || (fs[1].valid && near(t, fs[1]))) && !(e >= 0.f && e < 0.06f);
        }
    }
    ASSERT_GT(searched, 1600);
    EXPECT_GE(matched, 0.99 * searched) << matched << " of " << searched;
    EXPECT_LE(unmatched, 0.01 * tabled) << unmatched << " of " << tabled;
}

// The sampler draws its own density: χ² over the sphere (32 × 64 equal-area cells, 10⁶ samples),
// α = 0.01 Šidák-corrected over the three frames, which are anisotropic, about directions away from
// the cells' poles (sphere_chi2.h), and wide enough for the cells to resolve.
TEST(GlintProposal, SamplerMatchesItsDensity) {
    struct Widths {
        float s1, s2;
    };
    const Widths widths[] = {{0.1f, 0.1f}, {0.12f, 0.3f}, {0.4f, 0.15f}};
    const double alpha = test::sidak_alpha(0.01, 3);
    uint64_t seed = 21;
    for (const Widths& w : widths) {
        GlintFrameT<float> f;
        f.valid = true;
        f.w = normalize(Vec3f(1.f, 0.2f, 0.1f));
        f.e2 = normalize(cross(f.w, Vec3f(0.f, 0.f, 1.f)));
        f.e1 = cross(f.e2, f.w);
        f.sigma = w.s1, f.sigma2 = w.s2;
        auto sample = [&](float, const Vec2f& u) -> std::optional<BxDFSample> {
            BxDFSample s;
            s.wi = glint_sample<float>(f, u);
            s.pdf = glint_pdf<float>(f, s.wi);
            s.weight = Spectrum(1.f);
            s.lobe = BxDFFlags::GlossyReflection;
            return s;
        };
        const test::Chi2Result r = test::sphere_chi2(sample, [&](const Vec3f& wi) { return glint_pdf<float>(f, wi); }, seed++);
        EXPECT_GE(r.p_value, alpha) << "widths " << w.s1 << ", " << w.s2 << ": " << r.message;
        // And the density integrates to one over the hemisphere about ω* (nothing beyond it).
        EXPECT_NEAR(test::sphere_integral([&](const Vec3f& wi) { return glint_pdf<float>(f, wi); }, {}, 4), 1.0, 2e-3);
    }
}

namespace {
// A ground, a glass sphere of roughness `roughness` (principled 2015, α = roughness²) above it, and
// a directional light from above and behind: the camera looks down at the sphere's caustic.
std::string caustic_scene(float roughness, bool glints, int spp, int seed) {
    return R"({"camera": {"type": "perspective", "fov": 40,
            "to_world": [{"look_at": {"origin": [0, 2.2, 2.4], "target": [0, 0, 0.3], "up": [0, 1, 0]}}]},
        "film": {"width": 24, "height": 24, "filter": {"type": "box"}},
        "sampler": {"sample_count": )" + std::to_string(spp) + R"(, "seed": )" + std::to_string(seed) + R"(},
        "integrator": {"type": "path", "max_depth": 6, "glints": )" + (glints ? "true" : "false") + R"(},
        "materials": {"ground": {"type": "lambertian", "reflectance": 0.5},
                      "glass": {"type": "principled", "variant": "2015", "roughness": )" + std::to_string(roughness) + R"(,
                                "specular_transmission": 1.0, "eta": 1.5}},
        "shapes": [{"type": "rectangle", "material": "ground",
                    "to_world": [{"scale": 4}, {"rotate": {"axis": [1, 0, 0], "angle": -90}}]},
                   {"type": "sphere", "center": [0, 0.6, -0.2], "radius": 0.4, "material": "glass"}],
        "lights": [{"type": "directional", "direction": [0, -1, 0.45], "irradiance": 3}]})";
}
RenderResult render(const std::string& json) {
    auto scene = scene_from(json);
    RenderOptions o;
    return make_integrator(*scene)->render(*scene, o);
}
}  // namespace

// With the proposals the estimate is the path tracer's: the sphere at α = 0.05 (rough enough for the
// path tracer alone to converge, and still among the spheres that get proposals), the two images
// compared over 6 × 6-pixel blocks (the caustic covers a few blocks) by a two-sample z-test of the
// blocks' sums with both films' variances, α = 0.01 Šidák-corrected over the blocks and the channels,
// and over the whole image at α = 1e-4. Blocks, not pixels: without the proposals a pixel's estimate
// is heavy-tailed near the caustic, and its film variance from 2,048 samples understates it.
TEST(GlintRender, AgreesWithThePathTracerWithoutProposals) {
    const float roughness = std::sqrt(0.05f);
    const RenderResult on = render(caustic_scene(roughness, true, 2048, 3));
    const RenderResult off = render(caustic_scene(roughness, false, 2048, 4));
    const int w = on.image.width, h = on.image.height, B = 6;
    ASSERT_EQ(on.image.data.size(), off.image.data.size());
    ASSERT_EQ(w % B, 0);
    const int blocks = (w / B) * (h / B) * 3;
    const double z_max = test::z_two_sided(test::sidak_alpha(0.01, blocks));
    int fails = 0;
    double d_all = 0, v_all = 0, mean = 0;
    for (int by = 0; by < h / B; ++by)
        for (int bx = 0; bx < w / B; ++bx)
            for (int ch = 0; ch < 3; ++ch) {
                double d = 0, v = 0;
                for (int y = by * B; y < (by + 1) * B; ++y)
                    for (int x = bx * B; x < (bx + 1) * B; ++x) {
                        const size_t i = (size_t(y) * w + x) * 3 + ch;
                        d += double(on.image.data[i]) - off.image.data[i];
                        v += double(on.variance.data[i]) + off.variance.data[i];
                        mean += off.image.data[i];
                    }
                if (std::fabs(d) > z_max * std::sqrt(v + 1e-12)) ++fails;
                d_all += d, v_all += v;
            }
    EXPECT_EQ(fails, 0) << "blocks beyond |z| = " << z_max;
    EXPECT_LT(std::fabs(d_all), test::z_two_sided(1e-4) * std::sqrt(v_all)) << "image sums differ by " << d_all;
    EXPECT_GT(mean / double(on.image.data.size()), 0.05) << "the scene is lit";
    EXPECT_EQ(on.stats.invalid_samples, 0u);
}

// The proposals cut the variance of the caustic a glossy sphere (α = 0.01) casts: over the image,
// the pixels' summed film variance with them is below half of that without (measured: about a
// third: 0.35), at the same seeds and sample count.
TEST(GlintRender, CutTheVarianceOfAGlossySpheresCaustic) {
    const float roughness = 0.1f;
    double v_on = 0, v_off = 0;
    for (int seed : {5, 6}) {
        const RenderResult on = render(caustic_scene(roughness, true, 256, seed));
        const RenderResult off = render(caustic_scene(roughness, false, 256, seed));
        for (float v : on.variance.data) v_on += v;
        for (float v : off.variance.data) v_off += v;
    }
    EXPECT_LT(v_on, 0.5 * v_off) << "summed variance " << v_on << " with the proposals, " << v_off << " without";
}

// Which scenes get pairs: only spheres of a glossy transmissive material (α ≤ 0.05) lit by delta
// lights, and none with "glints": false.
TEST(GlintSetup, PairsOnlyForGlossyGlassSpheresUnderDeltaLights) {
    auto pairs = [](float roughness, bool glints, const std::string& light) {
        std::string json = caustic_scene(roughness, glints, 4, 1);
        const std::string dir = R"({"type": "directional", "direction": [0, -1, 0.45], "irradiance": 3})";
        json.replace(json.find(dir), dir.size(), light);
        return make_glint_setup(*scene_from(json)).pairs.size();
    };
    const std::string dir = R"({"type": "directional", "direction": [0, -1, 0.45], "irradiance": 3})";
    const std::string point = R"({"type": "point", "position": [0, 3, -1], "intensity": 5})";
    const std::string env = R"({"type": "constant", "radiance": 1})";
    EXPECT_EQ(pairs(0.1f, true, dir), 1u);
    EXPECT_EQ(pairs(0.1f, true, dir + ", " + point), 2u);
    EXPECT_EQ(pairs(0.1f, true, env), 0u);        // no delta light
    EXPECT_EQ(pairs(0.1f, false, dir), 0u);       // switched off
    EXPECT_EQ(pairs(0.5f, true, dir), 0u);        // α = 0.25: BSDF sampling finds it
    {  // a smooth dielectric: a delta lobe, which light sampling never evaluates
        std::string json = caustic_scene(0.1f, true, 4, 1);
        const size_t at = json.find(R"({"type": "principled")");
        ASSERT_NE(at, std::string::npos);
        json.replace(at, json.find('}', at) + 1 - at, R"({"type": "dielectric", "int_ior": 1.5})");
        EXPECT_EQ(make_glint_setup(*scene_from(json)).pairs.size(), 0u);
    }
    const GlintSetup gs = make_glint_setup(*scene_from(caustic_scene(0.1f, true, 4, 1)));
    ASSERT_EQ(gs.pairs.size(), 1u);
    EXPECT_EQ(gs.tables.size(), size_t(kGlintTableA) * kGlintTableT * kGlintNode);
    EXPECT_NEAR(gs.pairs[0].alpha, 0.01f, 1e-6f);
}
