// Parameter updates on the scene description.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/scene/scene_update.h"

#include <chrono>
#include <map>
#include <set>

#include "pellucid/medium/medium_builder.h"
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

Node* node_at(Node& root, const std::vector<Step>& steps, size_t count) {
    Node* n = &root;
    for (size_t i = 0; i < count; ++i) n = steps[i].is_index ? &n->item(steps[i].index) : n->find(steps[i].key);
    return n;
}

/// The edits applied to a description, undone in reverse order unless kept.
class EditLog {
public:
    explicit EditLog(Node& root) : m_root(root) {}
    ~EditLog() {
        if (m_keep) return;
        for (auto it = m_undo.rbegin(); it != m_undo.rend(); ++it) *node_at(m_root, it->first, it->first.size()) = std::move(it->second);
    }
    EditLog(const EditLog&) = delete;
    EditLog& operator=(const EditLog&) = delete;

    /// Set the value at `steps`; returns the value it replaces (null for a key that was absent).
    const Node& set(const std::vector<Step>& steps, Node value) {
        Node* parent = node_at(m_root, steps, steps.size() - 1);
        const Step& last = steps.back();
        Node* target = last.is_index ? &parent->item(last.index) : parent->find(last.key);
        if (!target) {  // a key left at its default: undone by restoring the whole (small) object
            m_undo.emplace_back(std::vector<Step>(steps.begin(), steps.end() - 1), *parent);
            parent->set(last.key, std::move(value));
            return m_absent;
        }
        m_undo.emplace_back(steps, std::move(*target));
        *target = std::move(value);
        return m_undo.back().second;
    }
    void keep() { m_keep = true; }

private:
    Node& m_root;
    std::vector<std::pair<std::vector<Step>, Node>> m_undo;
    Node m_absent;
    bool m_keep = false;
};

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

/// What fixes the material ids (build.cpp numbers named materials first, then inline and default
/// materials in shape order, a shape with no material or a `null` one taking the default): the
/// named materials' names, and per shape the kind of its material.
std::vector<std::string> material_layout(const Node& root) {
    std::vector<std::string> out;
    std::set<std::string> null_names;
    if (const Node* m = root.find("materials"); m && m->is_object())
        for (const auto& [name, v] : m->members()) {
            out.push_back("named " + name);
            if (is_null_material(v)) null_names.insert(name);
        }
    if (const Node* shapes = root.find("shapes"); shapes && shapes->is_array())
        for (const Node& s : shapes->items()) {
            const Node* m = s.is_object() ? s.find("material") : nullptr;
            const bool null = m && (is_null_material(*m) || (m->is_string() && null_names.count(m->as_string())));
            out.push_back(!m || null ? "default" : m->kind_name());
        }
    return out;
}

/// Which shapes must be built anew, or `full` when everything must (material ids could move).
struct Plan {
    bool full = false;
    std::set<std::string> changed;
};

/// Plan for one edit of the description (at `steps`, replacing `before` with `after`, both applied).
void plan_edit(Plan& plan, const Node& root, const std::vector<Step>& steps, const Node& before, const Node& after) {
    if (steps[0].key != "shapes" || same(before, after)) return;
    if (steps.size() < 3 || !steps[1].is_index) {  // the shape list itself
        plan.full = true;
        return;
    }
    const std::string& key = steps[2].key;
    // Every key of a shape but these is geometry.
    bool rebuild = key != "material" && key != "emitter" && key != "interior" && key != "exterior";
    // An OBJ resolves its usemtl names against the shape's material when it builds its mesh.
    const Node& shape = root.find("shapes")->items()[steps[1].index];
    const Node* type = shape.find("type");
    if (key == "material" && steps.size() == 3 && type && type->is_string() && type->as_string() == "obj")
        rebuild = true;
    if (rebuild) plan.changed.insert(path_index("shapes", steps[1].index));
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
    to.needs_footprints = from.needs_footprints;
    to.has_one_sided = from.has_one_sided;
    to.lights = std::move(from.lights);
    to.infinite_lights = std::move(from.infinite_lights);
    to.light_distribution = std::move(from.light_distribution);
    to.nee_lights = from.nee_lights;
    to.camera = from.camera;
    to.filter = from.filter;
    to.film_splatting = from.film_splatting;
    to.width = from.width;
    to.height = from.height;
    to.spp = from.spp;
    to.seed = from.seed;
    to.sampler = from.sampler;
    to.integrator = from.integrator;
    to.media = std::move(from.media);
    to.camera_medium = from.camera_medium;
    to.has_null_surfaces = from.has_null_surfaces;
    to.subsurface = std::move(from.subsurface);
    to.shape_subsurface = std::move(from.shape_subsurface);
    to.subsurface_choices = std::move(from.subsurface_choices);
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
    SceneDesc& desc = *scene.desc;
    std::vector<std::vector<Step>> targets;
    {
        PathIndex index(desc.root);  // every key path is checked before anything changes
        for (const auto& [path, value] : edits) targets.push_back(resolve(index, desc, path, true));
    }
    const std::vector<std::string> layout = material_layout(desc.root);
    EditLog log(desc.root);  // undoes the edits on every exit but success
    Plan plan;
    for (size_t i = 0; i < edits.size(); ++i) {
        const Node& before = log.set(targets[i], edits[i].second);
        plan_edit(plan, desc.root, targets[i], before, *node_at(desc.root, targets[i], targets[i].size()));
    }
    plan.full = plan.full || material_layout(desc.root) != layout;
    GeometryReuse reuse;
    if (!plan.full) {
        reuse.prior = &scene;
        reuse.changed = plan.changed;
    }
    std::unique_ptr<Scene> built = build_scene(desc, reuse);
    UpdateReport report;
    report.full = plan.full;
    report.geometry = plan.full || !plan.changed.empty();
    report.shapes_rebuilt = plan.full ? built->shapes.size() : plan.changed.size();
    PELLUCID_CHECK((built->bvh_builds > 0) == report.geometry, "an update builds a BVH exactly when geometry changed");
    adopt(scene, *built, report.geometry);
    log.keep();
    ++scene.updates;
    scene.bvh_builds += built->bvh_builds;  // the BVH builds the builder ran (Embree commits)
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}
}  // namespace pellucid
