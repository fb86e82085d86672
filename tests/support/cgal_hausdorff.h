// CGAL's bounded-error Hausdorff distance, the oracle of tests/hausdorff_test.cpp, compiled
// apart from the tests: at -O2 and, in the sanitizers' build, without instrumentation.
// Under ASan at the tests' -O1, CGAL's AABB traversal in it took about 4 of the
// sanitized suite's 11 CPU minutes. It is third-party code that checks ours; ours
// (compare_hausdorff, SurfaceIndex) stays instrumented in the tests that call it.
#pragma once

#include "mesh/halfedge_view_cgal.h"

namespace ffd {

class Mesh;

/// The polygons of `m` fanned into triangles of their own, as SurfaceIndex fans them.
SurfaceMesh triangle_soup(const Mesh& m);

/// The larger of CGAL's two one-sided bounded-error Hausdorff distances between the
/// triangles of `a` and `b` (triangle_soup), each to within `error`.
double cgal_hausdorff(const Mesh& a, const Mesh& b, double error);

}  // namespace ffd
