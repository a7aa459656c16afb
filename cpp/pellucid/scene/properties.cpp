// Typed parameter access with key paths in every error.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/scene/properties.h"

#include <cmath>
#include <sstream>

#include "pellucid/scene/mitsuba_table.h"
#include "pellucid/util/error.h"
#include "pellucid/util/limits.h"
#include "pellucid/util/suggest.h"

namespace pellucid {

std::string format_error(const std::string& source, const std::string& path, const std::string& msg) {
    std::string s;
    if (!source.empty()) s += source + ": ";
    if (!path.empty()) s += path + ": ";
    return s + msg;
}

namespace {
/// A number as a user would write it (1e+39, not 1000000000000000044885712678075916785549312.000000).
std::string number_text(double v) {
    std::ostringstream os;
    os.precision(15);
    os << v;
    return os.str();
}
thread_local std::vector<ParameterRecord>* t_recorder = nullptr;

/// "unknown parameter", with a hint: what this type calls a Mitsuba parameter of the plugin it
/// imports from, else the nearest of the keys that the object's builder read.
std::string unknown_key_message(const Node& node, const std::set<std::string>& queried, const std::string& key) {
    const Node* t = node.find("type");
    const std::string type = t && t->is_string() ? t->as_string() : "";
    for (const MitsubaPlugin& plugin : mitsuba_import_table()) {
        if (type.empty() || type != plugin.ours) continue;
        for (const MitsubaParam& q : plugin.params) {
            if (key != q.mitsuba || key == q.ours) continue;
            if (q.use == MitsubaParamUse::ignored)
                return "unknown parameter (Mitsuba's '" + key + "' has no counterpart here)";
            return "unknown parameter (Mitsuba's '" + key + "' is " +
                   (q.use == MitsubaParamUse::converted ? "converted to '" : "'") + q.ours + "' here)";
        }
    }
    std::string hint = did_you_mean(key, std::vector<std::string>(queried.begin(), queried.end()));
    return hint.empty() ? "unknown parameter" : "unknown parameter (" + hint + ")";
}
}

void set_parameter_recorder(std::vector<ParameterRecord>* out) { t_recorder = out; }

Properties::Properties(const Node& node, std::string source, std::string path)
    : m_node(node), m_source(std::move(source)), m_path(std::move(path)) {
    if (!node.is_object())
        throw Error(format_error(m_source, m_path, std::string("expected an object, got a ") + node.kind_name()));
}

Properties::~Properties() {
    if (!t_recorder) return;
    try {
        ParameterRecord r{m_path, "", {}};
        if (const Node* t = m_node.find("type"); t && t->is_string()) r.type = t->as_string();
        std::set<std::string> keys = m_queried;
        keys.insert(m_tested.begin(), m_tested.end());
        r.keys.assign(keys.begin(), keys.end());
        t_recorder->push_back(std::move(r));
    } catch (...) {  // a destructor must not throw; a lost record only weakens a docs check
    }
}

void Properties::fail(const std::string& key, const std::string& msg) const {
    throw Error(format_error(m_source, key.empty() ? m_path : key_path(key), msg));
}

const Node* Properties::lookup(const std::string& key) {
    m_queried.insert(key);
    return m_node.find(key);
}

std::string Properties::type() {
    const Node* n = lookup("type");
    if (!n) fail("", "missing required key 'type'");
    if (!n->is_string()) fail("type", std::string("expected a string, got a ") + n->kind_name());
    return n->as_string();
}

float Properties::number_of(const Node& n, const std::string& key) {
    if (!n.is_number()) fail(key, std::string("expected a number, got a ") + n.kind_name());
    double v = n.as_number();
    if (!std::isfinite(v)) fail(key, "value " + std::to_string(v) + " is not finite");
    if (!fits_float(v)) fail(key, "value " + number_text(v) + " overflows a 32-bit float (largest: 3.4e38)");
    return float(v);
}

float Properties::get_float(const std::string& key, float def) {
    const Node* n = lookup(key);
    return n ? number_of(*n, key) : def;
}
float Properties::get_float(const std::string& key) {
    const Node* n = lookup(key);
    if (!n) fail("", "missing required key '" + key + "'");
    return number_of(*n, key);
}
int Properties::get_int(const std::string& key, int def) {
    const Node* n = lookup(key);
    if (!n) return def;
    if (!n->is_number()) fail(key, std::string("expected a number, got a ") + n->kind_name());
    double d = n->as_number();
    if (!std::isfinite(d) || d != std::floor(d))
        fail(key, "expected an integer, got " + number_text(d));
    if (std::fabs(d) > 2147483647.0)
        fail(key, "value " + number_text(d) + " is out of range (a 32-bit integer: at most 2147483647 in magnitude)");
    return int(d);
}
std::string Properties::get_choice(const std::string& key, const std::string& def, const std::string& what,
                                   std::initializer_list<const char*> known) {
    std::string v = get_string(key, def);
    std::string list;
    for (const char* k : known) {
        if (v == k) return v;
        list += (list.empty() ? "" : ", ") + std::string(k);
    }
    fail(key, "unknown " + what + " '" + v + "' (known: " + list + ")");
}

bool Properties::get_bool(const std::string& key, bool def) {
    const Node* n = lookup(key);
    if (!n) return def;
    if (!n->is_bool()) fail(key, std::string("expected a boolean, got a ") + n->kind_name());
    return n->as_bool();
}
std::string Properties::get_string(const std::string& key, const std::string& def) {
    const Node* n = lookup(key);
    if (!n) return def;
    if (!n->is_string()) fail(key, std::string("expected a string, got a ") + n->kind_name());
    return n->as_string();
}
std::string Properties::get_string(const std::string& key) {
    if (!has(key)) fail("", "missing required key '" + key + "'");
    return get_string(key, "");
}

Spectrum Properties::get_spectrum(const std::string& key, const Spectrum& def) {
    const Node* n = lookup(key);
    if (!n) return def;
    if (n->is_number()) return Spectrum(number_of(*n, key));
    if (n->is_array() && n->size() == 3) {
        Spectrum s;
        for (int i = 0; i < 3; ++i) s[i] = number_of(n->items()[i], key);
        return s;
    }
    fail(key, std::string("expected a number or an array of 3 numbers, got a ") + n->kind_name() +
                  (n->is_array() ? " of " + std::to_string(n->size()) + " elements" : ""));
}

Vec3f Properties::get_vec3(const std::string& key, const Vec3f& def) {
    const Node* n = lookup(key);
    if (!n) return def;
    if (!n->is_array() || n->size() != 3)
        fail(key, std::string("expected an array of 3 numbers, got a ") + n->kind_name());
    return Vec3f(number_of(n->items()[0], key), number_of(n->items()[1], key),
                 number_of(n->items()[2], key));
}
Vec3f Properties::get_vec3(const std::string& key) {
    if (!has(key)) fail("", "missing required key '" + key + "'");
    return get_vec3(key, Vec3f(0.f));
}

std::vector<float> Properties::get_float_array(const std::string& key) {
    const Node* n = lookup(key);
    if (!n) return {};
    if (!n->is_array()) fail(key, std::string("expected an array of numbers, got a ") + n->kind_name());
    std::vector<float> out;
    out.reserve(n->size());
    for (size_t i = 0; i < n->size(); ++i) {
        const Node& v = n->items()[i];
        if (!v.is_number() || !fits_float(v.as_number()))
            fail(path_index(key, i), "expected a finite number that fits a 32-bit float");
        out.push_back(float(v.as_number()));
    }
    return out;
}
std::vector<int64_t> Properties::get_int_array(const std::string& key) {
    const Node* n = lookup(key);
    if (!n) return {};
    if (!n->is_array()) fail(key, std::string("expected an array of integers, got a ") + n->kind_name());
    std::vector<int64_t> out;
    out.reserve(n->size());
    for (size_t i = 0; i < n->size(); ++i) {
        const Node& v = n->items()[i];
        if (!v.is_number() || v.as_number() != std::floor(v.as_number()))
            fail(path_index(key, i), "expected an integer");
        out.push_back(int64_t(v.as_number()));
    }
    return out;
}

const Node* Properties::get_node(const std::string& key) { return lookup(key); }

namespace {
Vec3f vec3_of(const Node& n, const std::string& src, const std::string& path) {
    if (!n.is_array() || n.size() != 3)
        throw Error(format_error(src, path, "expected an array of 3 numbers"));
    Vec3f v;
    for (int i = 0; i < 3; ++i) {
        const Node& c = n.items()[i];
        if (!c.is_number() || !fits_float(c.as_number()))
            throw Error(format_error(src, path, "expected finite numbers that fit a 32-bit float"));
        v[i] = float(c.as_number());
    }
    return v;
}

Transform transform_op(const Node& op, const std::string& src, const std::string& path) {
    if (!op.is_object() || op.size() != 1)
        throw Error(format_error(src, path, "expected an object with exactly one of translate, scale, "
                                            "rotate, look_at, matrix"));
    const auto& [name, v] = op.members()[0];
    std::string p = path_join(path, name);
    if (name == "translate") return Transform::translate(vec3_of(v, src, p));
    if (name == "scale") {
        if (v.is_number() && !fits_float(v.as_number()))
            throw Error(format_error(src, p, "expected a finite number that fits a 32-bit float"));
        Vec3f s = v.is_number() ? Vec3f(float(v.as_number())) : vec3_of(v, src, p);
        if (s.x == 0.f || s.y == 0.f || s.z == 0.f)
            throw Error(format_error(src, p, "scale must be non-zero, got " + to_string(s)));
        return Transform::scale(s);
    }
    if (name == "rotate") {
        Properties r(v, src, p);
        Vec3f axis = r.get_vec3("axis");
        float angle = r.get_float("angle");
        r.check_unqueried();
        if (length(axis) == 0.f) r.fail("axis", "rotation axis must be non-zero");
        return Transform::rotate(axis, angle);
    }
    if (name == "look_at") {
        Properties r(v, src, p);
        Vec3f o = r.get_vec3("origin"), t = r.get_vec3("target"), up = r.get_vec3("up", Vec3f(0, 1, 0));
        r.check_unqueried();
        if (length(t - o) == 0.f) r.fail("target", "target equals origin");
        if (!(length(up) > 0.f)) r.fail("up", "up vector " + to_string(up) + " is zero (or underflows a float)");
        if (!(length(cross(normalize(up), normalize(t - o))) >= 1e-6f))
            r.fail("up", "up is parallel to the view direction");
        return Transform::look_at(o, t, up);
    }
    if (name == "matrix") {
        if (!v.is_array() || v.size() != 16)
            throw Error(format_error(src, p, "expected 16 numbers (row-major 4x4)"));
        Mat4f m;
        for (int r = 0; r < 4; ++r)
            for (int c = 0; c < 4; ++c) {
                const Node& e = v.items()[r * 4 + c];
                if (!e.is_number() || !fits_float(e.as_number()))
                    throw Error(format_error(src, p, "expected finite numbers that fit a 32-bit float"));
                m[c][r] = float(e.as_number());
            }
        if (std::fabs(glm::determinant(m)) < 1e-12f)
            throw Error(format_error(src, p, "matrix is singular"));
        return Transform(m);
    }
    throw Error(format_error(src, path, "unknown transform operation '" + name +
                                            "' (expected translate, scale, rotate, look_at, matrix)"));
}
}  // namespace

Transform Properties::get_transform(const std::string& key) {
    const Node* n = lookup(key);
    if (!n) return Transform();
    std::string p = key_path(key);
    if (n->is_object()) return transform_op(*n, m_source, p);
    if (!n->is_array()) fail(key, std::string("expected a list of transform operations, got a ") + n->kind_name());
    if (n->size() == 16 && n->items()[0].is_number()) {
        Node op = Node::object();
        op.set("matrix", *n);
        return transform_op(op, m_source, p);
    }
    // Operations apply in order: the first one acts on the object first (as nested Mitsuba tags).
    Transform t;
    for (size_t i = 0; i < n->size(); ++i) t = transform_op(n->items()[i], m_source, path_index(p, i)) * t;
    return t;
}

float Properties::check_range(const std::string& key, float v, float lo, float hi) {
    if (!(v >= lo && v <= hi)) {
        std::ostringstream os;
        os << "value " << v << " is out of range [" << lo << ", " << hi << "]";
        fail(key, os.str());
    }
    return v;
}
void Properties::check_spectrum_range(const std::string& key, const Spectrum& s, float lo, float hi) {
    for (int i = 0; i < 3; ++i)
        if (!(s[i] >= lo && s[i] <= hi)) {
            std::ostringstream os;
            os << "value " << s.to_string() << " is out of range [" << lo << ", " << hi << "]";
            fail(key, os.str());
        }
}

void Properties::check_unqueried() const {
    for (const auto& [key, value] : m_node.members())
        if (!m_queried.count(key)) fail(key, unknown_key_message(m_node, m_queried, key));
}
}  // namespace pellucid
