// The quality guard of volume meshes: each 3D cell's signed volume and the minimum
// scaled Jacobian at its corners, and the inverted cells among them.
//
// Definitions (the choices are ours where the literature varies):
// - A corner's scaled Jacobian is det[e1 e2 e3] / (|e1| |e2| |e3|) for the three edges
//   leaving it in the order of the cell's reference shape (VTK's parametric coordinates,
//   so a cell as VTK orders it scores > 0), divided by the same value on the ideal cell
//   (regular tetrahedron, cube, equilateral wedge, pyramid with equal edges), so an ideal
//   cell scores 1 at every corner. The pyramid's apex has four edges: it counts as the
//   four corners of consecutive edge triples. This is Verdict's scaled Jacobian without
//   its centre term.
// - The signed volume: a tetrahedron's determinant / 6; other cells by the divergence
//   theorem over their faces, each face fanned into triangles around its centroid;
//   a polyhedron (VTK 42, OpenFOAM cells) the same over its own faces.
// - A cell is inverted when its volume or any corner's scaled Jacobian is ≤ 0; a
//   polyhedron when its volume or any of its face pyramids' tetrahedra (cell centroid,
//   face centroid, edge: OpenFOAM's checkMesh decomposition) is ≤ 0, and its scaled
//   Jacobian is the lowest of those tetrahedra's, as a tetrahedron's.
// - Quadratic cells are judged by their corner nodes; 0D, 1D, 2D cells and kinds ffdtool
//   only carries are not checked.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "mesh/volume_mesh.h"

namespace ffd {

/// One cell's measures.
struct CellMeasure {
  std::uint64_t cell = 0;        // index into VolumeCells
  double scaled_jacobian = 1;    // the minimum over its corners
  double volume = 0;             // signed
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // mean of its corner nodes
};

/// The guard's verdict on a mesh at some positions.
struct CellQuality {
  std::size_t checked = 0;       // 3D cells measured
  std::size_t inverted = 0;      // volume or a corner ≤ 0
  double min_scaled_jacobian = 1;  // over the checked cells (1 when there are none)
  std::vector<CellMeasure> worst;  // the lowest scaled Jacobians, lowest first, ties by cell
  std::uint64_t first_inverted = 0;  // the lowest inverted cell index, if inverted > 0
};

/// Whether cell c is one the guard measures (a 3D cell of a known kind).
bool measured_cell(const VolumeCells& cells, std::size_t c);

/// Cell c's measures at `positions` (3 × nodes). \pre measured_cell(cells, c).
CellMeasure measure_cell(const VolumeCells& cells, std::size_t c, const Eigen::Matrix3Xd& positions);

/// Whether a measure is an inverted (or degenerate) cell.
inline bool inverted(const CellMeasure& m) { return !(m.volume > 0) || !(m.scaled_jacobian > 0); }

/// Measures every 3D cell, in parallel; the result does not depend on the thread count.
/// `worst` cells are kept (0: none).
CellQuality cell_quality(const VolumeCells& cells, const Eigen::Matrix3Xd& positions, std::size_t worst = 5);

/// The last verdict's positions and its per-block parts (the cells in fixed blocks).
struct CellQualityCache {
  Eigen::Matrix3Xd positions;
  std::vector<CellQuality> blocks;
  std::size_t worst = 0;
};

/// The same, measuring again only the blocks of cells with a node that moved since the
/// verdict in `cache` (all of them when it is empty); `cache` becomes this verdict's.
/// The result is cell_quality's, bit for bit: a block's verdict depends on its cells only.
CellQuality cell_quality(const VolumeCells& cells, const Eigen::Matrix3Xd& positions, CellQualityCache& cache,
                         std::size_t worst = 5);

}  // namespace ffd
