// SceneDesc value tree.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/scene/scene_desc.h"

namespace pellucid {

void Node::set(const std::string& key, Node v) {
    for (auto& m : m_members)
        if (m.first == key) {
            m.second = std::move(v);
            return;
        }
    m_members.emplace_back(key, std::move(v));
}

const Node* Node::find(const std::string& key) const {
    for (const auto& m : m_members)
        if (m.first == key) return &m.second;
    return nullptr;
}

const char* Node::kind_name(Kind k) {
    switch (k) {
        case Kind::Null: return "null";
        case Kind::Bool: return "boolean";
        case Kind::Number: return "number";
        case Kind::String: return "string";
        case Kind::Array: return "array";
        case Kind::Object: return "object";
    }
    return "?";
}

std::string path_join(const std::string& path, const std::string& key) {
    return path.empty() ? key : path + "." + key;
}
std::string path_index(const std::string& path, size_t i) {
    return path + "[" + std::to_string(i) + "]";
}
}  // namespace pellucid
