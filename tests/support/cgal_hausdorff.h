// The Hausdorff oracles of tests/hausdorff_test.cpp: CGAL's bounded-error distance and a
// brute force, in a shared library of their own (tests/support/CMakeLists.txt). It is
// compiled at -O2 and, in the sanitizers' build, without instrumentation, and its symbols
// are hidden but for the two below. A static oracle's CGAL templates (the AABB traversal,
// the point-triangle distance) are the same symbols as the library's instrumented
// SurfaceIndex's, and the linker kept one copy of each, the instrumented one: the oracle
// then ran at the sanitized -O1's speed. Both are third-party code or plain loops that
// check ours; ours (compare_hausdorff, SurfaceIndex) stays instrumented in the tests.
// Neither uses the library: the polygons are fanned from their first corners here.
#pragma once

#ifndef FFD_ORACLE_API
#define FFD_ORACLE_API __attribute__((visibility("default")))
#endif

namespace ffd {

class Mesh;

/// The larger of CGAL's two one-sided bounded-error Hausdorff distances between the
/// triangles of `a` and `b`, each to within `error`.
FFD_ORACLE_API double cgal_hausdorff(const Mesh& a, const Mesh& b, double error);

/// The largest distance from points of `from` (its vertices and the points of a
/// `samples`-step barycentric grid on each triangle) to `to`'s triangles, by CGAL's
/// point-triangle distance to every triangle (but those whose box lies farther than the
/// best so far): a lower bound of the one-sided Hausdorff distance that tends to it.
FFD_ORACLE_API double brute_force_directed_hausdorff(const Mesh& from, const Mesh& to, int samples);

}  // namespace ffd
