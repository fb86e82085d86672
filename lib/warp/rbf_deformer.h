// RbfDeformer: radial basis function morphing of scattered control points, the map of
// PyGeM's RBF (Forti & Rozza; Buhmann 2003):
//   M(x) = c + Q x + sum_i gamma_i phi(|x - x_i|),
// interpolating the moved points y_i at the rest points x_i, with the side conditions
// sum gamma_i = 0 and sum gamma_i x_i = 0 (PyGeM's H = [Phi P; P^T 0], P = [1 x y z]).
//
// Promises:
// - Displacement form: M(x) = x + D(x), where D interpolates y_i - x_i by the same system.
//   By linearity this is PyGeM's map exactly (the system reproduces x itself with
//   gamma = 0, c = 0, Q = I); written this way an unmoved deformer is the identity bit for
//   bit.
// - The system is factorized once, when the deformer is made (one control-point layout);
//   a move changes only the right-hand side: one solve with the factor, then evaluation.
//   Global kernels: a dense LU. The compact kernel (Wendland's): the sparse kernel matrix
//   from a k-d tree's radius searches, factored by common/supernodal_cholesky.h, and the
//   4 x 4 Schur complement of the polynomial (UMFPACK's LU of the whole H spends 70% of
//   its time in Debian's reference BLAS, Eigen's SparseLU is slower still); each
//   evaluation sums over the control points within the radius only (the same terms, the
//   others being exactly 0).
// - Linear in the moved points: dM(x)/dy_j = w_j(x) I, w(x) = H^-1 b(x) restricted to the
//   points, b(x) = [phi(|x - x_i|); 1; x] (H is symmetric).
// - Global, compact kernel included: a move changes every coefficient through the
//   coupled solve and the polynomial, so it re-evaluates every point.
// - The kernels and their parameters are PyGeM's (rbf_factory.py), under the same names.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "warp/scattered_deformer.h"

namespace ffd {

class PointTree;

enum class RbfKernel {
  Gaussian,           // gaussian_spline: exp(-r^2 / R^2)
  MultiQuadratic,     // multi_quadratic_biharmonic_spline: sqrt(r^2 + R^2)
  InvMultiQuadratic,  // inv_multi_quadratic_biharmonic_spline: 1 / sqrt(r^2 + R^2)
  ThinPlate,          // thin_plate_spline: s^k log s, s = r / R (0 at s = 0)
  Wendland,           // beckert_wendland_c2_basis: (1 - s)_+^4 (4 s + 1), zero beyond R
  Polyharmonic,       // polyharmonic_spline: s^k for odd k, s^k log s for even k
};

struct RbfOptions {
  RbfKernel kernel = RbfKernel::Gaussian;
  double radius = 0.5;  // R: PyGeM's radius
  int k = 2;            // thin_plate_spline and polyharmonic_spline
};

/// phi(r) and, when `dphi_over_r` is given, phi'(r) / r (the Jacobian's radial factor; 0 at
/// r = 0 where the kernel has no derivative there).
double rbf_kernel(const RbfOptions& options, double r, double* dphi_over_r = nullptr);

class RbfDeformer : public ScatteredDeformer {
public:
  /// Control points at `rest`, factorized once.
  /// \throw InputError about "points": fewer than 4 points, two equal points (naming
  /// them), points in one plane (the linear polynomial needs them to span 3D), or a
  /// system too ill-conditioned to solve (its condition number).
  RbfDeformer(std::vector<Eigen::Vector3d> rest, const RbfOptions& options);
  ~RbfDeformer() override;

  const RbfOptions& options() const { return options_; }
  /// The estimated condition number of the system H (1-norm, Hager's estimator: the
  /// reciprocal of LAPACK's rcond).
  double condition() const { return condition_; }
  /// Whether the system is sparse (a compact kernel) and how many entries H has.
  bool sparse() const { return tree_ != nullptr; }
  std::size_t matrix_entries() const { return entries_; }

  std::string kind() const override { return "rbf"; }
  void movable_weights(int level, const Eigen::Vector3d& x, PointWeights& out) const override;
  using ScatteredDeformer::apply;
  Eigen::Vector3d apply(const Eigen::Vector3d& x, Eigen::Matrix3d* jacobian) const override;

private:
  struct System;
  void update_after_move() override;
  void check_layout() const;
  /// P = [1 x y z], one row per control point: H's polynomial block.
  Eigen::MatrixXd polynomial_rows() const;
  /// Assemble and factorize H, dense or sparse.
  void factorize_dense();
  void factorize_sparse();
  /// Estimates H's condition from its 1-norm. \throw InputError when it is singular.
  void check_condition(double norm, bool factorized);
  /// phi(|x - x_i|) of control points `ids` (or, when null, of the first `count`) into out.
  void kernel_values(const Eigen::Vector3d& x, const std::uint32_t* ids, Eigen::Index count, double* out) const;
  /// b(x) = [phi(|x - x_i|); 1; x].
  Eigen::VectorXd basis_row(const Eigen::Vector3d& x) const;
  /// Adds the kernel terms of control points `ids` (or, when null, of the first `count`)
  /// to the displacement d and its Jacobian.
  void add_terms(const Eigen::Vector3d& x, const std::uint32_t* ids, Eigen::Index count, Eigen::Vector3d& d,
                 Eigen::Matrix3d* jacobian) const;

  RbfOptions options_;
  std::unique_ptr<System> system_;
  std::unique_ptr<PointTree> tree_;  // compact kernels: the control points within a radius
  Eigen::MatrixX3d rest_columns_;    // rest_ as rows: each axis contiguous, for the kernel sums
  Eigen::MatrixXd coefficients_;     // (n + 4) x 3: gamma, c, Q^T of the displacement
  double condition_ = 0;
  std::size_t entries_ = 0;
};

}  // namespace ffd
