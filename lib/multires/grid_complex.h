// GridComplex: a lattice of hexahedral cells taken from a regular grid (Ono et al.'s
// octree subdivision lattices, and their Catmull-Clark subdivisions).
//
// Why this structure: an octree lattice without local subdivision, and every
// Catmull-Clark subdivision of it, is a set of cells of one regular grid (a step doubles
// the resolution; every new cell is a hexahedron, since every point has valence 3). So a
// cell is its integer index, a point its grid node, and edges and faces are implied by
// the indices: adjacency is one array lookup, and nothing but the cell list, a dense
// index over the complex's bounding range and the positions is stored (see
// `bytes()`; the paper's LEDS needs ~600 B per cell, this ~45 B on a full grid).
//
// Promises: `cells` and `points` are sorted by (k, j, i); a point is a grid node that is
// a corner of at least one cell; indices of cells and points are positions in those lists.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace ffd {

using GridIndex = std::array<int, 3>;

struct GridComplex {
  int resolution = 1;              // cells per axis of the whole grid (2^level)
  GridIndex lo{0, 0, 0};           // the cells' bounding range is [lo, hi)
  GridIndex hi{0, 0, 0};
  std::vector<GridIndex> cells;    // cell (i, j, k) spans nodes (i..i+1, j..j+1, k..k+1)
  std::vector<GridIndex> points;   // grid nodes
  std::vector<std::int32_t> cell_index;   // dense over [lo, hi): index in `cells`, or -1
  std::vector<std::int32_t> point_index;  // dense over [lo, hi]: index in `points`, or -1

  /// Index of cell (i, j, k), or -1 when it is not in the complex.
  std::int32_t cell(int i, int j, int k) const {
    if (i < lo[0] || j < lo[1] || k < lo[2] || i >= hi[0] || j >= hi[1] || k >= hi[2]) return -1;
    const long long nx = hi[0] - lo[0], ny = hi[1] - lo[1];
    return cell_index[static_cast<std::size_t>(((k - lo[2]) * ny + (j - lo[1])) * nx + (i - lo[0]))];
  }
  bool has_cell(int i, int j, int k) const { return cell(i, j, k) >= 0; }
  /// Index of grid node (i, j, k), or -1 when it is no cell's corner.
  std::int32_t point(int i, int j, int k) const {
    if (i < lo[0] || j < lo[1] || k < lo[2] || i > hi[0] || j > hi[1] || k > hi[2]) return -1;
    const long long nx = hi[0] - lo[0] + 1, ny = hi[1] - lo[1] + 1;
    return point_index[static_cast<std::size_t>(((k - lo[2]) * ny + (j - lo[1])) * nx + (i - lo[0]))];
  }
  std::int32_t point(const GridIndex& n) const { return point(n[0], n[1], n[2]); }
  /// The point index of corner c (bit 0: +i, bit 1: +j, bit 2: +k) of cell `cell`.
  std::int32_t corner(std::size_t cell, int c) const {
    const GridIndex& g = cells[cell];
    return point(g[0] + (c & 1), g[1] + ((c >> 1) & 1), g[2] + ((c >> 2) & 1));
  }
  /// corner(cell, c) for every c: the corners of a cell are nodes of the dense range, so
  /// their indices are read at fixed offsets from the first's.
  void corners(std::size_t cell, std::int32_t out[8]) const {
    const GridIndex& g = cells[cell];
    const long long nx = hi[0] - lo[0] + 1, ny = hi[1] - lo[1] + 1;
    const std::int32_t* first = point_index.data() + ((g[2] - lo[2]) * ny + (g[1] - lo[1])) * nx + (g[0] - lo[0]);
    for (int c = 0; c < 8; ++c) out[c] = first[(c & 1) + ((c >> 1) & 1) * nx + ((c >> 2) & 1) * nx * ny];
  }
  std::size_t num_cells() const { return cells.size(); }
  std::size_t num_points() const { return points.size(); }
  /// Bytes held by the topology (cells, points, dense indices).
  std::size_t bytes() const;
};

/// The cell, of a grid with `resolution` cells per axis over the unit cube, that holds
/// box coordinates t (points outside are clamped to the nearest cell).
inline GridIndex grid_cell_at(const Eigen::Vector3d& t, int resolution) {
  GridIndex c;
  for (int a = 0; a < 3; ++a) c[a] = std::clamp(static_cast<int>(std::floor(t[a] * resolution)), 0, resolution - 1);
  return c;
}

/// Index of cell c in a dense array over every cell of a grid with `resolution` per axis.
inline std::size_t dense_cell(const GridIndex& c, int resolution) {
  return (static_cast<std::size_t>(c[2]) * resolution + c[1]) * resolution + c[0];
}

/// The complex of the given cells of a grid with `resolution` cells per axis. Duplicates
/// are merged. \throw std::invalid_argument for a cell outside [0, resolution).
GridComplex make_grid_complex(int resolution, std::vector<GridIndex> cells);

/// The complex whose cells are the 8 children of every cell of `coarse`, at twice the
/// resolution: the connectivity both octree and Catmull-Clark subdivision produce
/// (reconnection rules (1)-(3) of Ono et al. section 2.1 and of the appendix).
GridComplex refine(const GridComplex& coarse);

/// The complex of the cells of `complex` for which `keep(cell index)` is true.
template <class Keep>
GridComplex sub_complex(const GridComplex& complex, Keep keep) {
  std::vector<GridIndex> kept;
  for (std::size_t c = 0; c < complex.cells.size(); ++c)
    if (keep(c)) kept.push_back(complex.cells[c]);
  return make_grid_complex(complex.resolution, std::move(kept));
}

}  // namespace ffd
