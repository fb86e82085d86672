// StepGrid: C^k, the k-th Catmull-Clark subdivision of an octree level's grid, as the
// octree lattice reads it: which cells exist, and where each node's value is kept.
//
// Why: a level's C^k is not built as a GridComplex. Its topology is implied by
// the level's (every cell of C^k is a child of a child ... of a level cell, refine()), so
// building it whole (level 5 of a 38k-vertex bunny: 234k cells, 16 MB of dense indices,
// 25 ms) would undo the locality of a first move. Instead a node's value has a slot:
//   slot(n) = point(n >> k) * 8^k + (n mod 2^k),
// the block of the level point at n >> k, at the node's offset inside it. Every node of a
// cell of C^k has one slot: the cell lies in level cell c = cell >> k, and its corner n has
// n >> k in c + {0, 1}^3, a corner of c and so a level point. Distinct nodes get distinct
// slots. Slots of nodes in no cell are never used; blocks are 8^k slots long whatever the
// level's shape, so fields over the slots are allocated lazily (never-written pages are
// never touched). A cell of C^k is named by the slot of its first corner.
//
// A level of at most OctreeLattice::kBuiltLevelCells cells (whose first move needs most
// of C^k) builds its C^k as GridComplexes; a StepGrid over a built complex reads it
// instead, so the lattice has one way to read both.
#pragma once

#include <cstdint>

#include "multires/grid_complex.h"

namespace ffd {

struct StepGrid {
  const GridComplex* level = nullptr;  // the level's grid (C^0)
  const GridComplex* built = nullptr;  // C^k as a complex, when the level built it
  int k = 0;

  int resolution() const { return built ? built->resolution : level->resolution << k; }
  /// Slots (or points of `built`) a field over C^k holds.
  std::size_t num_points() const {
    return built ? built->num_points() : level->num_points() << (3 * k);
  }
  /// The slot of grid node n of C^k, or -1 when no level point owns it.
  std::int32_t point(const GridIndex& n) const {
    if (built) return built->point(n);
    const std::int32_t owner = level->point(n[0] >> k, n[1] >> k, n[2] >> k);
    if (owner < 0) return -1;
    const int mask = (1 << k) - 1;
    return (owner << (3 * k)) | ((n[2] & mask) << (2 * k)) | ((n[1] & mask) << k) | (n[0] & mask);
  }
  /// The grid node of slot p.
  GridIndex node(std::int32_t p) const {
    if (built) return built->points[static_cast<std::size_t>(p)];
    const GridIndex& owner = level->points[static_cast<std::size_t>(p >> (3 * k))];
    const int mask = (1 << k) - 1;
    return {(owner[0] << k) | (p & mask), (owner[1] << k) | ((p >> k) & mask), (owner[2] << k) | ((p >> (2 * k)) & mask)};
  }
  bool has_cell(int i, int j, int z) const {
    return built ? built->has_cell(i, j, z) : level->has_cell(i >> k, j >> k, z >> k);
  }
  /// The cell (i, j, z) of C^k, or -1 when it does not exist.
  std::int32_t cell(int i, int j, int z) const {
    if (built) return built->cell(i, j, z);
    return level->has_cell(i >> k, j >> k, z >> k) ? point({i, j, z}) : -1;
  }
  /// corner(cell, c) for every c. A cell whose corners all lie in its owner's block (no
  /// coordinate at the block's last node) has them at fixed offsets from its own slot.
  void corners(std::int32_t cell, std::int32_t out[8]) const {
    if (built) return built->corners(static_cast<std::size_t>(cell), out);
    const int mask = (1 << k) - 1;
    const GridIndex n = node(cell);
    if ((n[0] & mask) != mask && (n[1] & mask) != mask && (n[2] & mask) != mask) {
      for (int c = 0; c < 8; ++c) out[c] = cell + (c & 1) + (((c >> 1) & 1) << k) + (((c >> 2) & 1) << (2 * k));
      return;
    }
    for (int c = 0; c < 8; ++c) out[c] = point({n[0] + (c & 1), n[1] + ((c >> 1) & 1), n[2] + ((c >> 2) & 1)});
  }
  /// The slot of corner c (bit 0: +i, bit 1: +j, bit 2: +k) of cell `cell`.
  std::int32_t corner(std::int32_t cell, int c) const {
    if (built) return built->corner(static_cast<std::size_t>(cell), c);
    const GridIndex n = node(cell);
    return point({n[0] + (c & 1), n[1] + ((c >> 1) & 1), n[2] + ((c >> 2) & 1)});
  }
};

}  // namespace ffd
