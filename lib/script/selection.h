// Evaluating selections of mesh vertices and control points (docs/script-reference.md):
// indices, a sphere, a box, the nearest point, a file of indices, or a union of these.
// Selections are read and their files loaded with the script (script_values.h); what
// only the mesh or the lattice decides is checked here, with the selection's place.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "mesh/volume_mesh.h"
#include "script/script_checks.h"
#include "script/script_values.h"
#include "multires/octree_lattice.h"
#include "warp/deformer.h"

namespace ffd {

/// The mesh vertices (columns of `positions`) `selection` picks, sorted and unique; a
/// `marker` part picks the nodes of `volume`'s marker of that name.
/// \throw InputError (placed at the selection, the part or its file) for an index out of
/// range, a lattice index given for vertices, a marker the mesh does not have, or an
/// empty pick.
std::vector<std::uint32_t> select_vertices(const Selection& selection,
                                           const Eigen::Ref<const Eigen::Matrix3Xd>& positions,
                                           const VolumeSource* volume = nullptr);

/// The movable points of level `level` of a deformer that `selection` picks (by current
/// position, or by index: [i, j, k] on grids), as point ids, sorted. \throw InputError for
/// an index with no movable point (naming which are movable), a vertex index or file given
/// for control points, or an empty pick.
std::vector<std::size_t> select_points(const Selection& selection, const Deformer& deformer, int level);

/// The cells of grid level `level` of an octree lattice `selection` picks: by cell index
/// [i, j, k], or by the centroids of the cells as shown (`near`: the cell nearest the
/// point, which on a regular grid is the cell holding it). Cell indices, sorted.
std::vector<std::size_t> select_octree_cells(const Selection& selection, const OctreeLattice& lattice, int level);
/// What the script alone decides about a selection, checked before any work with the
/// messages and places the run would give (the run still checks what only the mesh or the
/// lattice decides: vertex counts, an octree's cut cells). Of control points of level
/// `level` of a deformer of `shape`: each index's form and whether it may be movable, and
/// no file. \throw InputError at the first fault.
void check_point_selection(const Selection& selection, const DeformerShape& shape, int level);
/// Of the cells of octree grid level `level` (2^level cells per axis): [i, j, k] in range, no file.
void check_cell_selection(const Selection& selection, int level);
/// Of mesh vertices: no lattice index.
void check_vertex_selection(const Selection& selection);

/// Reads a selection file: one non-negative vertex index per line, '#' comments.
/// \throw InputError "file:line: ..." on anything else.
std::vector<std::uint32_t> read_index_file(const std::string& path);

}  // namespace ffd
