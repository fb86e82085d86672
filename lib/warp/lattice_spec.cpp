#include "warp/lattice_spec.h"

#include "warp/bernstein_lattice.h"
#include "warp/bspline_lattice.h"

namespace ffd {

void movable_span(const LatticeSpec& spec, int axis, int& lo, int& hi) {
  if (spec.basis == Lattice::Basis::Bernstein) {
    lo = 0;
    hi = spec.cells[axis];
  } else {
    BSplineLattice::movable_span(spec.degree, spec.cells[axis], lo, hi);
  }
}

std::string movable_text(const LatticeSpec& spec) {
  static const char* names = "ijk";
  std::string s;
  for (int a = 0; a < 3; ++a) {
    int lo, hi;
    movable_span(spec, a, lo, hi);
    s += (a ? ", " : "") + std::string(1, names[a]) + " in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  }
  return s;
}

std::unique_ptr<Lattice> make_lattice(const LatticeSpec& spec, const Parallelepiped& box) {
  if (spec.basis == Lattice::Basis::Bernstein) return std::make_unique<BernsteinLattice>(box, spec.cells);
  return std::make_unique<BSplineLattice>(box, spec.cells, spec.degree);
}

}  // namespace ffd
