// The chord proposals' pairs of a scene (integrator/glint.h).
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/integrator/glint.h"

#include <cmath>
#include <limits>
#include <type_traits>
#include <variant>

#include "pellucid/scene/scene.h"

namespace pellucid {
namespace {
// A transmissive model's √(αx αy) and relative IOR, or false: the rough dielectrics, and the
// principled solids with a transmission lobe.
bool transmissive_lobe(const BxDF& b, float* alpha, float* eta) {
    return std::visit(
        [&](const auto& m) -> bool {
            using T = std::decay_t<decltype(m)>;
            if constexpr (std::is_same_v<T, PrincipledBSDF>) {
                if (m.thin() || !has_flag(m.flags(), BxDFFlags::Transmission)) return false;
                *alpha = std::sqrt(m.specular_distribution().alpha_x() * m.specular_distribution().alpha_y());
                *eta = m.eta();
                return true;
            } else if constexpr (std::is_same_v<T, RoughDielectric<GGX>> || std::is_same_v<T, RoughDielectric<Beckmann>>) {
                *alpha = std::sqrt(m.distribution().alpha_x() * m.distribution().alpha_y());
                *eta = m.eta();
                return true;
            } else {
                return false;
            }
        },
        b);
}
}  // namespace

void glint_table(float eta, float* out) {
    for (int i = 0; i < kGlintTableA; ++i) {
        const float X = float(kGlintTableA) / (float(i) + 0.5f);
        const float psim = std::acos(1.f / X) * 0.999f;
        for (int j = 0; j < kGlintTableT; ++j) {
            const float theta = kPi * float(j) / float(kGlintTableT - 1);
            const float Lx = std::cos(theta), Ly = std::sin(theta);
            float root[2];
            glint_roots<float, 48, 20>(X, Lx, Ly, true, eta, true, root);
            float* node = out + (size_t(i) * kGlintTableT + size_t(j)) * kGlintNode;
            for (int b = 0; b < 2; ++b) {
                float ft = 0.f, fs = 0.f;
                const bool ok = root[b] == root[b] && glint_widths<float>(X, Lx, Ly, true, eta, root[b] * psim, psim, &ft, &fs);
                node[3 * b] = ok ? root[b] : std::numeric_limits<float>::quiet_NaN();
                node[3 * b + 1] = ok ? ft : 0.f, node[3 * b + 2] = ok ? fs : 0.f;
            }
        }
    }
}

GlintSetup make_glint_setup(const Scene& scene) {
    GlintSetup gs;
    if (!scene.integrator.glints) return gs;
    for (const ShapeRecord& s : scene.shapes) {
        if (s.kind != ShapeRecord::Kind::Sphere || s.light >= 0 || s.null_surface || s.flip_normals) continue;
        if (s.material >= scene.material_bxdfs.size() || scene.material_textures[s.material].has_textured_params() ||
            scene.material_textures[s.material].perturbs_normal())
            continue;
        float alpha = 0.f, eta = 1.f;
        if (!scene.material_textures[s.material].two_sided ||
            !transmissive_lobe(scene.material_bxdfs[s.material], &alpha, &eta))
            continue;
        if (!(alpha >= 1e-3f && alpha <= GlintSetup::kMaxAlpha && eta >= 1.01f && eta <= 1.9f)) continue;
        for (const Light& light : scene.lights) {
            GlintPair g;
            g.cx = s.center.x, g.cy = s.center.y, g.cz = s.center.z, g.r = s.radius, g.alpha = alpha, g.eta = eta;
            bool use = true;
            std::visit(
                [&](const auto& l) {
                    using T = std::decay_t<decltype(l)>;
                    if constexpr (std::is_same_v<T, DirectionalLight>) {
                        const Vec3f w = -normalize(l.direction());
                        g.directional = true, g.lx = w.x, g.ly = w.y, g.lz = w.z;
                    } else if constexpr (std::is_same_v<T, PointLight> || std::is_same_v<T, SpotLight>) {
                        const Point3f p = l.position();
                        g.directional = false, g.lx = p.x, g.ly = p.y, g.lz = p.z;
                        use = length(p - s.center) > 1.001f * s.radius;  // not inside the sphere
                    } else {
                        use = false;
                    }
                },
                light);
            if (use && gs.pairs.size() < size_t(GlintSetup::kMaxPairs)) gs.pairs.push_back(g);
        }
    }
    // The root tables of the directional pairs, one per η (glint_roots at each node).
    std::vector<float> etas;
    for (GlintPair& g : gs.pairs) {
        if (!g.directional) continue;
        size_t k = 0;
        while (k < etas.size() && etas[k] != g.eta) ++k;
        if (k == etas.size()) {
            etas.push_back(g.eta);
            const size_t base = gs.tables.size();
            gs.tables.resize(base + size_t(kGlintTableA) * kGlintTableT * kGlintNode);
            glint_table(g.eta, &gs.tables[base]);
        }
        g.table = int32_t(k * size_t(kGlintTableA) * kGlintTableT * kGlintNode);
    }
    return gs;
}
}  // namespace pellucid
