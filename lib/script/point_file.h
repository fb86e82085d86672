// Files of control-point positions, as the move op's `positions` reads them: the save
// op's control nets (OBJ `v` lines), or plain text of `x y z` lines.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace ffd {

/// The points of `path` in file order: an .obj file's `v` lines (the first three numbers of
/// each; every other line is passed over), or for any other extension one `x y z` line per
/// point, blank lines and '#' comments passed over.
/// \throw InputError "path:line: ..." for a line it cannot read, or naming the file when it
/// cannot be read or holds no point.
std::vector<Eigen::Vector3d> read_point_file(const std::string& path);

}  // namespace ffd
