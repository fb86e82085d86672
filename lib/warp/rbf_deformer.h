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
// - Linear in the moved points: dM(x)/dy_j = w_j(x) I, w(x) = H^-1 b(x) restricted to the
//   points, b(x) = [phi(|x - x_i|); 1; x] (H is symmetric).
// - The kernels and their parameters are PyGeM's (rbf_factory.py), under the same names.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Dense>

#include "warp/deformer.h"

namespace ffd {

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

class RbfDeformer : public Deformer {
public:
  /// Control points at `rest`, factorized once.
  /// \throw InputError about "points": fewer than 4 points, two equal points (naming
  /// them), points in one plane (the linear polynomial needs them to span 3D), or a
  /// system too ill-conditioned to solve (its condition number).
  RbfDeformer(std::vector<Eigen::Vector3d> rest, const RbfOptions& options);

  const RbfOptions& options() const { return options_; }
  /// The estimated condition number of the system H (reciprocal of LU's rcond, 1-norm).
  double condition() const { return condition_; }

  // Deformer: one level, points named by a plain index 0..n-1, all movable.
  std::string kind() const override { return "rbf"; }
  std::size_t num_points(int) const override { return rest_.size(); }
  Eigen::Matrix3Xd points(int level) const override;
  Eigen::Matrix3Xd points(int level, const std::vector<std::size_t>& ids) const override;
  bool grid_indexed() const override { return false; }
  std::optional<std::size_t> find_point(int, const PointIndex& index) const override;
  std::string missing_point(int level, const PointIndex& index) const override;
  PointIndex point_index(int, std::size_t id) const override { return {false, {0, 0, 0}, static_cast<long long>(id)}; }
  std::string movable_text(int) const override;
  MoveReport move_points(int level, const std::vector<std::size_t>& ids,
                         const std::vector<Eigen::Vector3d>& targets) override;
  void movable_weights(int level, const Eigen::Vector3d& x, PointWeights& out) const override;
  std::vector<std::array<std::uint32_t, 2>> net_edges(int) const override { return {}; }
  /// The diagonal of the control points' bounding box.
  double scale() const override;

  // Warp
  Eigen::Vector3d apply(const Eigen::Vector3d& x, Eigen::Matrix3d* jacobian) const override;
  void apply(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos, const Eigen::Ref<const Eigen::Matrix3Xd>& in_nrm,
             const std::vector<std::uint32_t>& ids, Eigen::Ref<Eigen::Matrix3Xd> out_pos,
             Eigen::Ref<Eigen::Matrix3Xd> out_nrm, WarpCounts& counts) const override;
  /// Every point: a move changes every coefficient (the cardinal functions are global,
  /// compact kernels included, because of the polynomial and the coupled solve).
  void changed_points(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos, std::vector<std::uint32_t>& ids) const override;
  bool has_changes() const override { return changed_; }
  void clear_changes() override { changed_ = false; }
  /// The smallest distance between two control points: the finest scale of the control.
  double feature_size() const override { return spacing_; }

private:
  /// b(x) = [phi(|x - x_i|); 1; x].
  Eigen::VectorXd basis_row(const Eigen::Vector3d& x) const;
  void check_layout() const;

  RbfOptions options_;
  std::vector<Eigen::Vector3d> rest_, current_;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
  Eigen::MatrixXd coefficients_;  // (n + 4) x 3: gamma, c, Q^T of the displacement
  double condition_ = 0, spacing_ = 0;
  bool moved_ = false;  // some point is off its rest position (else the coefficients are zero)
  bool changed_ = false;
};

}  // namespace ffd
