// OBJ (tinyobjloader's streaming callback parser; the only tinyobjloader user) and PLY (our own)
// mesh loading.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/geometry/mesh_io.h"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unordered_map>

#include "pellucid/util/error.h"
#include "pellucid/util/limits.h"
#include "pellucid/util/log.h"

namespace pellucid {
namespace {

/// A directory opens as a stream on Linux, and reading it throws from inside the standard library.
bool is_regular(const std::string& path) {
    std::error_code ec;
    return std::filesystem::is_regular_file(path, ec);
}

void finish(TriangleMesh& m, const MeshLoadOptions& opt) {
    if (opt.face_normals) m.normals.clear();
    else if (opt.smooth_normals && m.normals.empty() && !m.indices.empty()) m.compute_smooth_normals();
    if (opt.flip_tex_coords)
        for (Vec2f& uv : m.uvs) uv.y = 1.f - uv.y;
    // Size the vectors exactly when growth left much slack (polygons triangulated, OBJ sharing).
    auto fit = [](auto& v) {
        if (v.capacity() > v.size() + v.size() / 16) v.shrink_to_fit();
    };
    fit(m.positions);
    fit(m.normals);
    fit(m.uvs);
    fit(m.indices);
}

// ---- OBJ ----------------------------------------------------------------------------------------

struct ObjCorner {
    int v, t, n;
    bool operator==(const ObjCorner& o) const { return v == o.v && t == o.t && n == o.n; }
};
struct ObjCornerHash {
    size_t operator()(const ObjCorner& c) const {
        uint64_t h = uint64_t(uint32_t(c.v)) * 0x9E3779B97F4A7C15ull;
        h ^= (uint64_t(uint32_t(c.t)) + 0x632BE59BD9B4E019ull + (h << 6) + (h >> 2));
        h ^= (uint64_t(uint32_t(c.n)) + 0x85EBCA77C2B2AE63ull + (h << 6) + (h >> 2));
        return size_t(h);
    }
};

struct ObjState {
    std::vector<Vec3f> v, vn;
    std::vector<Vec2f> vt;
    ObjMesh out;
    std::vector<ObjCorner> corners;  // per output vertex (resolved, 0-based, -1 = none)
    std::unordered_map<ObjCorner, uint32_t, ObjCornerHash> shared;
    uint32_t material = ObjMesh::kNoMaterial;
    bool any_usemtl = false;
    size_t faces = 0;
    std::string error;
    const size_t max_elements = size_t(max_mesh_elements());

    /// False (with the error set) once `count` elements of kind `what` would pass the limit.
    bool within_limit(size_t count, const char* what) {
        if (count < max_elements) return true;
        if (error.empty())
            error = std::string("more than ") + std::to_string(max_elements) + " " + what +
                    " (the mesh element limit; raise it with PELLUCID_MAX_MESH_ELEMENTS)";
        return false;
    }

    // OBJ indices: 1-based, negative = relative to the end so far, 0 = absent.
    bool resolve(int raw, size_t count, const char* what, int& out_index) {
        if (raw == 0) {
            out_index = -1;
            return true;
        }
        long long i = raw > 0 ? (long long)raw - 1 : (long long)count + raw;
        if (i < 0 || i >= (long long)count) {
            if (error.empty())
                error = "face " + std::to_string(faces) + ": " + what + " index " + std::to_string(raw) +
                        " is out of range (" + std::to_string(count) + " defined so far)";
            return false;
        }
        out_index = int(i);
        return true;
    }

    void face(const tinyobj::index_t* idx, int n) {
        ++faces;
        if (!error.empty()) return;
        if (n < 3) {
            error = "face " + std::to_string(faces) + " has " + std::to_string(n) + " vertices (need >= 3)";
            return;
        }
        uint32_t ids[3];
        uint32_t first = 0, prev = 0;
        for (int k = 0; k < n; ++k) {
            ObjCorner c;
            if (idx[k].vertex_index == 0) {
                error = "face " + std::to_string(faces) + ": missing vertex index";
                return;
            }
            if (!resolve(idx[k].vertex_index, v.size(), "vertex", c.v) ||
                !resolve(idx[k].texcoord_index, vt.size(), "texture coordinate", c.t) ||
                !resolve(idx[k].normal_index, vn.size(), "normal", c.n))
                return;
            auto [it, inserted] = shared.emplace(c, uint32_t(corners.size()));
            if (inserted) {
                if (!within_limit(corners.size(), "vertices")) return;
                corners.push_back(c);
            }
            uint32_t id = it->second;
            // Fan triangulation: (0, k-1, k).
            if (k == 0) first = id;
            else if (k >= 2) {
                if (!within_limit(out.face_material.size(), "triangles")) return;
                ids[0] = first;
                ids[1] = prev;
                ids[2] = id;
                out.mesh.indices.insert(out.mesh.indices.end(), ids, ids + 3);
                out.face_material.push_back(material);
            }
            prev = id;
        }
    }

    void use_material(const char* name) {
        any_usemtl = true;
        auto it = std::find(out.material_names.begin(), out.material_names.end(), name);
        material = uint32_t(it - out.material_names.begin());
        if (it == out.material_names.end()) out.material_names.emplace_back(name);
    }
};
}  // namespace

ObjMesh load_obj(const std::string& path, const MeshLoadOptions& options) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot open OBJ file (does it exist?)");
    if (!is_regular(path)) throw Error(path + ": not a regular file (a directory?)");

    ObjState st;
    tinyobj::callback_t cb;
    cb.vertex_cb = [](void* u, tinyobj::real_t x, tinyobj::real_t y, tinyobj::real_t z, tinyobj::real_t) {
        auto* s = static_cast<ObjState*>(u);
        if (s->within_limit(s->v.size(), "vertex positions")) s->v.emplace_back(x, y, z);
    };
    cb.normal_cb = [](void* u, tinyobj::real_t x, tinyobj::real_t y, tinyobj::real_t z) {
        auto* s = static_cast<ObjState*>(u);
        if (s->within_limit(s->vn.size(), "normals")) s->vn.emplace_back(x, y, z);
    };
    cb.texcoord_cb = [](void* u, tinyobj::real_t x, tinyobj::real_t y, tinyobj::real_t) {
        auto* s = static_cast<ObjState*>(u);
        if (s->within_limit(s->vt.size(), "texture coordinates")) s->vt.emplace_back(x, y);
    };
    cb.index_cb = [](void* u, tinyobj::index_t* idx, int n) { static_cast<ObjState*>(u)->face(idx, n); };
    cb.usemtl_cb = [](void* u, const char* name, int) { static_cast<ObjState*>(u)->use_material(name); };

    std::string warn, err;
    bool ok = tinyobj::LoadObjWithCallback(in, cb, &st, nullptr, &warn, &err);
    if (!st.error.empty()) throw Error(path + ": " + st.error);
    if (!ok) throw Error(path + ": malformed OBJ: " + err);
    if (st.out.mesh.indices.empty()) throw Error(path + ": OBJ file has no faces");

    for (const Vec3f& p : st.v)
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            throw Error(path + ": non-finite vertex position");

    TriangleMesh& m = st.out.mesh;
    size_t nv = st.corners.size();
    bool all_n = true, any_n = false, all_t = true, any_t = false;
    for (const ObjCorner& c : st.corners) {
        all_n &= c.n >= 0;
        any_n |= c.n >= 0;
        all_t &= c.t >= 0;
        any_t |= c.t >= 0;
    }
    m.positions.reserve(nv);
    for (const ObjCorner& c : st.corners) m.positions.push_back(st.v[size_t(c.v)]);
    if (any_n && !all_n)
        log_warning(path + ": only some faces have normals; file normals ignored");
    if (all_n && !options.face_normals) {
        m.normals.reserve(nv);
        for (const ObjCorner& c : st.corners) m.normals.push_back(normalize(st.vn[size_t(c.n)]));
    }
    if (any_t) {
        if (!all_t) log_warning(path + ": only some faces have texture coordinates; the others get (0, 0)");
        m.uvs.reserve(nv);
        for (const ObjCorner& c : st.corners) m.uvs.push_back(c.t >= 0 ? st.vt[size_t(c.t)] : Vec2f(0.f));
    }
    if (!st.any_usemtl) st.out.face_material.clear();
    finish(m, options);
    if (st.out.face_material.capacity() > st.out.face_material.size() + st.out.face_material.size() / 16)
        st.out.face_material.shrink_to_fit();
    return std::move(st.out);
}

// ---- PLY ----------------------------------------------------------------------------------------
namespace {

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

bool ply_type(const std::string& s, PlyType& t) {
    static const std::pair<const char*, PlyType> kTypes[] = {
        {"char", PlyType::Int8},     {"int8", PlyType::Int8},     {"uchar", PlyType::UInt8},
        {"uint8", PlyType::UInt8},   {"short", PlyType::Int16},   {"int16", PlyType::Int16},
        {"ushort", PlyType::UInt16}, {"uint16", PlyType::UInt16}, {"int", PlyType::Int32},
        {"int32", PlyType::Int32},   {"uint", PlyType::UInt32},   {"uint32", PlyType::UInt32},
        {"float", PlyType::Float32}, {"float32", PlyType::Float32}, {"double", PlyType::Float64},
        {"float64", PlyType::Float64}};
    for (const auto& [name, type] : kTypes)
        if (s == name) {
            t = type;
            return true;
        }
    return false;
}

size_t ply_size(PlyType t) {
    switch (t) {
        case PlyType::Int8: case PlyType::UInt8: return 1;
        case PlyType::Int16: case PlyType::UInt16: return 2;
        case PlyType::Int32: case PlyType::UInt32: case PlyType::Float32: return 4;
        case PlyType::Float64: return 8;
    }
    return 0;
}

bool ply_is_integer(PlyType t) { return t != PlyType::Float32 && t != PlyType::Float64; }

struct PlyProperty {
    std::string name;
    PlyType type = PlyType::Float32;
    bool is_list = false;
    PlyType count_type = PlyType::UInt8;
};

struct PlyElement {
    std::string name;
    size_t count = 0;
    std::vector<PlyProperty> props;
    int line = 0;
};

enum class PlyFormat { Ascii, BinaryLE, BinaryBE };

/// Reads values of the data section: binary (with byte order) or ASCII tokens (tracking lines).
class PlyData {
public:
    PlyData(const std::string& path, const std::string& buf, size_t pos, PlyFormat fmt, int line)
        : m_path(path), m_buf(buf), m_pos(pos), m_fmt(fmt), m_line(line) {}

    void set_context(const PlyElement* e, size_t item) {
        m_elem = e;
        m_item = item;
    }

    double read(PlyType t) {
        if (m_fmt == PlyFormat::Ascii) return read_ascii(t);
        size_t n = ply_size(t);
        if (m_pos + n > m_buf.size()) fail("unexpected end of file (truncated)");
        unsigned char b[8];
        std::memcpy(b, m_buf.data() + m_pos, n);
        m_pos += n;
        if (m_fmt == PlyFormat::BinaryBE) std::reverse(b, b + n);  // our targets are little-endian
        switch (t) {
            case PlyType::Int8: { int8_t v; std::memcpy(&v, b, 1); return v; }
            case PlyType::UInt8: return b[0];
            case PlyType::Int16: { int16_t v; std::memcpy(&v, b, 2); return v; }
            case PlyType::UInt16: { uint16_t v; std::memcpy(&v, b, 2); return v; }
            case PlyType::Int32: { int32_t v; std::memcpy(&v, b, 4); return v; }
            case PlyType::UInt32: { uint32_t v; std::memcpy(&v, b, 4); return v; }
            case PlyType::Float32: { float v; std::memcpy(&v, b, 4); return v; }
            case PlyType::Float64: { double v; std::memcpy(&v, b, 8); return v; }
        }
        return 0.0;
    }

    [[noreturn]] void fail(const std::string& msg) const {
        std::string where = m_path;
        if (m_fmt == PlyFormat::Ascii) where += ":" + std::to_string(m_line);
        if (m_elem) where += ": element '" + m_elem->name + "' " + std::to_string(m_item);
        throw Error(where + ": " + msg);
    }

    int line() const { return m_line; }

private:
    double read_ascii(PlyType t) {
        while (m_pos < m_buf.size() && std::isspace(static_cast<unsigned char>(m_buf[m_pos]))) {
            if (m_buf[m_pos] == '\n') ++m_line;
            ++m_pos;
        }
        if (m_pos >= m_buf.size()) fail("unexpected end of file (truncated)");
        size_t start = m_pos;
        while (m_pos < m_buf.size() && !std::isspace(static_cast<unsigned char>(m_buf[m_pos]))) ++m_pos;
        std::string tok = m_buf.substr(start, m_pos - start);
        char* end = nullptr;
        errno = 0;
        double v = ply_is_integer(t) ? double(std::strtoll(tok.c_str(), &end, 10)) : std::strtod(tok.c_str(), &end);
        if (end != tok.c_str() + tok.size() || errno == ERANGE)
            fail("expected " + std::string(ply_is_integer(t) ? "an integer" : "a number") + ", got '" + tok + "'");
        return v;
    }

    const std::string& m_path;
    const std::string& m_buf;
    size_t m_pos;
    PlyFormat m_fmt;
    int m_line;
    const PlyElement* m_elem = nullptr;
    size_t m_item = 0;
};

int find_prop(const PlyElement& e, const char* name) {
    for (size_t i = 0; i < e.props.size(); ++i)
        if (!e.props[i].is_list && e.props[i].name == name) return int(i);
    return -1;
}
}  // namespace

TriangleMesh load_ply(const std::string& path, const MeshLoadOptions& options) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot open PLY file (does it exist?)");
    if (!is_regular(path)) throw Error(path + ": not a regular file (a directory?)");
    std::string buf((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());

    // ---- header ----
    size_t pos = 0;
    int line = 0;
    auto next_line = [&](std::string& out) {
        if (pos >= buf.size()) return false;
        size_t e = buf.find('\n', pos);
        if (e == std::string::npos) e = buf.size();
        out = buf.substr(pos, e - pos);
        if (!out.empty() && out.back() == '\r') out.pop_back();
        pos = std::min(e + 1, buf.size() + 1);
        ++line;
        return true;
    };
    auto header_fail = [&](const std::string& msg) -> void {
        throw Error(path + ":" + std::to_string(line) + ": " + msg);
    };
    std::string l;
    if (!next_line(l) || l != "ply") {
        line = 1;
        header_fail("not a PLY file (the first line must be 'ply')");
    }
    bool have_format = false, ended = false;
    PlyFormat fmt = PlyFormat::Ascii;
    std::vector<PlyElement> elems;
    while (next_line(l)) {
        std::istringstream ls(l);
        std::string kw;
        ls >> kw;
        if (kw.empty() || kw == "comment" || kw == "obj_info") continue;
        if (kw == "end_header") {
            ended = true;
            break;
        }
        if (kw == "format") {
            std::string f, ver;
            ls >> f >> ver;
            if (f == "ascii") fmt = PlyFormat::Ascii;
            else if (f == "binary_little_endian") fmt = PlyFormat::BinaryLE;
            else if (f == "binary_big_endian") fmt = PlyFormat::BinaryBE;
            else header_fail("unknown PLY format '" + f + "' (known: ascii, binary_little_endian, binary_big_endian)");
            if (ver != "1.0") header_fail("unsupported PLY version '" + ver + "' (expected 1.0)");
            have_format = true;
        } else if (kw == "element") {
            PlyElement e;
            long long count = -1;
            ls >> e.name >> count;
            if (e.name.empty() || !ls || count < 0) header_fail("malformed element line '" + l + "'");
            if (count > max_mesh_elements())
                header_fail("element '" + e.name + "' has " + std::to_string(count) + " items, more than the limit of " +
                            std::to_string(max_mesh_elements()) +
                            " (the mesh element limit; raise it with PELLUCID_MAX_MESH_ELEMENTS)");
            e.count = size_t(count);
            e.line = line;
            elems.push_back(e);
        } else if (kw == "property") {
            if (elems.empty()) header_fail("property before any element");
            PlyProperty p;
            std::string t;
            ls >> t;
            if (t == "list") {
                std::string ct, it;
                ls >> ct >> it >> p.name;
                p.is_list = true;
                if (!ply_type(ct, p.count_type)) header_fail("unsupported property type '" + ct + "'");
                if (!ply_type(it, p.type)) header_fail("unsupported property type '" + it + "'");
                if (!ply_is_integer(p.count_type)) header_fail("list count type must be an integer type, got '" + ct + "'");
            } else {
                ls >> p.name;
                if (!ply_type(t, p.type)) header_fail("unsupported property type '" + t + "'");
            }
            if (p.name.empty()) header_fail("malformed property line '" + l + "'");
            elems.back().props.push_back(p);
        } else {
            header_fail("unknown header keyword '" + kw + "'");
        }
    }
    if (!ended) header_fail("truncated header (no end_header)");
    if (!have_format) header_fail("missing 'format' line");

    const PlyElement* vert = nullptr;
    const PlyElement* face = nullptr;
    for (const PlyElement& e : elems) {
        if (e.name == "vertex") vert = &e;
        if (e.name == "face") face = &e;
    }
    if (!vert) throw Error(path + ": no 'vertex' element");
    if (!face || face->count == 0) throw Error(path + ": no faces (point clouds are not meshes)");
    int px = find_prop(*vert, "x"), py = find_prop(*vert, "y"), pz = find_prop(*vert, "z");
    if (px < 0 || py < 0 || pz < 0)
        throw Error(path + ":" + std::to_string(vert->line) + ": element 'vertex' needs properties x, y, z");
    int nx = find_prop(*vert, "nx"), ny = find_prop(*vert, "ny"), nz = find_prop(*vert, "nz");
    bool has_n = nx >= 0 && ny >= 0 && nz >= 0;
    int pu = -1, pv = -1;
    for (auto [u, v] : {std::pair<const char*, const char*>{"u", "v"}, {"s", "t"}, {"texture_u", "texture_v"},
                        {"texture_s", "texture_t"}}) {
        pu = find_prop(*vert, u);
        pv = find_prop(*vert, v);
        if (pu >= 0 && pv >= 0) break;
    }
    bool has_uv = pu >= 0 && pv >= 0;
    int pidx = -1;
    for (size_t i = 0; i < face->props.size(); ++i)
        if (face->props[i].is_list && (face->props[i].name == "vertex_indices" || face->props[i].name == "vertex_index"))
            pidx = int(i);
    if (pidx < 0)
        throw Error(path + ":" + std::to_string(face->line) +
                    ": element 'face' needs a list property 'vertex_indices' (or 'vertex_index')");
    if (!ply_is_integer(face->props[size_t(pidx)].type))
        throw Error(path + ":" + std::to_string(face->line) + ": face vertex indices must have an integer type");

    // ---- data ----
    // Every item takes at least a few bytes of the file (binary: its fixed-size properties and list
    // counts; ASCII: one character and a separator per value): a header that claims more items
    // than the data can hold is truncated, and is reported before any memory is reserved for it.
    {
        const size_t data_bytes = buf.size() - std::min(pos, buf.size());
        double need = 0.0;
        for (const PlyElement& e : elems) {
            size_t item = 0;
            for (const PlyProperty& p : e.props)
                item += fmt == PlyFormat::Ascii ? 1 : ply_size(p.is_list ? p.count_type : p.type);
            need += double(e.count) * double(item);
        }
        if (fmt == PlyFormat::Ascii) need = 2.0 * need - 1.0;
        if (need > double(data_bytes))
            throw Error(path + ": the header declares " + std::to_string(vert->count) + " vertices and " +
                        std::to_string(face->count) + " faces, more than the " + std::to_string(data_bytes) +
                        " bytes of data can hold (truncated file?)");
    }
    TriangleMesh m;
    m.positions.reserve(vert->count);
    if (has_n && !options.face_normals) m.normals.reserve(vert->count);
    if (has_uv) m.uvs.reserve(vert->count);
    m.indices.reserve(3 * face->count);
    PlyData data(path, buf, std::min(pos, buf.size()), fmt, line + 1);
    std::vector<double> vals;
    for (const PlyElement& e : elems) {
        bool is_vert = &e == vert, is_face = &e == face;
        if (e.props.empty()) continue;  // items without properties occupy no data
        vals.assign(e.props.size(), 0.0);
        for (size_t item = 0; item < e.count; ++item) {
            data.set_context(&e, item);
            for (size_t pi = 0; pi < e.props.size(); ++pi) {
                const PlyProperty& p = e.props[pi];
                if (!p.is_list) {
                    vals[pi] = data.read(p.type);
                    continue;
                }
                double cnt = data.read(p.count_type);
                if (cnt < 0) data.fail("negative list length");
                size_t n = size_t(cnt);
                if (!(is_face && int(pi) == pidx)) {
                    for (size_t k = 0; k < n; ++k) data.read(p.type);
                    continue;
                }
                if (n < 3) data.fail("face has " + std::to_string(n) + " vertices (need >= 3)");
                uint32_t first = 0, prev = 0;
                for (size_t k = 0; k < n; ++k) {
                    double iv = data.read(p.type);
                    if (iv < 0 || iv >= double(vert->count))
                        data.fail("vertex index " + std::to_string((long long)iv) + " is out of range [0, " +
                                  std::to_string(vert->count) + ")");
                    uint32_t id = uint32_t(iv);
                    if (k == 0) first = id;
                    else if (k >= 2) {
                        m.indices.push_back(first);
                        m.indices.push_back(prev);
                        m.indices.push_back(id);
                    }
                    prev = id;
                }
            }
            if (is_vert) {
                // Checked in double precision, before the conversion to the floats they are stored in.
                auto value = [&](int prop, const char* what) {
                    double v = vals[size_t(prop)];
                    if (!fits_float(v)) {
                        char text[32];
                        std::snprintf(text, sizeof text, "%g", v);
                        data.fail(std::string(what) + " " + e.props[size_t(prop)].name + " = " + text +
                                  " is not a finite number that fits a 32-bit float");
                    }
                    return float(v);
                };
                m.positions.emplace_back(value(px, "vertex position"), value(py, "vertex position"),
                                         value(pz, "vertex position"));
                if (has_n && !options.face_normals)
                    m.normals.emplace_back(value(nx, "normal"), value(ny, "normal"), value(nz, "normal"));
                if (has_uv) m.uvs.emplace_back(value(pu, "texture coordinate"), value(pv, "texture coordinate"));
            }
        }
    }
    finish(m, options);
    return m;
}

TriangleMesh load_mesh(const std::string& path, const MeshLoadOptions& options) {
    std::string ext = path.size() >= 4 ? path.substr(path.size() - 4) : "";
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == ".obj") return load_obj(path, options).mesh;
    if (ext == ".ply") return load_ply(path, options);
    throw Error(path + ": unknown mesh format (expected .obj or .ply)");
}

size_t mesh_memory_bytes(const TriangleMesh& m) {
    return m.positions.capacity() * sizeof(Point3f) + m.normals.capacity() * sizeof(Normal3f) +
           m.uvs.capacity() * sizeof(Vec2f) + m.indices.capacity() * sizeof(uint32_t);
}
}  // namespace pellucid
