// IdwDeformer: Shepard's inverse distance weighting of scattered control points' moves,
//   F(x) = x + d(x),  d(x) = sum_i w_i(x) d_i / sum_i w_i(x),  w_i(x) = |x - x_i|^-p,
// with d_i = y_i - x_i the moves of the control points, |.| Euclidean and p the classical
// exponent (`power`). At a control point F is exactly its target.
//
// PyGeM's IDW differs: it takes `power` as the order of a Minkowski norm and weighs by
// 1 / distance; ffdtool's `power` is Shepard's exponent (power 2 with PyGeM's default
// Euclidean norm is PyGeM's map with weights 1/d^2 instead of 1/d).
//
// Promises:
// - Linear in the moved points: dF/dy_j = w_j(x) / sum_i w_i(x) I (the cardinal weights).
// - The Jacobian is I + sum_i (d_i - d(x)) grad w_i^T / sum_i w_i, grad w_i = -p w_i
//   (x - x_i) / |x - x_i|^2; at a control point it is I (for p > 1 the derivative of
//   Shepard's interpolant vanishes there; for p <= 1 it has none, and I is a choice).
// - Weights are scaled by the nearest control point's (w_i (r_min)^p, at most 1), which
//   cancels in the quotient and keeps it finite next to a control point.
#pragma once

#include <vector>

#include "warp/scattered_deformer.h"

namespace ffd {

class IdwDeformer : public ScatteredDeformer {
public:
  /// \throw InputError about "points" for no points or two at one place (naming them),
  /// and about "power" when it is not positive.
  IdwDeformer(std::vector<Eigen::Vector3d> rest, double power);

  double power() const { return power_; }

  std::string kind() const override { return "idw"; }
  void movable_weights(int level, const Eigen::Vector3d& x, PointWeights& out) const override;
  using ScatteredDeformer::apply;
  Eigen::Vector3d apply(const Eigen::Vector3d& x, Eigen::Matrix3d* jacobian) const override;

private:
  void update_after_move() override;
  /// The scaled weights at x into `w` (all n); returns the control point at x, or -1.
  Eigen::Index weights(const Eigen::Vector3d& x, Eigen::ArrayXd& r2, Eigen::ArrayXd& w) const;

  double power_;
  Eigen::MatrixX3d rest_columns_;  // rest_ as rows: each axis contiguous
  Eigen::MatrixX3d moves_;         // d_i as rows
};

}  // namespace ffd
