#include "warp/idw_deformer.h"

#include <cmath>

#include "common/errors.h"

namespace ffd {

IdwDeformer::IdwDeformer(std::vector<Eigen::Vector3d> rest, double power)
    : ScatteredDeformer(std::move(rest), "control points"), power_(power) {
  if (rest_.empty()) throw InputError("IDW needs at least one control point", {"points"});
  if (!(power_ > 0)) throw InputError("the power must be positive", {"power"});
  const Eigen::Index n = static_cast<Eigen::Index>(rest_.size());
  rest_columns_.resize(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) rest_columns_.row(i) = rest_[static_cast<std::size_t>(i)].transpose();
  moves_ = Eigen::MatrixX3d::Zero(n, 3);
}

void IdwDeformer::update_after_move() {
  for (Eigen::Index i = 0; i < moves_.rows(); ++i)
    moves_.row(i) = (current_[static_cast<std::size_t>(i)] - rest_[static_cast<std::size_t>(i)]).transpose();
}

Eigen::Index IdwDeformer::weights(const Eigen::Vector3d& x, Eigen::ArrayXd& r2, Eigen::ArrayXd& w) const {
  r2 = (x[0] - rest_columns_.col(0).array()).square() + (x[1] - rest_columns_.col(1).array()).square() +
       (x[2] - rest_columns_.col(2).array()).square();
  Eigen::Index nearest = 0;
  const double r2_min = r2.minCoeff(&nearest);
  if (r2_min == 0) return nearest;
  // (r_min / r_i)^p = (r2_min / r2_i)^(p/2); p = 2 without exp and log.
  if (power_ == 2)
    w = r2_min / r2;
  else
    w = (0.5 * power_ * (r2_min / r2).log()).exp();
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
  Eigen::Vector3d d;
  for (int a = 0; a < 3; ++a) d[a] = (w * moves_.col(a).array()).sum() / total;
  if (jacobian) {
    // grad w_i / total = c_i (x - x_i), c_i = -p (w_i / total) / r_i^2, so
    // J = I + sum_i (d_i - d) c_i (x - x_i)^T; the scratch is the thread's, reused.
    thread_local Eigen::ArrayXd c, weighted;
    c = -power_ * w / (total * r2);
    for (int a = 0; a < 3; ++a) {
      weighted = (moves_.col(a).array() - d[a]) * c;
      for (int b = 0; b < 3; ++b) (*jacobian)(a, b) += (weighted * (x[b] - rest_columns_.col(b).array())).sum();
    }
  }
  return x + d;
}

}  // namespace ffd
