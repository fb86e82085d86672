// Evaluating selections of mesh vertices and lattice points (DESIGN.md's shared grammar):
// indices, a sphere, a box, the nearest point, a file of indices, or a union of these.
// Selections are read and their files loaded with the script (script_values.h); what
// only the mesh or the lattice decides is checked here, with the selection's place.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "script/script_values.h"
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

/// Reads a selection file: one non-negative vertex index per line, '#' comments.
/// \throw InputError "file:line: ..." on anything else.
std::vector<std::uint32_t> read_index_file(const std::string& path);

}  // namespace ffd
