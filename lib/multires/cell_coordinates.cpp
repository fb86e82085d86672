#include "multires/cell_coordinates.h"

#include <cmath>
#include <utility>

namespace ffd {

void trilinear_weights(const Eigen::Vector3d& u, double w[8], Eigen::Matrix<double, 8, 3>* dw) {
  const double a[2][3] = {{1 - u[0], 1 - u[1], 1 - u[2]}, {u[0], u[1], u[2]}};
  for (int c = 0; c < 8; ++c) {
    const int s0 = c & 1, s1 = (c >> 1) & 1, s2 = (c >> 2) & 1;
    w[c] = a[s0][0] * a[s1][1] * a[s2][2];
    if (dw) {
      (*dw)(c, 0) = (s0 ? 1.0 : -1.0) * a[s1][1] * a[s2][2];
      (*dw)(c, 1) = a[s0][0] * (s1 ? 1.0 : -1.0) * a[s2][2];
      (*dw)(c, 2) = a[s0][0] * a[s1][1] * (s2 ? 1.0 : -1.0);
    }
  }
}

namespace {

// Where Eigen's 3 x 3 solve rounds: gcc fuses a product into the sum that uses it
// (-ffp-contract=fast) when the target has FMA, and the first of two products in a sum
// stays rounded; clang fuses only within one expression, which Eigen's products and sums
// never share, and a target without FMA cannot fuse.
#if defined(__FMA__) && !defined(__clang__)
constexpr bool kFused = true;
#else
constexpr bool kFused = false;
#endif

/// c - a b, rounded where Eigen's code rounds it.
inline double minus_product(double c, double a, double b) {
  if (kFused) return std::fma(-a, b, c);
  const double product = a * b;  // its own statement: clang does not fuse it
  return c - product;
}

/// a0 b0 + a1 b1, rounded where Eigen's two-term dot product rounds it.
inline double dot2(double a0, double b0, double a1, double b1) {
  const double first = a0 * b0;
  if (kFused) return std::fma(a1, b1, first);
  const double second = a1 * b1;
  return first + second;
}

}  // namespace

Eigen::Vector3d pivoted_solve(const Eigen::Matrix3d& A, const Eigen::Vector3d& b) {
  double lu[3][3], x[3] = {b[0], b[1], b[2]};  // lu[row][column]
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) lu[i][j] = A(i, j);
  // Eigen's unblocked_lu: for the first two columns, the first row of largest magnitude
  // becomes the pivot (its row swapped, and the right-hand side's with it), the column
  // below is divided by it (unless it is zero), then the corner below and right loses the
  // outer product of that column and the pivot's row.
  for (int k = 0; k < 2; ++k) {
    int p = k;
    for (int i = k + 1; i < 3; ++i)
      if (std::abs(lu[i][k]) > std::abs(lu[p][k])) p = i;
    std::swap(lu[k], lu[p]);  // p = k when the column is zero
    std::swap(x[k], x[p]);
    if (lu[k][k] != 0)
      for (int i = k + 1; i < 3; ++i) lu[i][k] /= lu[k][k];
    for (int j = k + 1; j < 3; ++j)
      for (int i = k + 1; i < 3; ++i) lu[i][j] = minus_product(lu[i][j], lu[i][k], lu[k][j]);
  }
  // Eigen's unrolled triangular solves, unit lower then upper: row i loses the dot product
  // of its off-diagonal part with the values already solved, summed in column order.
  x[1] = minus_product(x[1], lu[1][0], x[0]);
  x[2] -= dot2(lu[2][0], x[0], lu[2][1], x[1]);
  x[2] /= lu[2][2];
  x[1] = minus_product(x[1], lu[1][2], x[2]);
  x[1] /= lu[1][1];
  x[0] -= dot2(lu[0][1], x[1], lu[0][2], x[2]);
  x[0] /= lu[0][0];
  return {x[0], x[1], x[2]};
}

Eigen::Vector3d trilinear(const CellCorners& Q, const Eigen::Vector3d& u, Eigen::Matrix3d* jacobian) {
  double w[8];
  Eigen::Matrix<double, 8, 3> dw;
  trilinear_weights(u, w, jacobian ? &dw : nullptr);
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  for (int c = 0; c < 8; ++c) x += w[c] * Q.col(c);
  if (jacobian) *jacobian = Q * dw;
  return x;
}

bool inverse_trilinear(const CellCorners& Q, const Eigen::Vector3d& x, Eigen::Vector3d& u,
                       const Eigen::Vector3d& guess, Eigen::Matrix3d* dx_du) {
  u = guess;
  const double scale = (Q.rowwise().maxCoeff() - Q.rowwise().minCoeff()).maxCoeff();
  if (!(scale > 0)) return false;
  Eigen::Matrix3d J;
  Eigen::Vector3d r = trilinear(Q, u, &J) - x;
  // Newton's method with a backtracking line search on |r|: bent cells (near cuts, shrunk
  // points) make the full step overshoot.
  for (int iteration = 0; iteration < 50; ++iteration) {
    if (r.norm() <= 1e-13 * scale) {
      if (dx_du) *dx_du = J;
      return true;
    }
    if (!(std::abs(J.determinant()) > 1e-300)) return false;
    const Eigen::Vector3d step = pivoted_solve(J, r);
    double t = 1;
    Eigen::Vector3d next_u = u - step, next_r;
    Eigen::Matrix3d next_J;
    for (int halving = 0; halving < 30; ++halving, t /= 2) {
      next_u = u - t * step;
      next_r = trilinear(Q, next_u, &next_J) - x;
      if (next_r.norm() < r.norm()) break;
    }
    if (!(next_r.norm() < r.norm())) break;
    u = next_u, r = next_r, J = next_J;
  }
  if (dx_du) *dx_du = J;
  return r.norm() <= 1e-9 * scale;
}

}  // namespace ffd
