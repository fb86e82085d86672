// Local coordinates in a hexahedral cell: the trilinear map of its 8 corners and its
// inverse (MacCracken & Joy's parameterization of a vertex in a hexahedral cell).
#pragma once

#include <Eigen/Dense>

namespace ffd {

/// Corner c of a cell (bit 0: +u, bit 1: +v, bit 2: +w).
using CellCorners = Eigen::Matrix<double, 3, 8>;

/// The 8 trilinear weights at u, and their derivatives dw/du (row c: corner c).
void trilinear_weights(const Eigen::Vector3d& u, double w[8], Eigen::Matrix<double, 8, 3>* dw);

/// sum_c w_c(u) Q_c, and its Jacobian d/du when asked.
Eigen::Vector3d trilinear(const CellCorners& Q, const Eigen::Vector3d& u, Eigen::Matrix3d* jacobian);

/// A^-1 b by Gaussian elimination with partial pivoting: Eigen 3.4's
/// `A.partialPivLu().solve(b)` for a 3 x 3, operation for operation, so with the same bits,
/// without its out-of-line factorization (a third of a Newton step's time).
Eigen::Vector3d pivoted_solve(const Eigen::Matrix3d& A, const Eigen::Vector3d& b);

/// The u with trilinear(Q, u) = x, by Newton's method with a line search from `guess`
/// (the cell's centre by default; for a cell of a regular grid, the fractional grid
/// position is exact and costs one evaluation). False when it does not converge or the
/// map is singular there; u may then lie anywhere.
bool inverse_trilinear(const CellCorners& Q, const Eigen::Vector3d& x, Eigen::Vector3d& u,
                       const Eigen::Vector3d& guess = Eigen::Vector3d::Constant(0.5));

/// Whether u lies in [0,1]^3 within `tolerance`.
inline bool in_unit_cube(const Eigen::Vector3d& u, double tolerance) {
  return (u.array() >= -tolerance).all() && (u.array() <= 1 + tolerance).all();
}

}  // namespace ffd
