// Density grids: trilinear lookup, block majorants, the procedural smoke and the .vol format.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/medium/density_grid.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>

#include "pellucid/util/error.h"

namespace pellucid {

DensityGrid::DensityGrid(int nx, int ny, int nz, std::vector<float> values) : m_values(std::move(values)) {
    m_n[0] = nx;
    m_n[1] = ny;
    m_n[2] = nz;
    PELLUCID_CHECK(nx > 0 && ny > 0 && nz > 0 && m_values.size() == size_t(nx) * ny * nz, "density grid size");
    build_majorants();
}

void DensityGrid::build_majorants() {
    const int B = kMajorantBlock;
    for (int a = 0; a < 3; ++a) m_c[a] = (m_n[a] + B - 1) / B;
    m_major.assign(size_t(m_c[0]) * m_c[1] * m_c[2], 0.f);
    m_max = 0.f;
    for (float v : m_values) m_max = std::max(m_max, v);
    // A point in block b interpolates voxels b·B − 1 … (b + 1)·B of each axis (cell-centred
    // voxels: the lower neighbour of the block's first half voxel lies in the block before).
    for (int cz = 0; cz < m_c[2]; ++cz)
        for (int cy = 0; cy < m_c[1]; ++cy)
            for (int cx = 0; cx < m_c[0]; ++cx) {
                float m = 0.f;
                const int c[3] = {cx, cy, cz};
                int lo[3], hi[3];
                for (int a = 0; a < 3; ++a) {
                    lo[a] = std::max(0, c[a] * B - 1);
                    hi[a] = std::min(m_n[a] - 1, (c[a] + 1) * B);
                }
                for (int k = lo[2]; k <= hi[2]; ++k)
                    for (int j = lo[1]; j <= hi[1]; ++j)
                        for (int i = lo[0]; i <= hi[0]; ++i) m = std::max(m, voxel(i, j, k));
                m_major[(size_t(cz) * m_c[1] + cy) * m_c[0] + cx] = m;
            }
}

float DensityGrid::density(const Vec3f& p) const {
    if (!(p.x >= 0.f && p.x <= 1.f && p.y >= 0.f && p.y <= 1.f && p.z >= 0.f && p.z <= 1.f)) return 0.f;
    int i0[3], i1[3];
    float t[3];
    for (int a = 0; a < 3; ++a) {
        const float f = p[a] * float(m_n[a]) - 0.5f;
        const float fl = std::floor(f);
        t[a] = f - fl;
        const int i = int(fl);
        i0[a] = std::clamp(i, 0, m_n[a] - 1);
        i1[a] = std::clamp(i + 1, 0, m_n[a] - 1);
    }
    auto lerp = [](float a, float b, float w) { return a + (b - a) * w; };
    const float c00 = lerp(voxel(i0[0], i0[1], i0[2]), voxel(i1[0], i0[1], i0[2]), t[0]);
    const float c10 = lerp(voxel(i0[0], i1[1], i0[2]), voxel(i1[0], i1[1], i0[2]), t[0]);
    const float c01 = lerp(voxel(i0[0], i0[1], i1[2]), voxel(i1[0], i0[1], i1[2]), t[0]);
    const float c11 = lerp(voxel(i0[0], i1[1], i1[2]), voxel(i1[0], i1[1], i1[2]), t[0]);
    return std::max(0.f, lerp(lerp(c00, c10, t[1]), lerp(c01, c11, t[1]), t[2]));
}

namespace {
// Value noise: a hashed lattice value in [0, 1) per integer point, smoothly interpolated.
float lattice(int x, int y, int z, uint32_t seed) {
    uint32_t h = uint32_t(x) * 0x8da6b343u ^ uint32_t(y) * 0xd8163841u ^ uint32_t(z) * 0xcb1ab31fu ^ seed * 0x9e3779b9u;
    h ^= h >> 16;
    h *= 0x7feb352du;
    h ^= h >> 15;
    h *= 0x846ca68bu;
    h ^= h >> 16;
    return float(h >> 8) * 0x1p-24f;
}
float value_noise(const Vec3f& p, uint32_t seed) {
    const Vec3f f = glm::floor(p);
    const Vec3f t = p - f;
    const Vec3f s = t * t * (Vec3f(3.f) - 2.f * t);  // smoothstep weights
    const int x = int(f.x), y = int(f.y), z = int(f.z);
    float v = 0.f;
    for (int c = 0; c < 8; ++c) {
        const int dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
        const float w = (dx ? s.x : 1.f - s.x) * (dy ? s.y : 1.f - s.y) * (dz ? s.z : 1.f - s.z);
        v += w * lattice(x + dx, y + dy, z + dz, seed);
    }
    return v;
}
float fbm(Vec3f p, uint32_t seed) {
    float sum = 0.f, amp = 0.5f;
    for (int o = 0; o < 4; ++o, p *= 2.03f, amp *= 0.5f) sum += amp * value_noise(p, seed + uint32_t(o));
    return sum / 0.9375f;  // the amplitudes' sum: the result lies in [0, 1)
}
}  // namespace

DensityGrid DensityGrid::smoke(int n, uint32_t seed) {
    std::vector<float> v(size_t(n) * n * n);
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const Vec3f p((i + 0.5f) / n, (j + 0.5f) / n, (k + 0.5f) / n);
                // A column along +y that widens and thins upward, its axis pushed around by noise.
                const float y = p.y;
                const float wob = 0.18f * y * (fbm(Vec3f(0.f, 3.f * y, 1.7f), seed) - 0.5f);
                const float dx = p.x - 0.5f - wob, dz = p.z - 0.5f + 0.6f * wob;
                const float radius = 0.08f + 0.3f * y;
                const float r = std::sqrt(dx * dx + dz * dz) / radius;
                const float shape = std::max(0.f, 1.f - r * r) * std::sqrt(std::max(0.f, 1.f - y)) *
                                    std::min(1.f, 8.f * y);
                const float detail = fbm(p * 6.f + Vec3f(0.f, -2.f * y, 0.f), seed + 17u);
                v[(size_t(k) * n + j) * n + i] = std::clamp(shape * (1.6f * detail - 0.2f), 0.f, 1.f);
            }
    return DensityGrid(n, n, n, std::move(v));
}

DensityGrid DensityGrid::constant(int n, float value) {
    return DensityGrid(n, n, n, std::vector<float>(size_t(n) * n * n, value));
}

std::string DensityGrid::to_string() const {
    return "DensityGrid[" + std::to_string(m_n[0]) + "x" + std::to_string(m_n[1]) + "x" + std::to_string(m_n[2]) +
           ", max=" + std::to_string(m_max) + "]";
}

namespace {
constexpr size_t kVolHeader = 48;
int32_t read_i32(const char* p) {
    int32_t v;
    std::memcpy(&v, p, 4);
    return v;
}
}  // namespace

DensityGrid read_vol_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot open the grid file (does it exist?)");
    std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (bytes.size() < kVolHeader || std::memcmp(bytes.data(), "VOL", 3) != 0)
        throw Error(path + ": not a .vol grid file (it must start with 'VOL' and a 48-byte header)");
    if (bytes[3] != 3) throw Error(path + ": .vol version " + std::to_string(int(bytes[3])) + " is not supported (only 3)");
    const int32_t enc = read_i32(&bytes[4]);
    if (enc != 1) throw Error(path + ": .vol encoding " + std::to_string(enc) + " is not supported (only 1, float32)");
    const int32_t nx = read_i32(&bytes[8]), ny = read_i32(&bytes[12]), nz = read_i32(&bytes[16]), ch = read_i32(&bytes[20]);
    if (ch != 1) throw Error(path + ": the grid has " + std::to_string(ch) + " channels; a density grid needs 1");
    constexpr int64_t kMaxVoxels = int64_t(1) << 30;
    if (nx < 1 || ny < 1 || nz < 1 || int64_t(nx) * ny * nz > kMaxVoxels)
        throw Error(path + ": grid size " + std::to_string(nx) + "x" + std::to_string(ny) + "x" + std::to_string(nz) +
                    " is invalid (each axis >= 1, at most 2^30 voxels)");
    const size_t count = size_t(nx) * ny * nz;
    if (bytes.size() != kVolHeader + 4 * count)
        throw Error(path + ": the file holds " + std::to_string(bytes.size()) + " bytes; a " + std::to_string(nx) + "x" +
                    std::to_string(ny) + "x" + std::to_string(nz) + " float32 grid needs " +
                    std::to_string(kVolHeader + 4 * count));
    std::vector<float> v(count);
    std::memcpy(v.data(), &bytes[kVolHeader], 4 * count);
    for (size_t i = 0; i < count; ++i)
        if (!std::isfinite(v[i]) || v[i] < 0.f)
            throw Error(path + ": voxel " + std::to_string(i) + " has density " + std::to_string(v[i]) +
                        "; densities must be finite and >= 0");
    return DensityGrid(nx, ny, nz, std::move(v));
}

void write_vol_file(const std::string& path, const DensityGrid& g) {
    std::ofstream out(path, std::ios::binary);
    if (!out) throw Error(path + ": cannot write the grid file");
    const int32_t head[5] = {1, g.nx(), g.ny(), g.nz(), 1};
    const float box[6] = {0.f, 0.f, 0.f, 1.f, 1.f, 1.f};
    out.write("VOL\x03", 4);
    out.write(reinterpret_cast<const char*>(head), sizeof head);
    out.write(reinterpret_cast<const char*>(box), sizeof box);
    out.write(reinterpret_cast<const char*>(g.values().data()), std::streamsize(4 * g.values().size()));
    if (!out) throw Error(path + ": writing the grid file failed");
}
}  // namespace pellucid
