// LatticeSpec: what a lattice is before it has a box: its basis, degree and cells. The
// script checks indices against it before any work; make_lattice builds the lattice.
#pragma once

#include <memory>
#include <string>

#include "warp/lattice.h"

namespace ffd {

struct LatticeSpec {
  Lattice::Basis basis = Lattice::Basis::BSpline;
  /// B-spline degree (1-3); a Bernstein lattice's degree per axis is its cell count.
  int degree = 3;
  /// Cells per axis: B-spline knot spans across the box, or Bernstein degrees.
  Index3 cells{0, 0, 0};
};

/// The movable index range of `spec`'s lattice along `axis` (empty when lo > hi).
void movable_span(const LatticeSpec& spec, int axis, int& lo, int& hi);
/// "i in [2, 4], j in [2, 4], k in [2, 6]", for messages.
std::string movable_text(const LatticeSpec& spec);
/// The lattice of `spec` on `box`, every point at rest. \throw InputError for a degree
/// or cell count its basis does not allow.
std::unique_ptr<Lattice> make_lattice(const LatticeSpec& spec, const Parallelepiped& box);

}  // namespace ffd
