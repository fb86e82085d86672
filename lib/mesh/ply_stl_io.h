// PLY and STL: our exact writers (the readers are in ply_io.h and stl_io.h).
#pragma once

#include <ostream>
#include <string>

#include "mesh/mesh.h"
#include "mesh/vertex_colors.h"
#include "mesh/soup.h"

namespace ffd {

/// Writes ASCII PLY with double coordinates (round-trip exact), optional per-vertex
/// normals (3 × n) and `colors` (uchar red green blue).
void write_ply(std::ostream& os, const Mesh& mesh, const Eigen::Matrix3Xd* normals, VertexColors colors);

/// Writes ASCII STL; polygons are split into triangle fans (STL holds only triangles).
void write_stl(std::ostream& os, const Mesh& mesh);

}  // namespace ffd
