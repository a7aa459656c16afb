// A density grid on the unit cube, with a majorant per coarse block for delta and ratio tracking.
// SPDX-License-Identifier: Apache-2.0
//
// Voxels are cell-centred: voxel (i, j, k) of an nx × ny × nz grid holds the density at
// ((i + ½)/nx, (j + ½)/ny, (k + ½)/nz), and density(p) interpolates trilinearly between the eight
// nearest voxel centres, clamped to the edge voxels inside [0, 1]³ (Mitsuba 3's gridvolume with
// its default filter does the same). Outside [0, 1]³ the density is 0.
//
// Majorants: the grid is split into blocks of kMajorantBlock³ voxels; a block's majorant is the
// largest value of any voxel that trilinear interpolation inside the block can reach (the block's
// voxels and the layer around it), so density(p) ≤ majorant(block of p) everywhere.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "pellucid/math/vec.h"

namespace pellucid {

class DensityGrid {
public:
    static constexpr int kMajorantBlock = 16;

    DensityGrid() = default;
    /// values[(k·ny + j)·nx + i] for voxel (i, j, k); every value finite and ≥ 0 (the builder checks).
    DensityGrid(int nx, int ny, int nz, std::vector<float> values);

    int nx() const { return m_n[0]; }
    int ny() const { return m_n[1]; }
    int nz() const { return m_n[2]; }
    const std::vector<float>& values() const { return m_values; }
    float max_value() const { return m_max; }

    /// Trilinear density at p in grid space ([0, 1]³); 0 outside.
    float density(const Vec3f& p) const;

    /// Coarse (majorant) grid: its size per axis, and each block's majorant.
    int coarse(int axis) const { return m_c[axis]; }
    float majorant(int cx, int cy, int cz) const { return m_major[(size_t(cz) * m_c[1] + cy) * m_c[0] + cx]; }

    /// A smoke-like procedural density: a rising plume (a column narrowing and fading upward,
    /// twisted by fractal value noise) with density in [0, 1], n³ voxels, deterministic in seed.
    static DensityGrid smoke(int n, uint32_t seed);
    /// Constant density value everywhere in [0, 1]³ (tests).
    static DensityGrid constant(int n, float value);

    std::string to_string() const;

private:
    void build_majorants();
    float voxel(int i, int j, int k) const { return m_values[(size_t(k) * m_n[1] + j) * m_n[0] + i]; }

    int m_n[3] = {0, 0, 0};
    int m_c[3] = {0, 0, 0};
    std::vector<float> m_values;
    std::vector<float> m_major;
    float m_max = 0.f;
};

/// Read a grid from Mitsuba's binary .vol format (the gridvolume format of Mitsuba 0.6 and 3):
///   bytes 0–2  'V' 'O' 'L';  byte 3  version, 3;
///   int32 encoding (1 = float32, the only one read here); int32 nx, ny, nz; int32 channels (1);
///   6 float32: a bounding box (ignored: the medium's to_world places the unit cube);
///   nx·ny·nz float32 values, x fastest, then y, then z; all little-endian.
/// Throws pellucid::Error naming the file for a bad header, size, or a negative or non-finite value.
DensityGrid read_vol_file(const std::string& path);
/// Write a grid in the same format (tests and tools).
void write_vol_file(const std::string& path, const DensityGrid& grid);
}  // namespace pellucid
