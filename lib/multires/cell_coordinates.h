// Local coordinates in a hexahedral cell: the trilinear map of its 8 corners and its
// inverse (MacCracken & Joy's parameterization of a vertex in a hexahedral cell).
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <limits>

namespace ffd {

/// Corner c of a cell (bit 0: +u, bit 1: +v, bit 2: +w).
using CellCorners = Eigen::Matrix<double, 3, 8>;

/// The 8 trilinear weights at u, and their derivatives dw/du (row c: corner c).
void trilinear_weights(const Eigen::Vector3d& u, double w[8], Eigen::Matrix<double, 8, 3>* dw);

/// sum_c w_c(u) Q_c, and its Jacobian d/du when asked.
Eigen::Vector3d trilinear(const CellCorners& Q, const Eigen::Vector3d& u, Eigen::Matrix3d* jacobian);

/// A^-1 b by Gaussian elimination with partial pivoting: Eigen 3.4's
/// `A.partialPivLu().solve(b)` for a 3 x 3, operation for operation, so with the same bits,
/// without the generic factorization it calls out of line for each Newton step.
Eigen::Vector3d pivoted_solve(const Eigen::Matrix3d& A, const Eigen::Vector3d& b);

/// The u with trilinear(Q, u) = x, by Newton's method with a line search from `guess`
/// (the cell's centre by default; for a cell of a regular grid, the fractional grid
/// position is exact and costs one evaluation). False when it does not converge or the
/// map is singular there; u may then lie anywhere.
/// `dx_du`, when given, receives the map's Jacobian at the u returned.
bool inverse_trilinear(const CellCorners& Q, const Eigen::Vector3d& x, Eigen::Vector3d& u,
                       const Eigen::Vector3d& guess = Eigen::Vector3d::Constant(0.5), Eigen::Matrix3d* dx_du = nullptr);

/// The square of an upper bound of the 2-norm of (dD/du)(dx/du)^-1, the gradient of the
/// displacement that trilinear interpolation of the corner displacements D gives a cell,
/// at a point of the cell where the rest map's Jacobian is dx_du:
/// - column a of dD/du is a convex combination of D's four edge differences along axis a,
///   so |dD/du|_F^2 <= the sum over a of the longest such difference squared;
/// - |(dx/du)^-1|_2 = 1 / s3 = s1 s2 / |det| <= |dx/du|_F^2 / (2 |det|) (s: singular values).
/// Squared, so that it takes no square root. Infinite when dx_du is singular. Inline: it
/// reads D where the caller just gathered it.
inline double squared_gradient_bound(const CellCorners& D, const Eigen::Matrix3d& dx_du) {
  // The edges' squared lengths, coordinate by coordinate (corner c: bit 0 +u, bit 1 +v,
  // bit 2 +w).
  double along[3][4] = {};
  for (int i = 0; i < 3; ++i) {
    double row[8];
    for (int c = 0; c < 8; ++c) row[c] = D(i, c);
    for (int e = 0; e < 4; ++e) {
      const double du = row[2 * e + 1] - row[2 * e];              // edges (0,1) (2,3) (4,5) (6,7)
      const double dv = row[e + 2 + (e & 2)] - row[e + (e & 2)];  // (0,2) (1,3) (4,6) (5,7)
      const double dw = row[e + 4] - row[e];                      // (0,4) (1,5) (2,6) (3,7)
      along[0][e] += du * du, along[1][e] += dv * dv, along[2][e] += dw * dw;
    }
  }
  double gradient = 0;  // the bound of |dD/du|_F^2: each axis' longest edge
  for (const auto& axis : along) gradient += std::max(std::max(axis[0], axis[1]), std::max(axis[2], axis[3]));
  const double det = std::abs(dx_du.determinant());
  if (!(det > 0)) return std::numeric_limits<double>::infinity();
  const double inverse = dx_du.squaredNorm() / (2 * det);  // the bound of |(dx/du)^-1|_2
  return gradient * (inverse * inverse);
}

/// Whether u lies in [0,1]^3 within `tolerance`.
inline bool in_unit_cube(const Eigen::Vector3d& u, double tolerance) {
  return (u.array() >= -tolerance).all() && (u.array() <= 1 + tolerance).all();
}

}  // namespace ffd
