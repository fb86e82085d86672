// The Hausdorff distance between two surfaces, with a stated error bound, and the
// decision whether it exceeds a tolerance (what `compare --metric hausdorff` exits on).
//
// The bounds are those of CGAL's bounded-error algorithm (Tang et al. 2009, CGAL's
// bounded_error_Hausdorff_distance): over a triangle T of A, d(·, B) is at least the
// largest of its corners' distances (l) and, d(·, t) being convex for any triangle t of
// B, at most min over t of max over T's corners of d(corner, t) (u). A triangle whose
// bounds differ by more than the error is split in four; one that cannot hold a point
// farther than the farthest found is dropped. The candidates t are the triangles closest
// to the sub-triangle's corners (and its parent's best), which makes u - l at most the
// sub-triangle's diameter, so the splitting ends.
//
// Unlike CGAL's, one pass gives both the decision (exact: where tolerance lies between a
// triangle's bounds, it is split on until they fall on one side, down to a floor of
// 1e-9 of the meshes' size) and the distance within its bound; one AABB tree per mesh
// serves both directions and the per-vertex distances; the passes run in parallel over
// fixed blocks of vertices and triangles, so the results do not depend on the thread count.
#pragma once

#include <cstddef>
#include <vector>

#include "mesh/surface_index.h"

namespace ffd {

struct HausdorffOptions {
  double tolerance = 0;    // the decision: is the distance larger than this?
  double error_bound = 0;  // the reported distance is within this of the true one
  int threads = 0;         // 0: OpenMP's default
};

/// From the surface of `from` to the surface of `to`: sup over points p of from of d(p, to).
struct DirectedHausdorff {
  double lower = 0;  // a distance reached: some point of `from` is this far from `to`
  double upper = 0;  // no point of `from` is farther (upper - lower <= the error bound, but
                     // for sub-triangles that reached the splitting depth limit)
  /// Each vertex of `from`'s distance to `to` (NaN for a vertex no polygon uses).
  std::vector<double> vertex_distances;
  std::size_t points = 0;           // points measured: the vertices and the splits' midpoints
  std::size_t split_triangles = 0;  // (sub-)triangles split
};

/// The one-sided distance from `from` to `to`. Both need triangles. When `matched`, vertex
/// i of `from` is taken to lie near vertex i of `to` (same vertex count: a mesh and its
/// deformed copy): the search for vertex i starts at a triangle of vertex i, which is
/// faster (the distances are the same; where two triangles are equally close, which one
/// a split starts from may differ, within the error bound).
DirectedHausdorff directed_hausdorff(const SurfaceIndex& from, const SurfaceIndex& to, const HausdorffOptions& options,
                                     bool matched);

}  // namespace ffd
