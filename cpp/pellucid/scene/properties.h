// Properties: typed, path-aware access to one object of the scene description. Every key that a
// builder does not read is an error ("materials.gold.roughnes: unknown parameter"), so typos never
// pass silently (Mitsuba 3 properties.h does the same).
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <initializer_list>
#include <set>
#include <string>
#include <vector>

#include "pellucid/math/spectrum.h"
#include "pellucid/math/transform.h"
#include "pellucid/math/vec.h"
#include "pellucid/scene/scene_desc.h"

namespace pellucid {

/// What one builder asked of its Properties: the object's key path, its "type" ("" if none) and
/// every key it read or tested with has(), present or not. Collected only while a recorder is set;
/// the documentation check (tests/python/test_docs.py) compares these keys with docs/scene-format.md.
struct ParameterRecord {
    std::string path, type;
    std::vector<std::string> keys;
};
/// While `out` is set (on this thread), every Properties object appends its record when destroyed.
/// Pass nullptr to stop. Build time only; nothing is recorded otherwise.
void set_parameter_recorder(std::vector<ParameterRecord>* out);

class Properties {
public:
    /// `source` is the file name ("<dict>" for dicts); `path` the key path of this object.
    Properties(const Node& node, std::string source, std::string path);
    ~Properties();
    Properties(const Properties&) = delete;
    Properties& operator=(const Properties&) = delete;

    const std::string& path() const { return m_path; }
    const std::string& source() const { return m_source; }
    bool has(const std::string& key) const {
        m_tested.insert(key);
        return m_node.find(key) != nullptr;
    }
    /// The "type" key (required).
    std::string type();

    float get_float(const std::string& key, float def);
    float get_float(const std::string& key);  // required
    int get_int(const std::string& key, int def);
    bool get_bool(const std::string& key, bool def);
    std::string get_string(const std::string& key, const std::string& def);
    std::string get_string(const std::string& key);
    /// A scalar (grey) or a 3-element array.
    Spectrum get_spectrum(const std::string& key, const Spectrum& def);
    Vec3f get_vec3(const std::string& key, const Vec3f& def);
    Vec3f get_vec3(const std::string& key);
    /// Transform as a list of operations applied in order, or a 16-number row-major matrix.
    Transform get_transform(const std::string& key);
    std::vector<float> get_float_array(const std::string& key);
    std::vector<int64_t> get_int_array(const std::string& key);
    /// A string that must be one of `known`; otherwise "unknown <what> 'v' (known: a, b)".
    std::string get_choice(const std::string& key, const std::string& def, const std::string& what,
                           std::initializer_list<const char*> known);
    /// Raw child node (marked as read); nullptr if absent.
    const Node* get_node(const std::string& key);

    /// Range checks with errors naming the key and value.
    float check_range(const std::string& key, float v, float lo, float hi);
    void check_spectrum_range(const std::string& key, const Spectrum& s, float lo, float hi);

    /// Throw for any key that was never read.
    void check_unqueried() const;
    [[noreturn]] void fail(const std::string& key, const std::string& msg) const;
    std::string key_path(const std::string& key) const { return path_join(m_path, key); }

private:
    const Node* lookup(const std::string& key);
    float number_of(const Node& n, const std::string& key);

    const Node& m_node;
    std::string m_source, m_path;
    std::set<std::string> m_queried;
    mutable std::set<std::string> m_tested;  ///< keys passed to has(), for the parameter record
};

/// "file: path: msg" (file omitted when empty).
std::string format_error(const std::string& source, const std::string& path, const std::string& msg);
}  // namespace pellucid
