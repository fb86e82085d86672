// PLY and STL: our exact writers (the readers are in ply_io.h and stl_io.h).
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "mesh/mesh.h"
#include "mesh/vertex_colors.h"
#include "mesh/soup.h"

namespace ffd {

/// Writes PLY, ASCII or binary little-endian, with double coordinates (round-trip exact
/// either way), optional per-vertex normals (3 × n), `colors` (uchar red green blue) and
/// the mesh's UVs (double u v) where vertex_uvs gives them.
/// Face lists count with a uchar, or an int where a polygon has more than 255 corners.
/// A mesh read from a PLY file is written by write_ply_source (ply_source.h) instead.
void write_ply(std::ostream& os, const Mesh& mesh, const Eigen::Matrix3Xd* normals, VertexColors colors,
               bool binary = false);

/// One UV per vertex, as PLY holds them: when every polygon corner has a UV and the
/// corners of each vertex agree (a PLY's, an OFF's, an OBJ without seams); empty
/// otherwise. A vertex in no polygon gets (0, 0).
std::vector<Eigen::Vector2d> vertex_uvs(const Mesh& mesh);

/// Writes STL, ASCII (shortest round-trip numbers) or binary (float32, as binary STL
/// holds them); polygons are split into triangle fans (STL holds only triangles).
/// 	hrow InputError if a binary STL cannot count the triangles (2^32 or more).
void write_stl(std::ostream& os, const Mesh& mesh, bool binary = false);

}  // namespace ffd
