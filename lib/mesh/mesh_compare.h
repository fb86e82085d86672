// Comparing two meshes, for regression tests and `ffdtool compare`.
#pragma once

#include <string>
#include <vector>

#include "mesh/mesh.h"

namespace ffd {

struct MeshDifference {
  std::string metric;          // "vertex" or "hausdorff"
  bool comparable = true;      // false: vertex metric on different vertex counts
  std::string reason;          // why not comparable / what differs
  bool same_connectivity = false;
  double max = 0;              // vertex: max |a_i - b_i|; hausdorff: two-sided distance
  double mean = 0;             // vertex: mean |a_i - b_i|; hausdorff: mean vertex-to-surface, both ways
  double rms = 0;
  std::size_t worst_vertex = 0;  // vertex metric: where max is reached
  /// Per vertex of b, its distance to a (as vertex_distances): what --heatmap colours.
  /// Empty when not comparable.
  std::vector<double> distances;
};

/// Per-vertex comparison: vertex i of a against vertex i of b; faces compared as lists.
MeshDifference compare_vertices(const Mesh& a, const Mesh& b);

/// Two-sided Hausdorff distance between the surfaces (CGAL's bounded-error algorithm,
/// within `error_bound`), for meshes whose connectivity differs; polygon faces are
/// triangulated on copies. Mean and RMS are over vertex-to-surface distances both ways.
MeshDifference compare_hausdorff(const Mesh& a, const Mesh& b, double error_bound);

/// Each vertex of `b`'s distance to `a`: |a_i - b_i| for the vertex metric (empty when
/// the vertex counts differ), else the distance to a's surface (CGAL's AABB tree; NaN
/// for a vertex no polygon of b uses). compare_vertices and compare_hausdorff keep them
/// in MeshDifference::distances.
std::vector<double> vertex_distances(const Mesh& a, const Mesh& b, bool hausdorff);

}  // namespace ffd
