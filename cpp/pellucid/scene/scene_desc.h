// SceneDesc: the one scene IR. A plain JSON-shaped value tree that both syntaxes (JSON files and
// Python dicts; Mitsuba XML later) parse into; everything after parsing is shared.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace pellucid {

class Node {
public:
    enum class Kind { Null, Bool, Number, String, Array, Object };
    using Member = std::pair<std::string, Node>;

    Node() = default;
    static Node boolean(bool b) { Node n; n.m_kind = Kind::Bool; n.m_bool = b; return n; }
    static Node number(double v, bool is_integer = false) {
        Node n; n.m_kind = Kind::Number; n.m_number = v; n.m_integer = is_integer; return n;
    }
    static Node string(std::string s) { Node n; n.m_kind = Kind::String; n.m_string = std::move(s); return n; }
    static Node array() { Node n; n.m_kind = Kind::Array; return n; }
    static Node object() { Node n; n.m_kind = Kind::Object; return n; }

    Kind kind() const { return m_kind; }
    bool is_null() const { return m_kind == Kind::Null; }
    bool is_bool() const { return m_kind == Kind::Bool; }
    bool is_number() const { return m_kind == Kind::Number; }
    bool is_integer() const { return m_kind == Kind::Number && m_integer; }
    bool is_string() const { return m_kind == Kind::String; }
    bool is_array() const { return m_kind == Kind::Array; }
    bool is_object() const { return m_kind == Kind::Object; }

    bool as_bool() const { return m_bool; }
    double as_number() const { return m_number; }
    const std::string& as_string() const { return m_string; }
    const std::vector<Node>& items() const { return m_items; }
    const std::vector<Member>& members() const { return m_members; }

    void push_back(Node v) { m_items.push_back(std::move(v)); }
    /// Set (or replace) an object member; insertion order is kept.
    void set(const std::string& key, Node v);
    /// Member lookup; nullptr when absent.
    const Node* find(const std::string& key) const;
    /// Mutable access, for parameter updates (scene/scene_update.cpp).
    Node* find(const std::string& key) { return const_cast<Node*>(std::as_const(*this).find(key)); }
    Node& item(size_t i) { return m_items.at(i); }
    size_t size() const { return m_kind == Kind::Array ? m_items.size() : m_members.size(); }

    /// Source line (1-based) when known (XML import), else 0.
    int line = 0;

    static const char* kind_name(Kind k);
    const char* kind_name() const { return kind_name(m_kind); }

private:
    Kind m_kind = Kind::Null;
    bool m_bool = false;
    bool m_integer = false;
    double m_number = 0.0;
    std::string m_string;
    std::vector<Node> m_items;
    std::vector<Member> m_members;
};

/// A scene description: the root object plus the name of its source (file path or "<dict>"),
/// which prefixes every error message, and the directory relative paths are resolved against.
struct SceneDesc {
    Node root;
    std::string source = "<dict>";
    std::string base_dir = ".";
};

/// Join a key path: path_join("shapes[3]", "material") = "shapes[3].material".
std::string path_join(const std::string& path, const std::string& key);
std::string path_index(const std::string& path, size_t i);
}  // namespace pellucid
