// Turning a polygon soup into a Mesh, with the checks every reader shares.
#pragma once

#include <string>

#include "mesh/mesh.h"
#include "mesh/soup.h"

namespace ffd {

/// Builds a Mesh from `soup` (pass it with std::move: its arrays move into the mesh), keeping vertex and element order,
/// per-corner UV and normal indices, colours, groups and header lines. Rest positions
/// and current positions are the soup's positions; rest and current normals are
/// computed (angle-weighted over the polygons). Any polygon soup is accepted: flipped,
/// duplicate, non-manifold or degenerate faces are the halfedge view's business
/// (halfedge_view.h), not a space warp's.
/// With `defer_normals`, the vertex normals are left to Mesh::compute_deferred_normals(),
/// with file normals or without (a caller writing OFF or PLY computes them when the file
/// normals miss a vertex: every_vertex_has_file_normal).
/// \throw InputError naming `file` and the element's line (or index) when an element
/// has no corner or indexes a vertex, texture coordinate or normal past the end.
Mesh build_mesh(PolygonSoup soup, const std::string& file, bool defer_normals = false);

}  // namespace ffd
