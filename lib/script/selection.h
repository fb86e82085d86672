// Selections of mesh vertices and lattice points (DESIGN.md's shared grammar):
// {"indices": [...]}, {"sphere": {...}}, {"box": {...}}, {"near": [x,y,z]}, {"file": "..."},
// or a list of these (their union).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "warp/lattice.h"

namespace ffd {

/// Where a selection came from, for messages: the script file, the folder its `file`
/// entries are relative to, and the JSON pointer of the selection.
struct SelectionContext {
  std::string script;
  std::string folder;
  std::string path;
};

/// The mesh vertices (columns of `positions`) a schema-checked selection picks, sorted and
/// unique. \throw InputError (naming the script and JSON path) for an index out of range,
/// a lattice index given for vertices, an unreadable or malformed file, or an empty pick.
std::vector<std::uint32_t> select_vertices(const nlohmann::json& selection,
                                           const Eigen::Ref<const Eigen::Matrix3Xd>& positions,
                                           const SelectionContext& where);

/// The movable lattice points a selection picks (by current position), as flat indices,
/// sorted. \throw InputError for an index out of range or not movable (naming the movable
/// range), a vertex index or file given for lattice points, or an empty pick.
std::vector<std::size_t> select_lattice_points(const nlohmann::json& selection, const Lattice& lattice,
                                               const SelectionContext& where);

/// Reads a selection file: one non-negative vertex index per line, '#' comments.
/// \throw InputError "file:line: ..." on anything else.
std::vector<std::uint32_t> read_index_file(const std::string& path);

}  // namespace ffd
