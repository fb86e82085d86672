// Comparing two meshes, for regression tests and `ffdtool compare`.
#pragma once

#include <string>
#include <vector>

#include "mesh/hausdorff.h"
#include "mesh/mesh.h"

namespace ffd {

struct MeshDifference {
  std::string metric;          // "vertex" or "hausdorff"
  bool comparable = true;      // false: vertex metric on different vertex counts
  std::string reason;          // why not comparable / what differs
  bool same_connectivity = false;
  double max = 0;              // vertex: max |a_i - b_i|; hausdorff: two-sided distance (a
                               // distance reached; the true one lies in [max, max_upper])
  double max_upper = 0;        // hausdorff: no point is farther than this from the other surface
  double error_bound = 0;      // hausdorff: the bound asked for (max_upper - max <= it)
  bool larger = false;         // hausdorff: the decision, distance > tolerance
  std::size_t points = 0;      // hausdorff: points measured (vertices and splits' midpoints)
  double mean = 0;             // vertex: mean |a_i - b_i|; hausdorff: mean vertex-to-surface, both ways
  double rms = 0;
  std::size_t worst_vertex = 0;  // vertex metric: where max is reached
  /// Per vertex of b, its distance to a (as vertex_distances): what --heatmap colours.
  /// Empty when not comparable.
  std::vector<double> distances;
};

/// What `compare` measures and against what.
struct CompareOptions {
  std::string metric = "vertex";  // "vertex" or "hausdorff"
  double tolerance = 1e-9;        // largest distance still "same"
  double error_bound = 0;         // hausdorff: the distance's bound; 0: tolerance / 10
                                  // (10^-6 of the meshes' diagonal at tolerance 0)
  int threads = 0;                // hausdorff: 0 for OpenMP's default
};

/// The metric `options` names, on a and b.
MeshDifference compare_meshes(const Mesh& a, const Mesh& b, const CompareOptions& options);

/// Whether d says "same" at `tolerance`: comparable, within it, and for the vertex metric
/// the same faces.
bool within_tolerance(const MeshDifference& d, double tolerance);

/// Per-vertex comparison: vertex i of a against vertex i of b; faces compared as lists.
MeshDifference compare_vertices(const Mesh& a, const Mesh& b);

/// Two-sided Hausdorff distance between the surfaces within `options.error_bound`, and
/// whether it exceeds `options.tolerance` (mesh/hausdorff.h), for meshes whose
/// connectivity differs; polygons are fanned into triangles. One AABB tree per mesh.
/// Mean and RMS are over vertex-to-surface distances both ways.
MeshDifference compare_hausdorff(const Mesh& a, const Mesh& b, const HausdorffOptions& options);

/// Each vertex of `b`'s distance to `a`: |a_i - b_i| for the vertex metric (empty when
/// the vertex counts differ), else the distance to a's surface (mesh/surface_index.h; NaN
/// for a vertex no polygon of b uses). compare_vertices and compare_hausdorff keep them
/// in MeshDifference::distances.
std::vector<double> vertex_distances(const Mesh& a, const Mesh& b, bool hausdorff);

}  // namespace ffd
