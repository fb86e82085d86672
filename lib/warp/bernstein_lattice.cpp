#include "warp/bernstein_lattice.h"

#include "common/errors.h"

namespace ffd {

BernsteinLattice::BernsteinLattice(const Parallelepiped& box, Index3 degrees) : Lattice(box, degrees) {
  for (int a = 0; a < 3; ++a)
    if (degrees[a] < 1 || degrees[a] > kMaxDegree)
      throw InputError("a Bernstein lattice's degree per axis must be in 1.." + std::to_string(kMaxDegree));
  init_points({0, 0, 0}, {degrees[0] + 1, degrees[1] + 1, degrees[2] + 1});
}

void BernsteinLattice::movable_span(int axis, int& lo, int& hi) const {
  lo = 0;
  hi = cells_[axis];
}

void BernsteinLattice::bernstein(int n, double u, double* out) {
  const double v = 1 - u;
  out[0] = 1;
  for (int d = 1; d <= n; ++d) {
    out[d] = u * out[d - 1];
    for (int i = d - 1; i >= 1; --i) out[i] = v * out[i] + u * out[i - 1];
    out[0] *= v;
  }
}

void BernsteinLattice::axis_weights(int axis, double u, int& first, double* w, double* dw) const {
  const int n = cells_[axis];
  first = 0;
  bernstein(n, u, w);
  // d/du B_i^n = n (B_{i-1}^{n-1} - B_i^{n-1}).
  double lower[kMaxDegree + 1];
  bernstein(n - 1, u, lower);
  for (int i = 0; i <= n; ++i) {
    const double left = i > 0 ? lower[i - 1] : 0.0;
    const double right = i < n ? lower[i] : 0.0;
    dw[i] = n * (left - right);
  }
}

}  // namespace ffd
