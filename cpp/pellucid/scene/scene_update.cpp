// Parameter updates on the scene description.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/scene/scene_update.h"

#include <chrono>
#include <map>
#include <set>

#include "pellucid/scene/build.h"
#include "pellucid/scene/properties.h"
#include "pellucid/util/error.h"
#include "pellucid/util/suggest.h"

namespace pellucid {
namespace {

/// One step of a key path: an object member or an array element.
struct Step {
    std::string key;
    size_t index = 0;
    bool is_index = false;
};

/// A key path of the description: a parameter (leaf) or an object that holds parameters.
struct Entry {
    std::vector<Step> steps;
    const Node* node = nullptr;
    bool leaf = false;
    bool extensible = false;  ///< an object whose absent keys may be set (its builder checks them)
};

/// Root members that hold named objects: a parameter update may not add names to them.
bool is_collection(const std::string& key) { return key == "materials" || key == "textures" || key == "media"; }

bool holds_objects(const Node& array) {
    for (const Node& item : array.items())
        if (item.is_object()) return true;
    return false;
}

/// Every key path of a description, in its order.
class PathIndex {
public:
    explicit PathIndex(const Node& root) {
        if (!root.is_object()) return;
        std::vector<Step> steps;
        for (const auto& [key, v] : root.members()) {
            steps.push_back({key});
            visit(v, key, steps, v.is_object() && !is_collection(key));
            steps.pop_back();
        }
    }

    const Entry* find(const std::string& path) const {
        auto it = m_by_path.find(path);
        return it == m_by_path.end() ? nullptr : &m_entries[it->second].second;
    }
    const std::vector<std::pair<std::string, Entry>>& entries() const { return m_entries; }
    std::vector<std::string> leaf_paths() const {
        std::vector<std::string> out;
        for (const auto& [path, e] : m_entries)
            if (e.leaf) out.push_back(path);
        return out;
    }

private:
    void add(const std::string& path, const std::vector<Step>& steps, const Node& n, bool leaf, bool extensible) {
        m_by_path[path] = m_entries.size();
        m_entries.push_back({path, Entry{steps, &n, leaf, extensible}});
    }

    void visit(const Node& n, const std::string& path, std::vector<Step>& steps, bool extensible) {
        const bool is_transform =
            !steps.empty() && !steps.back().is_index && (steps.back().key == "to_world" || steps.back().key == "to_uv");
        if (n.is_object()) {
            add(path, steps, n, false, extensible);
            for (const auto& [key, v] : n.members()) {
                if (key == "type") continue;
                steps.push_back({key});
                const Node* t = v.is_object() ? v.find("type") : nullptr;
                visit(v, path_join(path, key), steps, t && t->is_string());
                steps.pop_back();
            }
        } else if (n.is_array() && !is_transform && holds_objects(n)) {
            add(path, steps, n, false, false);
            for (size_t i = 0; i < n.size(); ++i) {
                steps.push_back({"", i, true});
                const Node& v = n.items()[i];
                const Node* t = v.is_object() ? v.find("type") : nullptr;
                visit(v, path_index(path, i), steps, t && t->is_string());
                steps.pop_back();
            }
        } else {
            add(path, steps, n, true, false);
        }
    }

    std::vector<std::pair<std::string, Entry>> m_entries;
    std::map<std::string, size_t> m_by_path;
};

/// The steps to set `path`: an existing parameter, or a new key of an extensible object.
std::vector<Step> resolve(const PathIndex& index, const SceneDesc& desc, const std::string& path, bool allow_new) {
    auto fail = [&](const std::string& msg) -> std::vector<Step> { throw Error(format_error(desc.source, path, msg)); };
    if (const Entry* e = index.find(path)) {
        if (e->leaf) return e->steps;
        std::string some;
        for (const auto& [p, other] : index.entries())
            if (other.leaf && p.compare(0, path.size() + 1, path + ".") == 0) {
                some = p;
                break;
            }
        return fail(std::string("this is ") + (e->node->is_array() ? "an array" : "an object") +
                    ", not a parameter; set its parameters one by one" + (some.empty() ? "" : " (such as '" + some + "')"));
    }
    const size_t dot = path.rfind('.');
    const std::string key = dot == std::string::npos ? path : path.substr(dot + 1);
    const Entry* parent = dot == std::string::npos ? nullptr : index.find(path.substr(0, dot));
    if (parent && key == "type" && parent->node->find("type"))
        return fail("an object's type is not a parameter (build a new scene to change it)");
    if (allow_new && parent && parent->extensible && !key.empty() && key.find_first_of("[]") == std::string::npos) {
        std::vector<Step> steps = parent->steps;
        steps.push_back({key});
        return steps;
    }
    const std::string hint = did_you_mean(path, index.leaf_paths());
    std::string msg = hint.empty() ? "unknown parameter" : "unknown parameter (" + hint + ")";
    if (!allow_new && parent && parent->extensible) msg += "; a key left at its default can be set, not read";
    return fail(msg);
}

void set_at(Node& root, const std::vector<Step>& steps, Node value) {
    Node* n = &root;
    for (size_t i = 0; i + 1 < steps.size(); ++i) n = steps[i].is_index ? &n->item(steps[i].index) : n->find(steps[i].key);
    const Step& last = steps.back();
    if (last.is_index) n->item(last.index) = std::move(value);
    else n->set(last.key, std::move(value));
}

bool same(const Node& a, const Node& b) {
    if (a.kind() != b.kind()) return false;
    switch (a.kind()) {
        case Node::Kind::Null: return true;
        case Node::Kind::Bool: return a.as_bool() == b.as_bool();
        case Node::Kind::Number: return a.as_number() == b.as_number() && a.is_integer() == b.is_integer();
        case Node::Kind::String: return a.as_string() == b.as_string();
        case Node::Kind::Array:
            if (a.size() != b.size()) return false;
            for (size_t i = 0; i < a.size(); ++i)
                if (!same(a.items()[i], b.items()[i])) return false;
            return true;
        case Node::Kind::Object:
            if (a.size() != b.size()) return false;
            for (size_t i = 0; i < a.size(); ++i)
                if (a.members()[i].first != b.members()[i].first || !same(a.members()[i].second, b.members()[i].second))
                    return false;
            return true;
    }
    return false;
}

/// Does a shape's geometry read this key? Everything but its material and its emitter.
bool is_geometry_key(const std::string& key) { return key != "material" && key != "emitter"; }

bool same_geometry(const Node& a, const Node& b) {
    if (!a.is_object() || !b.is_object()) return same(a, b);
    std::vector<const Node::Member*> ma, mb;
    for (const auto& m : a.members())
        if (is_geometry_key(m.first)) ma.push_back(&m);
    for (const auto& m : b.members())
        if (is_geometry_key(m.first)) mb.push_back(&m);
    if (ma.size() != mb.size()) return false;
    for (size_t i = 0; i < ma.size(); ++i)
        if (ma[i]->first != mb[i]->first || !same(ma[i]->second, mb[i]->second)) return false;
    return true;
}

/// What fixes the material ids (build.cpp numbers named materials first, then inline and default
/// materials in shape order): the named materials' names, and per shape the kind of its material.
std::vector<std::string> material_layout(const Node& root) {
    std::vector<std::string> out;
    if (const Node* m = root.find("materials"); m && m->is_object())
        for (const auto& [name, v] : m->members()) out.push_back("named " + name);
    if (const Node* shapes = root.find("shapes"); shapes && shapes->is_array())
        for (const Node& s : shapes->items()) {
            const Node* m = s.is_object() ? s.find("material") : nullptr;
            out.push_back(m ? m->kind_name() : "-");
        }
    return out;
}

const Node* shape_member(const Node& shape, const char* key) { return shape.is_object() ? shape.find(key) : nullptr; }

/// Which shapes must be built anew, or `full` when everything must (material ids could move).
struct Plan {
    bool full = false;
    std::set<std::string> changed;
};

Plan plan_update(const Node& before, const Node& after) {
    Plan plan;
    if (material_layout(before) != material_layout(after)) {
        plan.full = true;
        return plan;
    }
    const Node* sb = before.find("shapes");
    const Node* sa = after.find("shapes");
    if (!sb && !sa) return plan;
    if (!sb || !sa || !sa->is_array() || !sb->is_array() || sb->size() != sa->size()) {
        plan.full = true;
        return plan;
    }
    for (size_t i = 0; i < sa->size(); ++i) {
        const Node& b = sb->items()[i];
        const Node& a = sa->items()[i];
        bool rebuild = !same_geometry(b, a);
        // An OBJ resolves its usemtl names against the shape's material when it builds its mesh.
        const Node* type = shape_member(a, "type");
        const Node* mb = shape_member(b, "material");
        const Node* ma = shape_member(a, "material");
        if (type && type->is_string() && type->as_string() == "obj" && mb && ma && mb->is_string() && !same(*mb, *ma))
            rebuild = true;
        if (rebuild) plan.changed.insert(path_index("shapes", i));
    }
    return plan;
}

/// Carry the rebuilt parts of `from` into `to`; with `geometry`, the meshes and the BVH too.
void adopt(Scene& to, Scene& from, bool geometry) {
    if (geometry) {
        to.accel.swap(from.accel);
        to.meshes = std::move(from.meshes);
        to.triangle_count = from.triangle_count;
    }
    to.shapes = std::move(from.shapes);
    to.materials = std::move(from.materials);
    to.material_names = std::move(from.material_names);
    to.material_bxdfs = std::move(from.material_bxdfs);
    to.material_textures = std::move(from.material_textures);
    to.textures = std::move(from.textures);
    to.has_textures = from.has_textures;
    to.has_one_sided = from.has_one_sided;
    to.lights = std::move(from.lights);
    to.infinite_lights = std::move(from.infinite_lights);
    to.light_distribution = std::move(from.light_distribution);
    to.camera = from.camera;
    to.filter = from.filter;
    to.film_splatting = from.film_splatting;
    to.width = from.width;
    to.height = from.height;
    to.spp = from.spp;
    to.seed = from.seed;
    to.sampler = from.sampler;
    to.integrator = from.integrator;
}
}  // namespace

std::vector<SceneParameter> scene_parameters(const SceneDesc& desc) {
    PathIndex index(desc.root);
    std::vector<SceneParameter> out;
    for (const auto& [path, e] : index.entries())
        if (e.leaf) out.push_back({path, e.node});
    return out;
}

void check_parameter_path(const SceneDesc& desc, const std::string& path, bool allow_new) {
    PathIndex index(desc.root);
    resolve(index, desc, path, allow_new);
}

UpdateReport update_scene(Scene& scene, const std::vector<std::pair<std::string, Node>>& edits) {
    const auto start = std::chrono::steady_clock::now();
    if (!scene.desc) throw Error(scene.source + ": the scene keeps no description, so it cannot be updated");
    const SceneDesc& before = *scene.desc;
    auto after = std::make_shared<SceneDesc>(before);
    {
        PathIndex index(before.root);
        for (const auto& [path, value] : edits) set_at(after->root, resolve(index, before, path, true), value);
    }
    const Plan plan = plan_update(before.root, after->root);
    GeometryReuse reuse;
    if (!plan.full) {
        reuse.prior = &scene;
        reuse.changed = plan.changed;
    }
    std::unique_ptr<Scene> built = build_scene(*after, reuse);
    UpdateReport report;
    report.full = plan.full;
    report.geometry = plan.full || !plan.changed.empty();
    report.shapes_rebuilt = plan.full ? built->shapes.size() : plan.changed.size();
    adopt(scene, *built, report.geometry);
    scene.desc = std::move(after);
    ++scene.updates;
    if (report.geometry) ++scene.bvh_builds;
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}
}  // namespace pellucid
