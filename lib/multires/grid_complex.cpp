#include "multires/grid_complex.h"

#include <algorithm>
#include <stdexcept>

namespace ffd {

std::size_t GridComplex::bytes() const {
  return cells.capacity() * sizeof(GridIndex) + points.capacity() * sizeof(GridIndex) +
         cell_index.capacity() * sizeof(std::int32_t) + point_index.capacity() * sizeof(std::int32_t);
}

namespace {

bool zyx_less(const GridIndex& a, const GridIndex& b) {
  if (a[2] != b[2]) return a[2] < b[2];
  if (a[1] != b[1]) return a[1] < b[1];
  return a[0] < b[0];
}

/// Fills `point_index` and `points`: every node that is a corner of a cell, in (k, j, i) order.
void index_points(GridComplex& g) {
  const long long nx = g.hi[0] - g.lo[0] + 1, ny = g.hi[1] - g.lo[1] + 1, nz = g.hi[2] - g.lo[2] + 1;
  std::vector<std::uint8_t> used(static_cast<std::size_t>(nx * ny * nz), 0);
  for (const GridIndex& c : g.cells)
    for (int corner = 0; corner < 8; ++corner) {
      const long long i = c[0] - g.lo[0] + (corner & 1), j = c[1] - g.lo[1] + ((corner >> 1) & 1),
                      k = c[2] - g.lo[2] + ((corner >> 2) & 1);
      used[static_cast<std::size_t>((k * ny + j) * nx + i)] = 1;
    }
  g.point_index.assign(used.size(), -1);
  g.points.clear();
  std::size_t flat = 0;
  for (long long k = 0; k < nz; ++k)
    for (long long j = 0; j < ny; ++j)
      for (long long i = 0; i < nx; ++i, ++flat)
        if (used[flat]) {
          g.point_index[flat] = static_cast<std::int32_t>(g.points.size());
          g.points.push_back({static_cast<int>(i) + g.lo[0], static_cast<int>(j) + g.lo[1], static_cast<int>(k) + g.lo[2]});
        }
}

/// The complex of `cells`, sorted by (k, j, i) and without duplicates.
GridComplex complex_of_sorted(int resolution, std::vector<GridIndex> cells) {
  GridComplex g;
  g.resolution = resolution;
  g.cells = std::move(cells);
  if (g.cells.empty()) {
    g.cell_index.clear();
    g.point_index.assign(1, -1);
    return g;
  }
  g.lo = g.hi = g.cells.front();
  for (const GridIndex& c : g.cells)
    for (int a = 0; a < 3; ++a) {
      if (c[a] < 0 || c[a] >= resolution) throw std::invalid_argument("grid cell outside the grid");
      g.lo[a] = std::min(g.lo[a], c[a]);
      g.hi[a] = std::max(g.hi[a], c[a]);
    }
  for (int a = 0; a < 3; ++a) ++g.hi[a];
  const long long nx = g.hi[0] - g.lo[0], ny = g.hi[1] - g.lo[1], nz = g.hi[2] - g.lo[2];
  g.cell_index.assign(static_cast<std::size_t>(nx * ny * nz), -1);
  for (std::size_t c = 0; c < g.cells.size(); ++c) {
    const GridIndex& x = g.cells[c];
    g.cell_index[static_cast<std::size_t>(((x[2] - g.lo[2]) * ny + (x[1] - g.lo[1])) * nx + (x[0] - g.lo[0]))] =
        static_cast<std::int32_t>(c);
  }
  index_points(g);
  return g;
}

}  // namespace

GridComplex make_grid_complex(int resolution, std::vector<GridIndex> cells) {
  std::sort(cells.begin(), cells.end(), zyx_less);
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  return complex_of_sorted(resolution, std::move(cells));
}

GridComplex refine(const GridComplex& coarse) {
  // The children in (k, j, i) order without sorting: the coarse cells come sorted, so per
  // row of coarse cells (same j and k) and child offsets c (k) and b (j), the children of
  // the row in order with a (i) = 0, 1 are one row of the fine grid; rows go by k, then c,
  // then j, then b.
  std::vector<GridIndex> children;
  children.reserve(coarse.cells.size() * 8);
  const std::vector<GridIndex>& cells = coarse.cells;
  for (std::size_t slab = 0; slab < cells.size();) {
    std::size_t slab_end = slab;
    while (slab_end < cells.size() && cells[slab_end][2] == cells[slab][2]) ++slab_end;
    for (int c = 0; c < 2; ++c)
      for (std::size_t row = slab; row < slab_end;) {
        std::size_t row_end = row;
        while (row_end < slab_end && cells[row_end][1] == cells[row][1]) ++row_end;
        for (int b = 0; b < 2; ++b)
          for (std::size_t p = row; p < row_end; ++p)
            for (int a = 0; a < 2; ++a)
              children.push_back({2 * cells[p][0] + a, 2 * cells[p][1] + b, 2 * cells[p][2] + c});
        row = row_end;
      }
    slab = slab_end;
  }
  return complex_of_sorted(coarse.resolution * 2, std::move(children));
}

}  // namespace ffd
