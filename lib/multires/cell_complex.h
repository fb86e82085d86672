// CellComplex: a lattice of arbitrary topology (MacCracken & Joy; Ono et al. section 2):
// points, edges, faces (polygons of any size) and cells (closed sets of faces). It holds
// the locally subdivided levels of an octree lattice (Figure 3), whose cells next to the
// subdivided ones are no longer hexahedra, and their Catmull-Clark subdivisions.
//
// Storage is flat arrays (CSR), built once per step: faces as point loops with the edge
// between loop[i] and loop[i+1] beside each point, cells as face lists. A Catmull-Clark
// step's topology is computed from offsets alone (no search), so a step is linear time.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "multires/grid_complex.h"

namespace ffd {

struct CellComplex {
  std::int32_t num_points = 0;
  std::vector<std::array<std::int32_t, 2>> edges;
  std::vector<std::int32_t> face_offsets{0}, face_points, face_edges;  // face_edges[o + i]: loop[i] -> loop[i + 1]
  std::vector<std::int32_t> cell_offsets{0}, cell_faces;

  std::size_t num_faces() const { return face_offsets.size() - 1; }
  std::size_t num_cells() const { return cell_offsets.size() - 1; }
  /// The distinct points of cell c, in first-seen order.
  std::vector<std::int32_t> cell_points(std::size_t c) const;
  std::size_t bytes() const;
};

/// Level `grid` with the cells `subdivide` (flags per cell) subdivided by the octree rules
/// (Ono et al. Figure 3): each such cell becomes 8 hexahedra; a cell beside them keeps its
/// region, its faces shared with them split in four and its edges they split in two.
/// Points are named by their node at twice the grid's resolution (`nodes`).
CellComplex locally_subdivided(const GridComplex& grid, const std::vector<std::uint8_t>& subdivide,
                               std::vector<GridIndex>& nodes);

/// One Catmull-Clark volume step (Ono et al.'s appendix, with its boundary rules): the
/// finer complex, and `stencil` (fine points x coarse points) with fine = stencil * coarse.
CellComplex catmull_clark_step(const CellComplex& coarse, Eigen::SparseMatrix<double, Eigen::RowMajor>& stencil);

/// Why `complex` is not a valid lattice (a cell not closed: an edge of it in other than
/// two of its faces; a face in more than two cells), or empty.
std::string lattice_defect(const CellComplex& complex);

}  // namespace ffd
