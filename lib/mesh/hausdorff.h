// The Hausdorff distance between two surfaces, with a stated error bound, and the
// decision whether it exceeds a tolerance (what `compare --metric hausdorff` exits on).
//
// The bounds are those of CGAL's bounded-error algorithm (Tang et al. 2009, CGAL's
// bounded_error_Hausdorff_distance): over a triangle T of A, d(·, B) is at least the
// largest of its corners' distances (l) and, d(·, t) being convex for any triangle t of
// B, at most min over t of max over T's corners of d(corner, t) (u); also at most l plus
// the farthest a point of T lies from its nearest corner (d(·, B) is 1-Lipschitz). The
// candidates t are the triangles closest to T's corners, T's parent's best and, for a
// mesh and its deformed copy, T's own image, which usually settles T at once.
//
// A triangle that cannot hold a point farther than the farthest found is dropped; one
// whose u exceeds that by more than the error bound is split in four. When the tolerance
// still lies between the bounds this gives, a second pass splits the pieces that could
// hold the first point beyond it (l <= tolerance < u) until u - l <= error / 2: a
// distance over tolerance + error / 2 is always found, one at or under tolerance never
// claimed. Splitting ends: u - l is at most a piece's diameter.
//
// Unlike CGAL's, one pass gives both the decision and the distance within its bound; one
// AABB tree per mesh serves both directions and the per-vertex distances; the passes run
// in parallel over fixed blocks of vertices and triangles, so the results do not depend
// on the thread count.
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
  double upper = 0;  // no point of `from` is farther (upper - lower <= the error bound)
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
/// `reached`: a distance already reached elsewhere (the other direction's), which spares
/// the search of pieces that cannot exceed it; lower and upper then bound
/// max(reached, the one-sided distance).
DirectedHausdorff directed_hausdorff(const SurfaceIndex& from, const SurfaceIndex& to, const HausdorffOptions& options,
                                     bool matched, double reached = 0);

}  // namespace ffd
