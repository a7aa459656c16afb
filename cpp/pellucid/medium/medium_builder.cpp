// Media from the scene description; the checks on media, their references and their boundaries.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/medium/medium_builder.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <tuple>

#include "pellucid/scene/registry.h"
#include "pellucid/util/error.h"
#include "pellucid/util/suggest.h"

namespace pellucid {

std::string HomogeneousMedium::to_string() const {
    return "HomogeneousMedium[name=" + name + ", sigma_a=" + sigma_a.to_string() + ", sigma_s=" + sigma_s.to_string() +
           ", emission=" + le.to_string() + ", phase=" + pellucid::to_string(phase) + "]";
}
std::string GridMedium::to_string() const {
    return "GridMedium[name=" + name + ", " + (grid ? grid->to_string() : std::string("no grid")) +
           ", sigma_t=" + sigma_t.to_string() + ", albedo=" + albedo.to_string() + ", emission=" + le.to_string() +
           ", phase=" + pellucid::to_string(phase) + ", tracking=" + (tracking == Tracking::Delta ? "delta" : "ratio") +
           "]";
}

const std::vector<std::string>& medium_types() {
    static const std::vector<std::string> t = {"grid", "homogeneous"};
    return t;
}

PhaseFunction build_phase(const Node& n, const std::string& source, const std::string& path) {
    Properties p(n, source, path);
    const std::string type = p.type();
    PhaseFunction out = IsotropicPhase{};
    if (type == "hg") {
        const float g = p.get_float("g", 0.f);
        if (!(g >= -1.f && g <= 1.f)) {
            std::ostringstream os;
            os << "value " << g << " is out of range [-1, 1] (the mean cosine of the scattering angle)";
            p.fail("g", os.str());
        }
        out = HGPhase(g);
    } else if (type != "isotropic") {
        std::string hint = did_you_mean(type, {"hg", "isotropic"});
        p.fail("type", "unknown phase function type '" + type + "' (" + (hint.empty() ? "" : hint + " ") +
                           "known: hg, isotropic)");
    }
    p.check_unqueried();
    return out;
}

namespace {
Spectrum non_negative(Properties& p, const char* key, const Spectrum& def) {
    const Spectrum v = p.get_spectrum(key, def);
    if (v.has_negative() || !v.is_finite())
        p.fail(key, "value " + v.to_string() + " must be finite and >= 0 (a coefficient per colour channel)");
    return v;
}
Spectrum albedo_of(Properties& p) {
    const Spectrum a = p.get_spectrum("albedo", Spectrum(0.75f));
    p.check_spectrum_range("albedo", a, 0.f, 1.f);
    return a;
}
float scale_of(Properties& p) {
    const float s = p.get_float("scale", 1.f);
    if (!(s >= 0.f) || !std::isfinite(s)) p.fail("scale", "value " + std::to_string(s) + " must be finite and >= 0");
    return s;
}
PhaseFunction phase_of(Properties& p) {
    const Node* n = p.get_node("phase");
    return n ? build_phase(*n, p.source(), p.key_path("phase")) : PhaseFunction(IsotropicPhase{});
}

std::shared_ptr<const DensityGrid> density_of(Properties& p, const BuildContext& ctx) {
    const Node* n = p.get_node("density");
    if (!n) p.fail("", "missing required key 'density' (a grid: {\"type\": \"vol\", \"filename\": ...} or "
                       "{\"type\": \"smoke\"})");
    Properties d(*n, p.source(), p.key_path("density"));
    const std::string type = d.type();
    std::shared_ptr<const DensityGrid> g;
    if (type == "vol") {
        const std::string name = d.get_string("filename");
        try {
            g = std::make_shared<DensityGrid>(read_vol_file(ctx.resolve(name)));
        } catch (const Error& e) {
            d.fail("filename", e.what());
        }
    } else if (type == "smoke" || type == "constant") {
        const int n_res = d.get_int("resolution", type == "smoke" ? 64 : 16);
        if (n_res < 1 || n_res > 512) d.fail("resolution", "value " + std::to_string(n_res) + " is out of range [1, 512]");
        if (type == "smoke") {
            const int seed = d.get_int("seed", 1);
            if (seed < 0) d.fail("seed", "value " + std::to_string(seed) + " must be >= 0");
            g = std::make_shared<DensityGrid>(DensityGrid::smoke(n_res, uint32_t(seed)));
        } else {
            const float v = d.get_float("value", 1.f);
            if (!(v >= 0.f) || !std::isfinite(v)) d.fail("value", "value " + std::to_string(v) + " must be finite and >= 0");
            g = std::make_shared<DensityGrid>(DensityGrid::constant(n_res, v));
        }
    } else {
        d.fail("type", "unknown density type '" + type + "' (known: constant, smoke, vol)");
    }
    d.check_unqueried();
    return g;
}
}  // namespace

Medium build_medium(Properties& p, const BuildContext& ctx, const std::string& name) {
    const std::string type = p.type();
    if (type == "homogeneous") {
        HomogeneousMedium m;
        m.name = name;
        const bool split = p.has("sigma_a") || p.has("sigma_s");
        if (split && (p.has("sigma_t") || p.has("albedo")))
            p.fail(p.has("sigma_t") ? "sigma_t" : "albedo",
                   "give either sigma_a and sigma_s, or sigma_t and albedo, not both");
        const float scale = scale_of(p);
        if (split) {
            m.sigma_a = non_negative(p, "sigma_a", Spectrum(0.f)) * scale;
            m.sigma_s = non_negative(p, "sigma_s", Spectrum(0.f)) * scale;
        } else {
            const Spectrum st = non_negative(p, "sigma_t", Spectrum(1.f)) * scale, a = albedo_of(p);
            m.sigma_s = st * a;
            m.sigma_a = st - m.sigma_s;
            for (int c = 0; c < 3; ++c) m.sigma_a[c] = std::max(0.f, m.sigma_a[c]);
        }
        m.le = non_negative(p, "emission", Spectrum(0.f));
        m.phase = phase_of(p);
        p.check_unqueried();
        return m;
    }
    if (type == "grid") {
        GridMedium m;
        m.name = name;
        m.sigma_t = non_negative(p, "sigma_t", Spectrum(1.f)) * scale_of(p);
        m.albedo = albedo_of(p);
        m.le = non_negative(p, "emission", Spectrum(0.f));
        m.phase = phase_of(p);
        m.grid = density_of(p, ctx);
        const Transform to_world = p.get_transform("to_world");
        if (!(std::fabs(glm::determinant(Mat3f(to_world.matrix()))) > 0.f))
            p.fail("to_world", "the grid's transform is singular (it must map the unit cube to a volume)");
        m.world_to_grid = to_world.inverse_matrix();
        m.tracking = p.get_choice("tracking", "ratio", "tracking", {"ratio", "delta"}) == "delta" ? Tracking::Delta
                                                                                                : Tracking::Ratio;
        p.check_unqueried();
        return m;
    }
    p.fail("type", unknown_type_message("medium", type, medium_types()));
}

void build_media(const Node& n, const BuildContext& ctx, std::vector<Medium>& out) {
    if (!n.is_object())
        throw Error(format_error(ctx.source, "media", std::string("expected an object of named media, got a ") +
                                                          n.kind_name()));
    for (const auto& [name, m] : n.members()) {
        Properties p(m, ctx.source, path_join("media", name));
        out.push_back(build_medium(p, ctx, name));
    }
}

int32_t resolve_medium(Properties& p, const std::string& key, const std::vector<Medium>& media) {
    const Node* n = p.get_node(key);
    if (!n) return -1;
    if (!n->is_string()) p.fail(key, std::string("expected the name of a medium (a string), got a ") + n->kind_name());
    std::vector<std::string> names;
    for (size_t i = 0; i < media.size(); ++i) {
        if (name_of(media[i]) == n->as_string()) return int32_t(i);
        names.push_back(name_of(media[i]));
    }
    std::string hint = did_you_mean(n->as_string(), names);
    p.fail(key, "no medium '" + n->as_string() + "' (" + (hint.empty() ? "" : hint + " ") + "known: " +
                    (names.empty() ? std::string("none; define media under the top-level 'media'") : join_names(names)) +
                    ")");
}

bool is_null_material(const Node& n) {
    const Node* t = n.is_object() ? n.find("type") : nullptr;
    return t && t->is_string() && t->as_string() == "null";
}

size_t open_edge_count(const TriangleMesh& mesh) {
    // Weld vertices by exact position, then count each undirected edge's triangles.
    std::map<std::tuple<float, float, float>, uint32_t> ids;
    std::vector<uint32_t> weld(mesh.positions.size());
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
        const Point3f& q = mesh.positions[i];
        weld[i] = ids.emplace(std::make_tuple(q.x, q.y, q.z), uint32_t(ids.size())).first->second;
    }
    std::map<std::pair<uint32_t, uint32_t>, int> edges;
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3)
        for (int e = 0; e < 3; ++e) {
            uint32_t a = weld[mesh.indices[t + e]], b = weld[mesh.indices[t + (e + 1) % 3]];
            if (a > b) std::swap(a, b);
            if (a != b) ++edges[{a, b}];
        }
    size_t open = 0;
    for (const auto& [k, count] : edges) open += count != 2;
    return open;
}
}  // namespace pellucid
