#include "warp/rbf_deformer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <tuple>

#include "common/errors.h"
#include "common/numbers.h"

namespace ffd {
namespace {

/// Below this reciprocal condition number the system is refused as singular.
constexpr double kMinRcond = 1e-15;

/// s^k log s and, in `over_r`, its derivative by r over r (s = r / R), both 0 at s = 0.
double power_log(double s, int k, double R, double* over_r) {
  if (s <= 0) {
    if (over_r) *over_r = 0;
    return 0;
  }
  const double log_s = std::log(s);
  if (over_r) *over_r = std::pow(s, k - 2) * (k * log_s + 1) / (R * R);
  return std::pow(s, k) * log_s;
}

}  // namespace

double rbf_kernel(const RbfOptions& o, double r, double* over_r) {
  const double R = o.radius, s = r / R;
  double d = 0, phi = 0;
  switch (o.kernel) {
    case RbfKernel::Gaussian:
      phi = std::exp(-s * s);
      d = -2 * phi / (R * R);
      break;
    case RbfKernel::MultiQuadratic:
      phi = std::sqrt(r * r + R * R);
      d = 1 / phi;
      break;
    case RbfKernel::InvMultiQuadratic: {
      const double q = std::sqrt(r * r + R * R);
      phi = 1 / q;
      d = -phi / (q * q);
      break;
    }
    case RbfKernel::ThinPlate:
      return power_log(s, o.k, R, over_r);
    case RbfKernel::Wendland:
      if (s < 1) {
        const double t = 1 - s;
        phi = t * t * t * t * (4 * s + 1);
        d = -20 * t * t * t / (R * R);
      }
      break;
    case RbfKernel::Polyharmonic:
      // PyGeM's even-k formula, s^(k-1) log(s^s) below 1 and s^k log s above, is s^k log s.
      if (o.k % 2 == 0) return power_log(s, o.k, R, over_r);
      phi = std::pow(s, o.k);
      d = s > 0 ? o.k * std::pow(s, o.k - 2) / (R * R) : 0;
      break;
  }
  if (over_r) *over_r = d;
  return phi;
}

RbfDeformer::RbfDeformer(std::vector<Eigen::Vector3d> rest, const RbfOptions& options)
    : options_(options), rest_(std::move(rest)), current_(rest_) {
  check_layout();
  const Eigen::Index n = static_cast<Eigen::Index>(rest_.size());
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n + 4, n + 4);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j < n; ++j)
      H(i, j) = rbf_kernel(options_, (rest_[static_cast<std::size_t>(i)] - rest_[static_cast<std::size_t>(j)]).norm());
    H(i, n) = H(n, i) = 1;
    H.block<1, 3>(i, n + 1) = rest_[static_cast<std::size_t>(i)].transpose();
    H.block<3, 1>(n + 1, i) = rest_[static_cast<std::size_t>(i)];
  }
  spacing_ = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < rest_.size(); ++i)
    for (std::size_t j = i + 1; j < rest_.size(); ++j) spacing_ = std::min(spacing_, (rest_[i] - rest_[j]).norm());
  lu_.compute(H);
  const double rcond = lu_.rcond();
  condition_ = rcond > 0 ? 1 / rcond : std::numeric_limits<double>::infinity();
  if (!(rcond >= kMinRcond))
    throw InputError("the RBF system of these control points is singular (estimated condition number " +
                         format_number(condition_) + ")",
                     {"points"});
  coefficients_ = Eigen::MatrixXd::Zero(n + 4, 3);
}

void RbfDeformer::check_layout() const {
  const std::size_t n = rest_.size();
  if (n < 4) throw InputError("an RBF needs at least 4 control points (it has " + std::to_string(n) + ")", {"points"});
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  const auto less = [&](std::size_t a, std::size_t b) {
    const Eigen::Vector3d &p = rest_[a], &q = rest_[b];
    return std::tie(p[0], p[1], p[2], a) < std::tie(q[0], q[1], q[2], b);
  };
  std::sort(order.begin(), order.end(), less);
  for (std::size_t i = 1; i < n; ++i)
    if (rest_[order[i]] == rest_[order[i - 1]])
      throw InputError("control points " + std::to_string(order[i - 1]) + " and " + std::to_string(order[i]) +
                           " are at the same place",
                       {"points"});
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : rest_) centroid += p / static_cast<double>(n);
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : rest_) scatter += (p - centroid) * (p - centroid).transpose();
  const Eigen::Vector3d eig = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvalues();
  if (!(eig[0] > 1e-24 * eig[2]))
    throw InputError("the control points lie in one plane (or on one line): the RBF's linear polynomial needs them "
                     "to span 3D",
                     {"points"});
}

Eigen::Matrix3Xd RbfDeformer::points(int) const {
  Eigen::Matrix3Xd out(3, static_cast<Eigen::Index>(current_.size()));
  for (std::size_t i = 0; i < current_.size(); ++i) out.col(static_cast<Eigen::Index>(i)) = current_[i];
  return out;
}

Eigen::Matrix3Xd RbfDeformer::points(int, const std::vector<std::size_t>& ids) const {
  Eigen::Matrix3Xd out(3, static_cast<Eigen::Index>(ids.size()));
  for (std::size_t i = 0; i < ids.size(); ++i) out.col(static_cast<Eigen::Index>(i)) = current_[ids[i]];
  return out;
}

std::optional<std::size_t> RbfDeformer::find_point(int, const PointIndex& index) const {
  if (index.grid || index.n < 0 || static_cast<std::size_t>(index.n) >= rest_.size()) return std::nullopt;
  return static_cast<std::size_t>(index.n);
}

std::string RbfDeformer::missing_point(int level, const PointIndex& index) const {
  if (index.grid) return "expected a control point index (an integer), found " + index.text();
  return "point " + index.text() + " is not a control point (" + movable_text(level) + ")";
}

std::string RbfDeformer::movable_text(int) const {
  return "control points 0 to " + std::to_string(rest_.size() - 1);
}

MoveReport RbfDeformer::move_points(int, const std::vector<std::size_t>& ids, const std::vector<Eigen::Vector3d>& targets) {
  for (std::size_t i = 0; i < ids.size(); ++i) current_.at(ids[i]) = targets[i];
  const Eigen::Index n = static_cast<Eigen::Index>(rest_.size());
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n + 4, 3);
  for (Eigen::Index i = 0; i < n; ++i) rhs.row(i) = (current_[static_cast<std::size_t>(i)] - rest_[static_cast<std::size_t>(i)]).transpose();
  moved_ = !rhs.isZero(0.0);
  coefficients_ = moved_ ? Eigen::MatrixXd(lu_.solve(rhs)) : Eigen::MatrixXd::Zero(n + 4, 3);
  changed_ = changed_ || !ids.empty();
  MoveReport report;
  report.points_moved = ids.size();
  return report;
}

Eigen::VectorXd RbfDeformer::basis_row(const Eigen::Vector3d& x) const {
  const Eigen::Index n = static_cast<Eigen::Index>(rest_.size());
  Eigen::VectorXd b(n + 4);
  for (Eigen::Index i = 0; i < n; ++i) b[i] = rbf_kernel(options_, (x - rest_[static_cast<std::size_t>(i)]).norm());
  b[n] = 1;
  b.tail<3>() = x;
  return b;
}

void RbfDeformer::movable_weights(int, const Eigen::Vector3d& x, PointWeights& out) const {
  out.clear();
  const Eigen::VectorXd w = lu_.solve(basis_row(x));  // H^-1 b(x) = H^-T b(x): H is symmetric
  for (std::size_t i = 0; i < rest_.size(); ++i)
    if (w[static_cast<Eigen::Index>(i)] != 0) out.emplace_back(i, w[static_cast<Eigen::Index>(i)]);
}

double RbfDeformer::scale() const {
  Eigen::Vector3d lo = rest_[0], hi = rest_[0];
  for (const Eigen::Vector3d& p : rest_) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  return (hi - lo).norm();
}

Eigen::Vector3d RbfDeformer::apply(const Eigen::Vector3d& x, Eigen::Matrix3d* jacobian) const {
  if (jacobian) jacobian->setIdentity();
  const Eigen::Index n = static_cast<Eigen::Index>(rest_.size());
  if (!moved_) return x;  // unmoved: the identity, bit for bit
  // D(x) = sum gamma_i phi(r_i) + c + Q x; dD/dx = sum gamma_i (phi'/r)(x - x_i)^T + Q.
  Eigen::Vector3d d = coefficients_.row(n).transpose() + coefficients_.bottomRows<3>().transpose() * x;
  if (jacobian) *jacobian += coefficients_.bottomRows<3>().transpose();
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d e = x - rest_[static_cast<std::size_t>(i)];
    double over_r = 0;
    const double phi = rbf_kernel(options_, e.norm(), jacobian ? &over_r : nullptr);
    d += phi * coefficients_.row(i).transpose();
    if (jacobian) *jacobian += (over_r * coefficients_.row(i).transpose()) * e.transpose();
  }
  return x + d;
}

void RbfDeformer::apply(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos, const Eigen::Ref<const Eigen::Matrix3Xd>& in_nrm,
                        const std::vector<std::uint32_t>& ids, Eigen::Ref<Eigen::Matrix3Xd> out_pos,
                        Eigen::Ref<Eigen::Matrix3Xd> out_nrm, WarpCounts& counts) const {
  std::size_t folded = 0;
  const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(ids.size());
#pragma omp parallel for schedule(static) reduction(+ : folded)
  for (std::ptrdiff_t t = 0; t < count; ++t) {
    const std::uint32_t v = ids[static_cast<std::size_t>(t)];
    Eigen::Matrix3d J;
    out_pos.col(v) = apply(in_pos.col(v), &J);
    out_nrm.col(v) = J.isIdentity(0.0) ? Eigen::Vector3d(in_nrm.col(v)) : transformed_normal(J, in_nrm.col(v));
    if (J.determinant() <= 0) ++folded;
  }
  counts.folded += folded;
  counts.evaluated += ids.size();
}

void RbfDeformer::changed_points(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos, std::vector<std::uint32_t>& ids) const {
  if (!changed_) return;
  for (Eigen::Index v = 0; v < in_pos.cols(); ++v) ids.push_back(static_cast<std::uint32_t>(v));
}

}  // namespace ffd
