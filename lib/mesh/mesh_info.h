// Facts about a mesh, for `ffdtool info` and for checks before a solve.
#pragma once

#include <map>
#include <string>

#include "mesh/mesh.h"

namespace ffd {

struct MeshInfo {
  std::size_t vertices = 0, faces = 0, edges = 0;
  std::map<std::size_t, std::size_t> faces_by_degree;  // 3 -> triangles, 4 -> quads, ...
  std::size_t lines = 0, points = 0;  // OBJ l and p elements
  std::size_t boundary_edges = 0, boundary_loops = 0;
  std::size_t non_manifold_edges = 0;  // on three or more faces
  std::size_t components = 0;       // connected pieces of faces
  std::size_t isolated_vertices = 0;
  std::size_t degenerate_faces = 0; // zero area
  long euler = 0;                   // V - E + F
  Eigen::Vector3d min = Eigen::Vector3d::Zero(), max = Eigen::Vector3d::Zero();
  double diagonal = 0;
  double min_edge = 0, mean_edge = 0, max_edge = 0;
  bool has_uvs = false, has_normals = false, has_colors = false;
  /// Empty when the polygons form an oriented 2-manifold (what remesh and bcm need),
  /// else check_two_manifold's message naming the first offending element.
  std::string manifold_problem;
};

/// Counts and measures `mesh` at its current positions.
MeshInfo mesh_info(const Mesh& mesh);

}  // namespace ffd
