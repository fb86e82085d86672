// PLY and STL through CGAL's readers; our own exact writers.
#pragma once

#include <ostream>
#include <string>

#include "mesh/mesh.h"
#include "mesh/vertex_colors.h"
#include "mesh/soup.h"

namespace ffd {

/// Reads a PLY file (ASCII or binary) with CGAL: positions, faces, vertex normals
/// (nx ny nz) and colours (red green blue). \throw InputError naming the file and, for
/// bad values, the vertex.
PolygonSoup read_ply(const std::string& path);

/// Reads an STL file (ASCII or binary) with CGAL; equal corner points become one vertex.
PolygonSoup read_stl(const std::string& path);

/// Writes ASCII PLY with double coordinates (round-trip exact), optional per-vertex
/// normals (3 × n) and `colors` (uchar red green blue).
void write_ply(std::ostream& os, const Mesh& mesh, const Eigen::Matrix3Xd* normals, VertexColors colors);

/// Writes ASCII STL; polygons are split into triangle fans (STL holds only triangles).
void write_stl(std::ostream& os, const Mesh& mesh);

}  // namespace ffd
