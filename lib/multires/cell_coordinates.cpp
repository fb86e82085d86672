#include "multires/cell_coordinates.h"

#include <cmath>

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
                       const Eigen::Vector3d& guess) {
  u = guess;
  const double scale = (Q.rowwise().maxCoeff() - Q.rowwise().minCoeff()).maxCoeff();
  if (!(scale > 0)) return false;
  Eigen::Matrix3d J;
  Eigen::Vector3d r = trilinear(Q, u, &J) - x;
  // Newton's method with a backtracking line search on |r|: bent cells (near cuts, shrunk
  // points) make the full step overshoot.
  for (int iteration = 0; iteration < 50; ++iteration) {
    if (r.norm() <= 1e-13 * scale) return true;
    if (!(std::abs(J.determinant()) > 1e-300)) return false;
    const Eigen::Vector3d step = J.partialPivLu().solve(r);
    double t = 1;
    Eigen::Vector3d next_u = u - step, next_r;
    Eigen::Matrix3d next_J;
    for (int halving = 0; halving < 30; ++halving, t /= 2) {
      next_u = u - t * step;
      next_r = trilinear(Q, next_u, &next_J) - x;
      if (next_r.norm() < r.norm()) break;
    }
    if (!(next_r.norm() < r.norm())) return r.norm() <= 1e-9 * scale;
    u = next_u, r = next_r, J = next_J;
  }
  return r.norm() <= 1e-9 * scale;
}

}  // namespace ffd
