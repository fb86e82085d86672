// Evaluating selections of mesh vertices and lattice points (DESIGN.md's shared grammar):
// indices, a sphere, a box, the nearest point, a file of indices, or a union of these.
// Selections are read and their files loaded with the script (script_values.h); what
// only the mesh or the lattice decides is checked here, with the selection's place.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "script/script_values.h"
#include "multires/octree_lattice.h"
#include "warp/lattice.h"

namespace ffd {

/// The mesh vertices (columns of `positions`) `selection` picks, sorted and unique.
/// \throw InputError (placed at the selection, the part or its file) for an index out of
/// range, a lattice index given for vertices, or an empty pick.
std::vector<std::uint32_t> select_vertices(const Selection& selection,
                                           const Eigen::Ref<const Eigen::Matrix3Xd>& positions);

/// The movable lattice points `selection` picks (by current position), as flat indices,
/// sorted. \throw InputError for an index out of range or not movable (naming the movable
/// range), a vertex index or file given for lattice points, or an empty pick.
std::vector<std::size_t> select_lattice_points(const Selection& selection, const Lattice& lattice);

/// The points of level `level` of an octree lattice `selection` picks (by shown
/// position, or by grid node [i, j, k] at that level), as point indices, sorted. Every
/// point of a level is movable. \throw InputError as select_lattice_points.
std::vector<std::size_t> select_octree_points(const Selection& selection, const OctreeLattice& lattice, int level);
/// The cells of grid level `level` of an octree lattice `selection` picks: by cell index
/// [i, j, k], or by the centroids of the cells as shown (`near`: the cell nearest the
/// point, which on a regular grid is the cell holding it). Cell indices, sorted.
std::vector<std::size_t> select_octree_cells(const Selection& selection, const OctreeLattice& lattice, int level);
/// "the corners of level 2's cells, grid nodes [i, j, k] in [0, 4]", for messages
/// (`resolution`: 2^level, or a local level's).
std::string octree_points_text(int level, int resolution);

/// Reads a selection file: one non-negative vertex index per line, '#' comments.
/// \throw InputError "file:line: ..." on anything else.
std::vector<std::uint32_t> read_index_file(const std::string& path);

}  // namespace ffd
