#include "warp/idw_deformer.h"

#include <cmath>

#include "common/errors.h"

namespace ffd {

IdwDeformer::IdwDeformer(std::vector<Eigen::Vector3d> rest, double power)
    : ScatteredDeformer(std::move(rest), "control points"), power_(power) {
  if (rest_.empty()) throw InputError("IDW needs at least one control point", {"points"});
  if (!(power_ > 0)) throw InputError("the power must be positive", {"power"});
  const Eigen::Index n = static_cast<Eigen::Index>(rest_.size());
  rest_matrix_.resize(3, n);
  for (Eigen::Index i = 0; i < n; ++i) rest_matrix_.col(i) = rest_[static_cast<std::size_t>(i)];
  moves_ = Eigen::Matrix3Xd::Zero(3, n);
}

void IdwDeformer::update_after_move() {
  for (Eigen::Index i = 0; i < moves_.cols(); ++i)
    moves_.col(i) = current_[static_cast<std::size_t>(i)] - rest_[static_cast<std::size_t>(i)];
}

Eigen::Index IdwDeformer::weights(const Eigen::Vector3d& x, Eigen::ArrayXd& r2, Eigen::ArrayXd& w) const {
  r2 = (rest_matrix_.colwise() - x).colwise().squaredNorm().transpose().array();
  Eigen::Index nearest = 0;
  const double r2_min = r2.minCoeff(&nearest);
  if (r2_min == 0) return nearest;
  // (r_min / r_i)^p = (r2_min / r2_i)^(p/2); p = 2 without exp and log.
  w = power_ == 2 ? Eigen::ArrayXd(r2_min / r2) : Eigen::ArrayXd((0.5 * power_ * (r2_min / r2).log()).exp());
  return -1;
}

void IdwDeformer::movable_weights(int, const Eigen::Vector3d& x, PointWeights& out) const {
  out.clear();
  Eigen::ArrayXd r2, w;
  const Eigen::Index at = weights(x, r2, w);
  if (at >= 0) {
    out.emplace_back(static_cast<std::size_t>(at), 1.0);
    return;
  }
  const double total = w.sum();
  for (Eigen::Index i = 0; i < w.size(); ++i)
    if (w[i] != 0) out.emplace_back(static_cast<std::size_t>(i), w[i] / total);
}

Eigen::Vector3d IdwDeformer::apply(const Eigen::Vector3d& x, Eigen::Matrix3d* jacobian) const {
  if (jacobian) jacobian->setIdentity();
  if (!moved()) return x;  // unmoved: the identity, bit for bit
  thread_local Eigen::ArrayXd r2, w;
  const Eigen::Index at = weights(x, r2, w);
  if (at >= 0) return current_[static_cast<std::size_t>(at)];  // exactly the target
  const double total = w.sum();
  const Eigen::Vector3d d = (moves_ * w.matrix()) / total;
  if (jacobian) {
    // grad w_i / total = -p (w_i / total) (x - x_i) / r_i^2; J = I + sum (d_i - d) grad w_i^T / total.
    const Eigen::ArrayXd c = -power_ * w / (total * r2);
    const Eigen::Matrix3Xd e = (-rest_matrix_).colwise() + x;
    const Eigen::Matrix3Xd dd = moves_.colwise() - d;
    *jacobian += dd * c.matrix().asDiagonal() * e.transpose();
  }
  return x + d;
}

}  // namespace ffd
