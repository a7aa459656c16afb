// JSON scene reader and writer through nlohmann_json.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/scene/json_io.h"

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "pellucid/util/error.h"
#include "pellucid/util/limits.h"

namespace pellucid {
namespace {
Node from_json(const nlohmann::ordered_json& j) {
    switch (j.type()) {
        case nlohmann::ordered_json::value_t::null: return Node();
        case nlohmann::ordered_json::value_t::boolean: return Node::boolean(j.get<bool>());
        case nlohmann::ordered_json::value_t::number_integer:
        case nlohmann::ordered_json::value_t::number_unsigned: return Node::number(j.get<double>(), true);
        case nlohmann::ordered_json::value_t::number_float: return Node::number(j.get<double>(), false);
        case nlohmann::ordered_json::value_t::string: return Node::string(j.get<std::string>());
        case nlohmann::ordered_json::value_t::array: {
            Node a = Node::array();
            for (const auto& e : j) a.push_back(from_json(e));
            return a;
        }
        case nlohmann::ordered_json::value_t::object: {
            Node o = Node::object();
            for (auto it = j.begin(); it != j.end(); ++it) o.set(it.key(), from_json(it.value()));
            return o;
        }
        default: return Node();
    }
}

nlohmann::ordered_json to_nl(const Node& n) {
    switch (n.kind()) {
        case Node::Kind::Null: return nullptr;
        case Node::Kind::Bool: return n.as_bool();
        case Node::Kind::Number:
            if (n.is_integer()) return int64_t(n.as_number());
            return n.as_number();
        case Node::Kind::String: return n.as_string();
        case Node::Kind::Array: {
            auto a = nlohmann::ordered_json::array();
            for (const auto& e : n.items()) a.push_back(to_nl(e));
            return a;
        }
        case Node::Kind::Object: {
            auto o = nlohmann::ordered_json::object();
            for (const auto& [k, v] : n.members()) o[k] = to_nl(v);
            return o;
        }
    }
    return nullptr;
}
}  // namespace

Node parse_json(const std::string& text, const std::string& source) {
    try {
        // ordered_json keeps key order, so error paths and to_json round trips follow the file.
        // The parser itself is iterative; from_json recurses, so the depth is bounded while parsing.
        const int limit = max_scene_depth();
        auto depth_check = [&](int depth, nlohmann::ordered_json::parse_event_t, nlohmann::ordered_json&) {
            if (depth > limit)
                throw Error(source + ": objects and arrays nested deeper than " + std::to_string(limit) +
                            " levels (the scene depth limit; raise it with PELLUCID_MAX_SCENE_DEPTH)");
            return true;
        };
        return from_json(nlohmann::ordered_json::parse(text, depth_check));
    } catch (const nlohmann::json::exception& e) {
        // parse_error (syntax) and out_of_range (a number such as 1e999 that overflows a double).
        std::string msg = e.what();
        auto pos = msg.find("] ");
        throw Error(source + ": malformed JSON: " + (pos == std::string::npos ? msg : msg.substr(pos + 2)));
    }
}

SceneDesc read_json_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot open scene file (does it exist?)");
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) throw Error(path + ": not a regular file (a directory?)");
    std::stringstream ss;
    ss << in.rdbuf();
    SceneDesc desc;
    desc.root = parse_json(ss.str(), path);
    desc.source = path;
    desc.base_dir = std::filesystem::absolute(path).parent_path().string();
    return desc;
}

std::string to_json(const Node& node, int indent) { return to_nl(node).dump(indent); }
}  // namespace pellucid
