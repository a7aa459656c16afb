// Mitsuba 3 XML -> SceneDesc. The only pugixml user. The converter emits exactly the JSON-shaped
// tree of docs/scene-format.md, so the builder, its validation and its error messages are shared
// with JSON scenes. Every mapping and difference is listed in docs/mitsuba-import.md.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/scene/mitsuba_xml.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <pugixml.hpp>
#include <sstream>
#include <utility>
#include <vector>

#include "pellucid/scene/mitsuba_table.h"
#include "pellucid/util/error.h"
#include "pellucid/util/limits.h"
#include "pellucid/util/log.h"

namespace pellucid {
namespace {
namespace fs = std::filesystem;

constexpr int kMaxIncludeDepth = 16;
constexpr double kPiD = 3.14159265358979323846;

/// One parsed XML file (the scene or an include) with what is needed for "file:line" messages.
struct XmlFile {
    std::string name;  ///< as shown in messages
    fs::path dir;      ///< directory relative names in this file resolve against
    std::string text;
    std::vector<size_t> line_starts;
    pugi::xml_document doc;

    int line_of(ptrdiff_t offset) const {
        if (offset < 0) return 0;
        auto it = std::upper_bound(line_starts.begin(), line_starts.end(), size_t(offset));
        return int(it - line_starts.begin());
    }
};

/// A named parameter of a plugin: a property tag, a named nested texture or a named texture ref.
struct Prop {
    std::string name;
    Node value;
    pugi::xml_node node;
    bool used = false;
};

struct Collected {
    std::vector<Prop> props;
    std::vector<pugi::xml_node> objects;  ///< unnamed nested plugins and refs to them
};

/// An object with an id, for <ref id=...>.
struct IdEntry {
    std::string kind;  ///< "bsdf", "texture", or another tag (not referencable here)
    Node value;        ///< textures: the node to inline; bsdfs: the material name
    int line = 0;
};

bool is_property_tag(const std::string& t) {
    return t == "float" || t == "integer" || t == "boolean" || t == "string" || t == "rgb" ||
           t == "spectrum" || t == "point" || t == "vector" || t == "transform";
}

bool is_object_tag(const std::string& t) {
    return t == "bsdf" || t == "shape" || t == "emitter" || t == "sensor" || t == "film" ||
           t == "sampler" || t == "rfilter" || t == "integrator" || t == "texture" || t == "medium" ||
           t == "phase" || t == "volume" || t == "ref";
}

Node num(double v) { return Node::number(v, false); }

Node vec_node(const std::vector<double>& v) {
    Node a = Node::array();
    for (double x : v) a.push_back(num(x));
    return a;
}

class Converter {
public:
    Converter(bool lenient, const std::map<std::string, std::string>& params, fs::path base_dir)
        : m_lenient(lenient), m_params(params), m_base_dir(std::move(base_dir)) {}

    SceneDesc run(const std::string& text, const std::string& source) {
        XmlFile& f = load(text, source, m_base_dir, pugi::xml_node());
        pugi::xml_node root = scene_root(f);
        m_file = &f;
        check_version(root);
        parse_scene_children(root, 0);

        SceneDesc d;
        d.source = source;
        d.base_dir = m_base_dir.string();
        d.root = Node::object();
        d.root.line = line(root);
        if (m_camera) d.root.set("camera", *m_camera);
        if (m_film) d.root.set("film", *m_film);
        if (m_sampler) d.root.set("sampler", *m_sampler);
        if (m_integrator) d.root.set("integrator", *m_integrator);
        if (m_media.size()) d.root.set("media", m_media);
        if (m_materials.size()) d.root.set("materials", m_materials);
        if (m_shapes.size()) d.root.set("shapes", m_shapes);
        if (m_lights.size()) d.root.set("lights", m_lights);
        return d;
    }

private:
    // ---- files, lines, errors ------------------------------------------------------------------
    XmlFile& load(const std::string& text, const std::string& name, const fs::path& dir,
                  pugi::xml_node from) {
        auto f = std::make_unique<XmlFile>();
        f->name = name;
        f->dir = dir;
        f->text = text;
        f->line_starts.push_back(0);
        for (size_t i = 0; i < f->text.size(); ++i)
            if (f->text[i] == '\n') f->line_starts.push_back(i + 1);
        pugi::xml_parse_result r =
            f->doc.load_buffer(f->text.data(), f->text.size(), pugi::parse_default, pugi::encoding_utf8);
        if (!r)
            throw Error(name + ":" + std::to_string(f->line_of(r.offset)) + ": malformed XML: " +
                        r.description());
        m_files.push_back(std::move(f));
        return *m_files.back();
    }

    pugi::xml_node scene_root(const XmlFile& f) {
        pugi::xml_node root = f.doc.document_element();
        if (!root || std::string(root.name()) != "scene") {
            std::string got = root ? "<" + std::string(root.name()) + ">" : "nothing";
            throw Error(f.name + ":" + std::to_string(root ? f.line_of(root.offset_debug()) : 1) +
                        ": expected a <scene> root element, got " + got);
        }
        return root;
    }

    void check_version(pugi::xml_node root) {
        pugi::xml_attribute v = root.attribute("version");
        if (!v) return;
        int major = std::atoi(v.value());
        if (major < 2)
            unsupported(root, "Mitsuba scene version " + std::string(v.value()) +
                                  " is not supported (only 3.x; parameter names changed in 2.0)");
    }

    int line(pugi::xml_node n) const { return n ? m_file->line_of(n.offset_debug()) : 0; }
    std::string where(pugi::xml_node n) const { return m_file->name + ":" + std::to_string(line(n)); }

    [[noreturn]] void fail(pugi::xml_node n, const std::string& msg) const {
        throw Error(where(n) + ": " + msg);
    }

    /// Unsupported input: an error, or in lenient mode a warning (the caller skips the element).
    void unsupported(pugi::xml_node n, const std::string& msg) const {
        if (!m_lenient) fail(n, msg);
        log_warning(where(n) + ": " + msg + " (skipped)");
    }

    // ---- attributes and values ------------------------------------------------------------------
    std::string substitute(const std::string& s, pugi::xml_node n) const {
        if (s.find('$') == std::string::npos) return s;
        std::string out;
        for (size_t i = 0; i < s.size();) {
            if (s[i] != '$') {
                out += s[i++];
                continue;
            }
            size_t j = i + 1;
            while (j < s.size() && (std::isalnum(static_cast<unsigned char>(s[j])) || s[j] == '_')) ++j;
            std::string key = s.substr(i + 1, j - i - 1);
            if (key.empty()) fail(n, "stray '$' in attribute value '" + s + "'");
            auto p = m_params.find(key);
            if (p != m_params.end()) out += p->second;
            else {
                auto d = m_defaults.find(key);
                if (d == m_defaults.end())
                    fail(n, "undefined parameter '$" + key +
                                "' (declare it with <default name=\"" + key + "\" value=...> or pass it)");
                out += d->second;
            }
            i = j;
        }
        return out;
    }

    std::optional<std::string> opt_attr(pugi::xml_node n, const char* name) const {
        pugi::xml_attribute a = n.attribute(name);
        if (!a) return std::nullopt;
        return substitute(a.value(), n);
    }

    std::string attr(pugi::xml_node n, const char* name) const {
        auto v = opt_attr(n, name);
        if (!v) fail(n, "<" + std::string(n.name()) + "> needs a '" + name + "' attribute");
        return *v;
    }

    double parse_double(const std::string& s, pugi::xml_node n) const {
        const char* b = s.c_str();
        while (std::isspace(static_cast<unsigned char>(*b))) ++b;
        char* e = nullptr;
        double v = std::strtod(b, &e);
        while (e && std::isspace(static_cast<unsigned char>(*e))) ++e;
        if (e == b || !e || *e != '\0' || !std::isfinite(v)) fail(n, "expected a number, got '" + s + "'");
        return v;
    }

    std::vector<double> parse_doubles(const std::string& s, pugi::xml_node n) const {
        std::vector<double> out;
        std::string tok;
        auto flush = [&] {
            if (!tok.empty()) out.push_back(parse_double(tok, n));
            tok.clear();
        };
        for (char c : s) {
            if (c == ',' || std::isspace(static_cast<unsigned char>(c))) flush();
            else tok += c;
        }
        flush();
        return out;
    }

    std::vector<double> vec3_attr(pugi::xml_node n, const char* name) const {
        std::vector<double> v = parse_doubles(attr(n, name), n);
        if (v.size() != 3) fail(n, "'" + std::string(name) + "' needs 3 numbers, got " + std::to_string(v.size()));
        return v;
    }

    /// A 3-vector from value="x, y, z" or from x= y= z= attributes (missing ones = def).
    std::vector<double> xyz(pugi::xml_node n, double def) const {
        if (n.attribute("value")) return vec3_attr(n, "value");
        std::vector<double> v(3, def);
        const char* names[3] = {"x", "y", "z"};
        for (int i = 0; i < 3; ++i)
            if (auto a = opt_attr(n, names[i])) v[size_t(i)] = parse_double(*a, n);
        return v;
    }

    std::string resolve_filename(const std::string& name) const {
        fs::path p(name);
        if (p.is_absolute() || m_file->dir == m_base_dir) return name;
        fs::path full = fs::absolute(m_file->dir / p).lexically_normal();
        fs::path rel = full.lexically_relative(fs::absolute(m_base_dir).lexically_normal());
        return rel.empty() ? full.string() : rel.string();
    }

    Node parse_transform(pugi::xml_node t) const {
        Node ops = Node::array();
        for (pugi::xml_node c : t.children()) {
            if (c.type() != pugi::node_element) continue;
            std::string tag = c.name();
            Node op = Node::object();
            op.line = line(c);
            if (tag == "translate") {
                op.set("translate", vec_node(xyz(c, 0.0)));
            } else if (tag == "scale") {
                if (c.attribute("value")) {
                    std::vector<double> v = parse_doubles(attr(c, "value"), c);
                    if (v.size() == 1) op.set("scale", num(v[0]));
                    else if (v.size() == 3) op.set("scale", vec_node(v));
                    else fail(c, "<scale value> needs 1 or 3 numbers");
                } else {
                    op.set("scale", vec_node(xyz(c, 1.0)));
                }
            } else if (tag == "rotate") {
                Node r = Node::object();
                r.set("axis", vec_node(xyz(c, 0.0)));
                r.set("angle", num(parse_double(attr(c, "angle"), c)));
                op.set("rotate", r);
            } else if (tag == "lookat") {
                Node r = Node::object();
                r.set("origin", vec_node(vec3_attr(c, "origin")));
                r.set("target", vec_node(vec3_attr(c, "target")));
                if (c.attribute("up")) r.set("up", vec_node(vec3_attr(c, "up")));
                op.set("look_at", r);
            } else if (tag == "matrix") {
                std::vector<double> v = parse_doubles(attr(c, "value"), c);
                if (v.size() != 16) fail(c, "<matrix> needs 16 numbers (row-major 4x4), got " + std::to_string(v.size()));
                op.set("matrix", vec_node(v));
            } else {
                fail(c, "unknown transform operation <" + tag +
                            "> (known: translate, rotate, scale, lookat, matrix)");
            }
            ops.push_back(op);
        }
        return ops;
    }

    /// The value of a property tag; nullopt when skipped in lenient mode.
    std::optional<Node> parse_property(pugi::xml_node n) const {
        std::string tag = n.name();
        std::string name = attr(n, "name");
        Node v;
        if (tag == "float") {
            v = num(parse_double(attr(n, "value"), n));
        } else if (tag == "integer") {
            std::string s = attr(n, "value");
            char* e = nullptr;
            long long i = std::strtoll(s.c_str(), &e, 10);
            if (s.empty() || *e != '\0') fail(n, "expected an integer, got '" + s + "'");
            v = Node::number(double(i), true);
        } else if (tag == "boolean") {
            std::string s = attr(n, "value");
            std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
            if (s != "true" && s != "false") fail(n, "expected true or false, got '" + s + "'");
            v = Node::boolean(s == "true");
        } else if (tag == "string") {
            std::string s = attr(n, "value");
            v = Node::string(name == "filename" ? resolve_filename(s) : s);
        } else if (tag == "rgb") {
            std::vector<double> c = parse_doubles(attr(n, "value"), n);
            if (c.size() == 1) v = num(c[0]);
            else if (c.size() == 3) v = vec_node(c);
            else fail(n, "<rgb> needs 1 or 3 numbers, got " + std::to_string(c.size()));
        } else if (tag == "spectrum") {
            if (n.attribute("filename")) {
                unsupported(n, "spectrum files are not supported; use <rgb>");
                return std::nullopt;
            }
            std::string s = attr(n, "value");
            if (s.find(':') != std::string::npos) {
                unsupported(n, "spectra given as wavelength:value pairs are not supported; use <rgb>");
                return std::nullopt;
            }
            std::vector<double> c = parse_doubles(s, n);
            if (c.size() != 1) fail(n, "<spectrum value> needs one number (grey), got " + std::to_string(c.size()));
            v = num(c[0]);
        } else if (tag == "point" || tag == "vector") {
            v = vec_node(xyz(n, 0.0));
        } else if (tag == "transform") {
            v = parse_transform(n);
        }
        v.line = line(n);
        return v;
    }

    // ---- ids and refs ---------------------------------------------------------------------------
    const IdEntry& lookup_ref(pugi::xml_node ref) const {
        std::string id = attr(ref, "id");
        auto it = m_ids.find(id);
        if (it == m_ids.end()) fail(ref, "unknown reference id '" + id + "'");
        return it->second;
    }

    void register_id(pugi::xml_node n, const std::string& id, IdEntry e) {
        auto it = m_ids.find(id);
        if (it != m_ids.end())
            fail(n, "duplicate id '" + id + "' (first defined on line " + std::to_string(it->second.line) + ")");
        e.line = line(n);
        m_ids.emplace(id, std::move(e));
    }

    // ---- collecting a plugin's children ---------------------------------------------------------
    Collected collect(pugi::xml_node n) {
        Collected c;
        for (pugi::xml_node ch : n.children()) {
            if (ch.type() != pugi::node_element) continue;
            std::string tag = ch.name();
            if (is_property_tag(tag)) {
                std::string name = attr(ch, "name");
                if (auto v = parse_property(ch)) c.props.push_back({name, *v, ch});
            } else if (tag == "texture" && ch.attribute("name")) {
                if (auto v = texture_value(ch)) c.props.push_back({attr(ch, "name"), *v, ch});
            } else if (tag == "ref") {
                const IdEntry& e = lookup_ref(ch);
                if (e.kind == "texture") {
                    if (ch.attribute("name")) {
                        Node v = e.value;
                        v.line = line(ch);
                        c.props.push_back({attr(ch, "name"), v, ch});
                    } else {
                        c.objects.push_back(ch);
                    }
                } else {
                    c.objects.push_back(ch);
                }
            } else if (is_object_tag(tag)) {
                c.objects.push_back(ch);
            } else {
                unsupported(ch, "unknown element <" + tag + ">");
            }
        }
        return c;
    }

    Prop* take(Collected& c, const std::string& name) {
        for (Prop& p : c.props)
            if (!p.used && p.name == name) {
                p.used = true;
                return &p;
            }
        return nullptr;
    }

    /// The importer table's entry for an accepted plugin (the caller checked it is accepted).
    static const MitsubaPlugin& entry(const char* kind, const std::string& type) {
        const MitsubaPlugin* p = find_mitsuba_plugin(kind, type);
        if (!p) throw Error(std::string("internal: no importer table entry for ") + kind + " '" + type + "'");
        return *p;
    }

    /// Copy the remaining parameters under the names of the plugin's table entry, log the ignored
    /// ones; the rest is unsupported. Converted parameters must have been taken by the caller.
    void map_params(Node& out, Collected& c, const std::string& what, const MitsubaPlugin& plugin) {
        for (Prop& p : c.props) {
            if (p.used) continue;
            p.used = true;
            auto it = std::find_if(plugin.params.begin(), plugin.params.end(),
                                   [&](const MitsubaParam& m) { return p.name == m.mitsuba; });
            if (it == plugin.params.end()) {
                unsupported(p.node, "unsupported parameter '" + p.name + "' of " + what);
            } else if (it->use == MitsubaParamUse::ignored) {
                log_info(where(p.node) + ": parameter '" + p.name + "' of " + what + " is ignored");
            } else if (it->use == MitsubaParamUse::converted) {
                fail(p.node, "internal: parameter '" + p.name + "' of " + what + " was not converted");
            } else {
                if (out.find(it->ours)) fail(p.node, "parameter '" + p.name + "' given twice");
                out.set(it->ours, p.value);
            }
        }
    }

    static void set_default(Node& out, const std::string& key, Node v) {
        if (!out.find(key)) out.set(key, std::move(v));
    }

    Node make(const std::string& type, pugi::xml_node n) const {
        Node o = Node::object();
        o.line = line(n);
        o.set("type", Node::string(type));
        return o;
    }

    void no_objects(const Collected& c, const std::string& what) {
        for (pugi::xml_node o : c.objects) unsupported(o, "unexpected <" + std::string(o.name()) + "> inside " + what);
    }

    // ---- textures -------------------------------------------------------------------------------
    std::optional<Node> texture_value(pugi::xml_node n) {
        if (std::string(n.name()) == "ref") {
            const IdEntry& e = lookup_ref(n);
            if (e.kind != "texture") fail(n, "reference '" + attr(n, "id") + "' is a " + e.kind + ", expected a texture");
            return e.value;
        }
        std::string type = attr(n, "type");
        std::string what = "texture plugin '" + type + "'";
        const MitsubaPlugin* plugin = find_mitsuba_plugin("texture", type);
        if (!plugin) {
            unsupported(n, "unsupported " + what);
            return std::nullopt;
        }
        Collected c = collect(n);
        Node out = make(plugin->ours, n);
        if (type == "bitmap") {
            // raw="true" means linear values; without it our default applies (sRGB for 8/16-bit files,
            // linear for float files, and linear for bump and normal maps: docs/mitsuba-import.md).
            if (Prop* raw = take(c, "raw")) {
                if (!raw->value.is_bool()) fail(raw->node, "bitmap 'raw' must be a boolean");
                if (raw->value.as_bool()) out.set("color_space", Node::string("linear"));
            }
            map_params(out, c, what, *plugin);
            if (!out.find("filename")) fail(n, "bitmap texture needs a 'filename'");
        } else {  // checkerboard
            map_params(out, c, what, *plugin);
            // Mitsuba's checkerboard is point-sampled; keep its definition so renders agree.
            out.set("filtered", Node::boolean(false));
        }
        no_objects(c, what);
        if (auto id = opt_attr(n, "id")) register_id(n, *id, {"texture", out, 0});
        return out;
    }

    // ---- bsdfs ----------------------------------------------------------------------------------
    /// A shape's (or wrapper's) material: a name (for bsdfs with an id, or refs) or an inline object.
    std::optional<Node> bsdf_value(pugi::xml_node n) {
        // Wrappers (twosided, bumpmap, normalmap) recurse here once per level of nesting.
        struct Depth {
            int& d;
            ~Depth() { --d; }
        } depth{++m_bsdf_depth};
        if (m_bsdf_depth > max_scene_depth())
            fail(n, "bsdfs nested deeper than " + std::to_string(max_scene_depth()) +
                        " levels (the scene depth limit; raise it with PELLUCID_MAX_SCENE_DEPTH)");
        if (std::string(n.name()) == "ref") {
            const IdEntry& e = lookup_ref(n);
            if (e.kind != "bsdf") fail(n, "reference '" + attr(n, "id") + "' is a " + e.kind + ", expected a bsdf");
            return e.value;
        }
        std::optional<Node> b = convert_bsdf(n);
        if (!b) return std::nullopt;
        auto id = opt_attr(n, "id");
        if (!id) return b;
        // Named bsdfs become entries of "materials"; a wrapper that resolved to a name aliases it.
        Node mat = *b;
        if (mat.is_string()) mat = *m_materials.find(mat.as_string());
        register_id(n, *id, {"bsdf", Node::string(*id), 0});
        m_materials.set(*id, mat);
        return Node::string(*id);
    }

    std::optional<Node> convert_bsdf(pugi::xml_node n) {
        std::string type = attr(n, "type");
        std::string what = "bsdf plugin '" + type + "'";
        const MitsubaPlugin* plugin = find_mitsuba_plugin("bsdf", type);
        if (!plugin) {
            unsupported(n, "unsupported " + what);
            return std::nullopt;
        }
        if (type == "twosided") {
            // twosided(bsdf): the nested material with two_sided true (our default; the one-sided
            // plugins below set it false).
            Collected c = collect(n);
            Node none = Node::object();
            map_params(none, c, what, *plugin);
            std::vector<pugi::xml_node> inner;
            for (pugi::xml_node o : c.objects) {
                std::string t = o.name();
                if (t == "bsdf" || (t == "ref" && lookup_ref(o).kind == "bsdf")) inner.push_back(o);
                else unsupported(o, "unexpected <" + t + "> inside " + what);
            }
            if (inner.size() == 2) {
                unsupported(n, "twosided with different front and back bsdfs is not supported");
                return std::nullopt;
            }
            if (inner.size() != 1) fail(n, "twosided needs exactly one nested bsdf");
            std::optional<Node> v = bsdf_value(inner[0]);
            if (!v) return std::nullopt;
            Node mat = v->is_string() ? *m_materials.find(v->as_string()) : *v;
            if (!mat.find("two_sided")) return v;  // two-sided already (a named one stays shared)
            mat.set("two_sided", Node::boolean(true));
            return mat;
        }
        if (type == "bumpmap" || type == "normalmap") {
            const bool bump = type == "bumpmap";
            Collected c = collect(n);
            Node out = make(bump ? "bump_map" : "normal_map", n);
            std::optional<Node> inner;
            // bumpmap: Mitsuba takes exactly one Texture child under any name (its own documentation
            // names it "arbitrary"): an unnamed or named <texture>, or a <ref> to one with or without
            // a name. normalmap reads only the texture named "normalmap" (a parameter, below).
            std::vector<std::pair<pugi::xml_node, Node>> textures;
            for (pugi::xml_node o : c.objects) {
                std::string t = o.name();
                bool is_ref = t == "ref";
                std::string kind = is_ref ? lookup_ref(o).kind : t;
                if (kind == "bsdf") {
                    if (inner) fail(o, what + " takes exactly one nested bsdf");
                    inner = bsdf_value(o);
                    if (!inner) return std::nullopt;
                } else if (kind == "texture" && bump) {
                    std::optional<Node> tex = texture_value(o);
                    if (!tex) return std::nullopt;
                    textures.emplace_back(o, *tex);
                } else {
                    unsupported(o, "unexpected <" + t + "> inside " + what);
                }
            }
            if (bump)
                for (Prop& p : c.props) {
                    const std::string tag = p.node.name();
                    if (p.used || (tag != "texture" && tag != "ref")) continue;
                    p.used = true;
                    textures.emplace_back(p.node, p.value);
                }
            std::sort(textures.begin(), textures.end(), [](const auto& a, const auto& b) {
                return a.first.offset_debug() < b.first.offset_debug();
            });
            if (textures.size() > 1)
                fail(textures[1].first, what + " takes exactly one nested texture (under any name); the first is on "
                                            "line " + std::to_string(line(textures[0].first)));
            // Mitsuba's two options for perturbed normals, both on by default:
            // use_shadowing_function → terminator_softening (with Mitsuba's Estevez et al. 2019
            // term, below); flip_invalid_normals → invalid_normals "mirror" or "keep".
            if (Prop* sh = take(c, "use_shadowing_function")) {
                if (!sh->value.is_bool()) fail(sh->node, "'use_shadowing_function' of " + what + " must be a boolean");
                out.set("terminator_softening", sh->value);
            }
            if (Prop* fl = take(c, "flip_invalid_normals")) {
                if (!fl->value.is_bool()) fail(fl->node, "'flip_invalid_normals' of " + what + " must be a boolean");
                if (!fl->value.as_bool()) out.set("invalid_normals", Node::string("keep"));
            }
            map_params(out, c, what, *plugin);
            if (!inner) fail(n, what + " needs exactly one nested bsdf; it has none");
            if (bump && textures.empty()) fail(n, what + " needs exactly one nested texture (under any name); it has none");
            if (!bump && !out.find("normal_map")) fail(n, "normalmap needs a texture named 'normalmap'");
            // Our materials carry bump and normal maps as keys: copy the wrapped material and add them.
            Node mat = *inner;
            if (mat.is_string()) mat = *m_materials.find(mat.as_string());
            // A bitmap without raw: Mitsuba decodes sRGB-encoded (8/16-bit) files, bump and normal
            // maps too, where our data textures default to linear; "auto" decodes as Mitsuba does.
            auto decoded = [](Node t) {
                if (t.is_object() && !t.find("color_space") && t.find("type") && t.find("type")->as_string() == "image")
                    t.set("color_space", Node::string("auto"));
                return t;
            };
            if (bump) {
                mat.set("bump_map", decoded(textures[0].second));
                if (const Node* sc = out.find("bump_scale")) mat.set("bump_scale", *sc);
            } else {
                mat.set("normal_map", decoded(*out.find("normal_map")));
            }
            if (const Node* ts = out.find("terminator_softening")) mat.set("terminator_softening", *ts);
            // Mitsuba's gradient, frame, flip and shadowing term (docs/mitsuba-import.md).
            mat.set("bump_model", Node::string("mitsuba"));
            mat.set("terminator_model", Node::string("estevez"));
            mat.set("invalid_normals", out.find("invalid_normals") ? *out.find("invalid_normals") : Node::string("mirror"));
            return mat;
        }

        Collected c = collect(n);
        Node out = make(plugin->ours, n);
        if (type == "diffuse" || type == "null") {
            map_params(out, c, what, *plugin);
        } else if (type == "roughdiffuse") {
            // Mitsuba's alpha is an RMS slope; its Oren-Nayar sigma (radians) is alpha / sqrt(2).
            out.set("variant", Node::string("classic"));
            double alpha = 0.2;
            if (Prop* a = take(c, "alpha")) {
                if (!a->value.is_number()) {
                    unsupported(a->node, "roughdiffuse 'alpha' must be a number (textures are not supported)");
                    return std::nullopt;
                }
                alpha = a->value.as_number();
            }
            out.set("sigma", num(alpha / std::sqrt(2.0) * 180.0 / kPiD));
            map_params(out, c, what, *plugin);
        } else if (type == "conductor") {
            map_params(out, c, what, *plugin);
        } else if (type == "roughconductor") {
            map_params(out, c, what, *plugin);
            set_default(out, "distribution", Node::string("beckmann"));
            out.set("shadowing", Node::string("separable"));  // Mitsuba's G = G1(wi) G1(wo)
        } else if (type == "dielectric") {
            map_params(out, c, what, *plugin);
        } else if (type == "roughdielectric") {
            map_params(out, c, what, *plugin);
            set_default(out, "distribution", Node::string("beckmann"));
            out.set("shadowing", Node::string("separable"));
        } else if (type == "thindielectric") {
            map_params(out, c, what, *plugin);
        } else if (type == "plastic" || type == "roughplastic") {
            bool is_rough = type == "roughplastic";
            // nonlinear = false (Mitsuba's default): Kd/(1 − R̄), our "linear"; true: Kd/(1 − Kd R̄), "coupled".
            bool nonlinear = false;
            if (Prop* nl = take(c, "nonlinear")) {
                if (!nl->value.is_bool()) fail(nl->node, what + " 'nonlinear' must be a boolean");
                nonlinear = nl->value.as_bool();
            }
            map_params(out, c, what, *plugin);
            if (is_rough) set_default(out, "distribution", Node::string("beckmann"));
            out.set("variant", Node::string(nonlinear ? "coupled" : "linear"));
            if (is_rough) {
                // The coat's tabulated rough transmittance and separable G, as Mitsuba's roughplastic.
                out.set("coat_transmittance", Node::string("rough"));
                out.set("shadowing", Node::string("separable"));
            }
        } else if (type == "principled" || type == "principledthin") {
            // Mitsuba 3's principled is the Burley 2015 BSDF: our principled variant "2015"
            // (principledthin: its thin mode). Sampling rates change only the noise.
            bool thin = type == "principledthin";
            out.set("variant", Node::string("2015"));
            if (thin) out.set("thin", Node::boolean(true));
            map_params(out, c, what, *plugin);
            if (!thin) {
                if (out.find("eta") && out.find("specular"))
                    fail(n, what + " takes 'eta' or 'specular', not both (specular sets eta)");
            }
            // Mitsuba 3's defaults where they differ from ours.
            set_default(out, "base_color", num(0.5));
            set_default(out, "sheen_tint", num(0.0));
            if (thin) set_default(out, "eta", num(1.5));
            else set_default(out, "clearcoat_gloss", num(0.0));
        } else {
            fail(n, "internal: no conversion for " + what);
        }
        no_objects(c, what);
        // Mitsuba's opaque plugins reflect only toward the front of the shading normal (black from
        // behind); twosided (above) lifts it. dielectric, roughdielectric, thindielectric and
        // principledthin are two-sided there; principled keeps its specular lobes from behind, so
        // it stays two-sided here (docs/mitsuba-import.md, "Sidedness").
        static const char* one_sided[] = {"diffuse", "roughdiffuse", "conductor", "roughconductor", "plastic",
                                          "roughplastic"};
        for (const char* t : one_sided)
            if (type == t) out.set("two_sided", Node::boolean(false));
        return out;
    }

    // ---- media ----------------------------------------------------------------------------------
    /// A medium (a <medium>, or a <ref> to one) as the name of an entry of our `media` object. An
    /// inline medium without an id gets the name "medium@<file line>".
    std::optional<Node> medium_value(pugi::xml_node n) {
        if (std::string(n.name()) == "ref") {
            const IdEntry& e = lookup_ref(n);
            if (e.kind != "medium") fail(n, "reference '" + attr(n, "id") + "' is a " + e.kind + ", expected a medium");
            return e.value;
        }
        std::string type = attr(n, "type");
        std::string what = "medium plugin '" + type + "'";
        const MitsubaPlugin* plugin = find_mitsuba_plugin("medium", type);
        if (!plugin) {
            unsupported(n, "unsupported " + what + " (known: " + mitsuba_known_plugins("medium") + ")");
            return std::nullopt;
        }
        Collected c = collect(n);
        Node out = make(plugin->ours, n);
        map_params(out, c, what, *plugin);
        for (pugi::xml_node o : c.objects) {
            std::string t = o.name();
            if (t != "phase") {
                unsupported(o, "unexpected <" + t + "> inside " + what);
                continue;
            }
            if (out.find("phase")) fail(o, "a medium takes one phase function");
            if (std::optional<Node> ph = convert_phase(o)) out.set("phase", *ph);
        }
        auto id = opt_attr(n, "id");
        std::string name = id ? *id : "medium@" + m_file->name + ":" + std::to_string(line(n));
        if (m_media.find(name)) fail(n, "duplicate medium '" + name + "'");
        if (id) register_id(n, *id, {"medium", Node::string(name), 0});
        m_media.set(name, out);
        return Node::string(name);
    }

    std::optional<Node> convert_phase(pugi::xml_node n) {
        std::string type = attr(n, "type");
        std::string what = "phase plugin '" + type + "'";
        const MitsubaPlugin* plugin = find_mitsuba_plugin("phase", type);
        if (!plugin) {
            unsupported(n, "unsupported " + what + " (known: " + mitsuba_known_plugins("phase") + ")");
            return std::nullopt;
        }
        Collected c = collect(n);
        Node out = make(plugin->ours, n);
        map_params(out, c, what, *plugin);
        no_objects(c, what);
        return out;
    }

    // ---- shapes and emitters --------------------------------------------------------------------
    std::optional<Node> convert_shape(pugi::xml_node n) {
        std::string type = attr(n, "type");
        std::string what = "shape plugin '" + type + "'";
        const MitsubaPlugin* plugin = find_mitsuba_plugin("shape", type);
        if (!plugin) {
            unsupported(n, "unsupported " + what);
            return std::nullopt;
        }
        Node out = make(plugin->ours, n);
        Collected c = collect(n);
        map_params(out, c, what, *plugin);
        if (type == "obj" || type == "ply") {
            if (!out.find("filename")) fail(n, type + " shape needs a 'filename'");
            set_default(out, "face_normals", Node::boolean(false));
            // Mitsuba computes vertex normals for a mesh file without them unless face_normals is set
            // (found by tests/python/test_mitsuba_scenes.py, metals.xml).
            const Node* fnode = out.find("face_normals");
            set_default(out, "smooth_normals", Node::boolean(!(fnode && fnode->is_bool() && fnode->as_bool())));
            // Mitsuba flips OBJ texture v by default (OBJ's v points up, image rows go down).
            if (type == "obj") set_default(out, "flip_tex_coords", Node::boolean(true));
            // Mitsuba ignores an OBJ's usemtl (one bsdf per shape): so do we for its scenes.
            if (type == "obj") out.set("usemtl", Node::boolean(false));
        }
        std::optional<Node> material, emitter;
        for (pugi::xml_node o : c.objects) {
            std::string t = o.name();
            std::string kind = t == "ref" ? lookup_ref(o).kind : t;
            if (kind == "bsdf") {
                if (material) fail(o, "a shape takes one bsdf");
                material = bsdf_value(o);
            } else if (t == "emitter") {
                if (emitter) fail(o, "a shape takes one emitter");
                emitter = convert_area(o);
            } else if (kind == "medium") {
                // interior / exterior: a parameter of the shape in the importer table.
                const std::string side = o.attribute("name").value();
                auto known = std::find_if(plugin->params.begin(), plugin->params.end(),
                                          [&](const MitsubaParam& m) { return side == m.mitsuba; });
                if (side != "interior" && side != "exterior")
                    fail(o, "a medium inside a shape needs name=\"interior\" or name=\"exterior\", got '" + side + "'");
                if (known == plugin->params.end()) {
                    unsupported(o, "unsupported parameter '" + side + "' of " + what);
                    continue;
                }
                if (out.find(known->ours)) fail(o, "parameter '" + side + "' given twice");
                if (std::optional<Node> m = medium_value(o)) out.set(known->ours, *m);
            } else {
                unsupported(o, "unexpected <" + t + "> inside " + what);
            }
        }
        // Mitsuba gives an emitting shape without a bsdf a black diffuse one (it only emits), a
        // plain shape a 0.5 diffuse (our default material). Found by tests/python/test_mitsuba_scenes.py.
        if (emitter && !material) {
            Node black = make("lambertian", n);
            black.set("reflectance", num(0.0));
            material = black;
        }
        if (material) out.set("material", *material);
        if (emitter) out.set("emitter", *emitter);
        return out;
    }

    std::optional<Node> convert_area(pugi::xml_node n) {
        std::string type = attr(n, "type");
        if (type != "area") {
            unsupported(n, "emitter '" + type + "' cannot be attached to a shape (only 'area')");
            return std::nullopt;
        }
        Collected c = collect(n);
        const MitsubaPlugin& plugin = entry("emitter", "area");
        Node out = make(plugin.ours, n);
        map_params(out, c, "emitter plugin 'area'", plugin);
        no_objects(c, "emitter plugin 'area'");
        return out;
    }

    std::optional<Node> convert_light(pugi::xml_node n) {
        std::string type = attr(n, "type");
        std::string what = "emitter plugin '" + type + "'";
        if (type == "area") fail(n, "an 'area' emitter must be nested in a <shape>");
        const MitsubaPlugin* plugin = find_mitsuba_plugin("emitter", type);
        if (!plugin) {
            unsupported(n, "unsupported " + what);
            return std::nullopt;
        }
        Collected c = collect(n);
        Node out = make(plugin->ours, n);
        map_params(out, c, what, *plugin);
        no_objects(c, what);
        if (type == "envmap" && !out.find("filename")) fail(n, "envmap needs a 'filename'");
        return out;
    }

    // ---- sensor, film, sampler, integrator ------------------------------------------------------
    void convert_sensor(pugi::xml_node n) {
        std::string type = attr(n, "type");
        const MitsubaPlugin* plugin = find_mitsuba_plugin("sensor", type);
        if (!plugin) {
            unsupported(n, "unsupported sensor plugin '" + type + "' (known: " + mitsuba_known_plugins("sensor") + ")");
            return;
        }
        if (m_camera) fail(n, "more than one <sensor>");
        Collected c = collect(n);
        Node cam = make(plugin->ours, n);
        map_params(cam, c, "sensor plugin '" + type + "'", *plugin);
        for (pugi::xml_node o : c.objects) {
            std::string t = o.name();
            if (t == "film") convert_film(o);
            else if (t == "sampler") convert_sampler(o);
            else if (t == "medium" || (t == "ref" && lookup_ref(o).kind == "medium")) {
                if (cam.find("medium")) fail(o, "a sensor takes one medium");
                if (std::optional<Node> m = medium_value(o)) cam.set("medium", *m);
            } else unsupported(o, "unexpected <" + t + "> inside a sensor");
        }
        m_camera = cam;
    }

    void convert_film(pugi::xml_node n) {
        std::string type = attr(n, "type");
        const MitsubaPlugin* plugin = find_mitsuba_plugin("film", type);
        if (!plugin) {
            unsupported(n, "unsupported film plugin '" + type + "' (known: " + mitsuba_known_plugins("film") + ")");
            return;
        }
        Collected c = collect(n);
        Node film = Node::object();  // our film is not typed
        film.line = line(n);
        bool sample_border = false;
        if (Prop* sb = take(c, "sample_border")) {
            if (!sb->value.is_bool()) fail(sb->node, "film 'sample_border' must be a boolean");
            sample_border = sb->value.as_bool();
        }
        map_params(film, c, "film plugin '" + type + "'", *plugin);
        set_default(film, "width", Node::number(768, true));  // Mitsuba's defaults
        set_default(film, "height", Node::number(576, true));
        for (pugi::xml_node o : c.objects) {
            if (std::string(o.name()) != "rfilter") {
                unsupported(o, "unexpected <" + std::string(o.name()) + "> inside a film");
                continue;
            }
            std::string ft = attr(o, "type");
            std::string what = "rfilter plugin '" + ft + "'";
            const MitsubaPlugin* filter = find_mitsuba_plugin("rfilter", ft);
            if (!filter) {
                unsupported(o, "unsupported " + what + " (known: " + mitsuba_known_plugins("rfilter") + ")");
                continue;
            }
            Collected fc = collect(o);
            Node f = make(filter->ours, o);
            map_params(f, fc, what, *filter);
            no_objects(fc, what);
            // Mitsuba's Gaussian subtracts its value at the radius (docs/mitsuba-import.md).
            if (ft == "gaussian") f.set("shift", Node::boolean(true));
            film.set("filter", f);
        }
        if (!film.find("filter")) {  // Mitsuba's default rfilter
            Node f = make("gaussian", n);
            f.set("shift", Node::boolean(true));
            film.set("filter", f);
        }
        // Mitsuba splats every sample into all pixels within the filter radius; with sample_border it
        // also samples a border of one filter radius outside the film, so that a pixel at the edge
        // weighs the whole filter. Filter sampling has exactly that expectation: each pixel
        // integrates its full filter (pbrt-v4 §8.8), and its samples land in that pixel only.
        film.set("reconstruction", Node::string(sample_border ? "filter_sampling" : "splatting"));
        m_film = film;
    }

    void convert_sampler(pugi::xml_node n) {
        std::string type = attr(n, "type");
        const MitsubaPlugin* plugin = find_mitsuba_plugin("sampler", type);
        if (!plugin) {
            unsupported(n, "unsupported sampler plugin '" + type + "'");
            return;
        }
        // Mitsuba's stratified / low-discrepancy samplers become our Owen-scrambled Sobol sampler:
        // a different point set (docs/mitsuba-import.md), the same estimate in expectation.
        Collected c = collect(n);
        Node s = make(plugin->ours, n);
        map_params(s, c, "sampler plugin '" + type + "'", *plugin);
        set_default(s, "sample_count", Node::number(4, true));  // Mitsuba's default
        no_objects(c, "a sampler");
        m_sampler = s;
    }

    void convert_integrator(pugi::xml_node n) {
        std::string type = attr(n, "type");
        const MitsubaPlugin* plugin = find_mitsuba_plugin("integrator", type);
        if (!plugin) {
            unsupported(n, "unsupported integrator plugin '" + type + "' (known: " + mitsuba_known_plugins("integrator") +
                               ")");
            return;
        }
        Collected c = collect(n);
        Node it = make(plugin->ours, n);
        map_params(it, c, "integrator plugin '" + type + "'", *plugin);
        no_objects(c, "an integrator");
        m_integrator = it;
    }

    // ---- the scene ------------------------------------------------------------------------------
    void include(pugi::xml_node n, int depth) {
        std::string name = attr(n, "filename");
        if (depth >= kMaxIncludeDepth) fail(n, "includes nested deeper than 16 (a cycle?) at '" + name + "'");
        fs::path p(name);
        if (p.is_relative()) p = m_file->dir / p;
        std::ifstream in(p, std::ios::binary);
        if (!in) fail(n, "cannot open include file '" + p.string() + "'");
        std::stringstream ss;
        ss << in.rdbuf();
        const XmlFile* parent = m_file;
        XmlFile& f = load(ss.str(), p.string(), fs::absolute(p).parent_path(), n);
        pugi::xml_node root = scene_root(f);
        m_file = &f;
        check_version(root);
        parse_scene_children(root, depth + 1);
        m_file = parent;
    }

    void parse_scene_children(pugi::xml_node scene, int depth) {
        for (pugi::xml_node ch : scene.children()) {
            if (ch.type() != pugi::node_element) continue;
            std::string tag = ch.name();
            if (tag == "default") {
                std::string name = attr(ch, "name");
                pugi::xml_attribute v = ch.attribute("value");
                if (!v) fail(ch, "<default> needs a 'value' attribute");
                if (!m_params.count(name) && !m_defaults.count(name)) m_defaults[name] = v.value();
            } else if (tag == "include") {
                include(ch, depth);
            } else if (tag == "bsdf") {
                if (!ch.attribute("id")) {
                    log_warning(where(ch) + ": a top-level bsdf without an id cannot be used; ignored");
                    continue;
                }
                bsdf_value(ch);
            } else if (tag == "texture") {
                if (!ch.attribute("id")) {
                    log_warning(where(ch) + ": a top-level texture without an id cannot be used; ignored");
                    continue;
                }
                texture_value(ch);
            } else if (tag == "shape") {
                if (auto s = convert_shape(ch)) m_shapes.push_back(*s);
            } else if (tag == "emitter") {
                if (auto l = convert_light(ch)) m_lights.push_back(*l);
            } else if (tag == "sensor") {
                convert_sensor(ch);
            } else if (tag == "integrator") {
                if (m_integrator) fail(ch, "more than one <integrator>");
                convert_integrator(ch);
            } else if (tag == "medium") {
                if (!ch.attribute("id")) {
                    log_warning(where(ch) + ": a top-level medium without an id cannot be used; ignored");
                    continue;
                }
                medium_value(ch);
            } else if (tag == "phase") {
                unsupported(ch, "a <phase> belongs inside a <medium>");
            } else if (tag == "volume") {
                std::string type = ch.attribute("type").value();
                unsupported(ch, "volume textures (volume '" + type + "') are not supported; use a homogeneous medium");
            } else if (is_object_tag(tag) || is_property_tag(tag)) {
                unsupported(ch, "<" + tag + "> is not allowed at the top level of a scene");
            } else {
                unsupported(ch, "unknown element <" + tag + ">");
            }
        }
    }

    bool m_lenient;
    std::map<std::string, std::string> m_params, m_defaults;
    fs::path m_base_dir;
    std::deque<std::unique_ptr<XmlFile>> m_files;
    const XmlFile* m_file = nullptr;
    std::map<std::string, IdEntry> m_ids;
    int m_bsdf_depth = 0;  ///< nesting of bsdf_value calls

    std::optional<Node> m_camera, m_film, m_sampler, m_integrator;
    Node m_materials = Node::object();
    Node m_media = Node::object();
    Node m_shapes = Node::array();
    Node m_lights = Node::array();
};
}  // namespace

SceneDesc parse_mitsuba_xml(const std::string& text, const std::string& source, const std::string& base_dir,
                            bool lenient, const std::map<std::string, std::string>& params) {
    fs::path dir = base_dir.empty() ? fs::path(".") : fs::path(base_dir);
    return Converter(lenient, params, dir).run(text, source);
}

SceneDesc read_mitsuba_xml_file(const std::string& path, bool lenient,
                                const std::map<std::string, std::string>& params) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot open scene file (does it exist?)");
    std::stringstream ss;
    ss << in.rdbuf();
    return parse_mitsuba_xml(ss.str(), path, fs::absolute(path).parent_path().string(), lenient, params);
}
}  // namespace pellucid
