// Turning a polygon soup into a Mesh, with the checks every reader shares.
#pragma once

#include <string>

#include "mesh/mesh.h"
#include "mesh/soup.h"

namespace ffd {

/// Builds a Mesh from `soup`, keeping vertex and face order, per-corner UV and normal
/// indices, colours, groups and header lines. Rest positions and current positions are
/// the soup's positions; rest and current normals are computed (angle-weighted).
/// \throw InputError naming `file` and the face's line (or index) when a face has fewer
/// than three vertices, repeats a vertex, indexes past the end, or would make the mesh
/// non-manifold or inconsistently oriented.
Mesh build_mesh(const PolygonSoup& soup, const std::string& file);

/// "file:line" when the line is known, else "file: face N" (0-based), for messages.
std::string face_place(const std::string& file, const SoupFace& face, std::size_t index);

}  // namespace ffd
