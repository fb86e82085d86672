#include "warp/box_fit.h"

#include <Eigen/Eigenvalues>

#include <array>
#include <cmath>

#include "common/errors.h"

namespace ffd {
namespace {

template <class Fn>
void for_each_point(const Eigen::Ref<const Eigen::Matrix3Xd>& points, const std::vector<std::uint32_t>& ids, Fn fn) {
  if (ids.empty())
    for (Eigen::Index i = 0; i < points.cols(); ++i) fn(Eigen::Vector3d(points.col(i)));
  else
    for (std::uint32_t i : ids) fn(Eigen::Vector3d(points.col(i)));
}

// The columns of `d` reordered to lie closest to x, y, z (greedy on |cos|), signed
// positive along their axis, and right-handed.
Eigen::Matrix3d axis_ordered(const Eigen::Matrix3d& d) {
  Eigen::Matrix3d out;
  std::array<bool, 3> used{false, false, false};
  for (int axis = 0; axis < 3; ++axis) {
    int best = -1;
    for (int c = 0; c < 3; ++c)
      if (!used[c] && (best < 0 || std::abs(d(axis, c)) > std::abs(d(axis, best)))) best = c;
    used[best] = true;
    Eigen::Vector3d v = d.col(best).normalized();
    if (v[axis] < 0) v = -v;
    out.col(axis) = v;
  }
  if (out.determinant() < 0) out.col(2) = -out.col(2);
  return out;
}

}  // namespace

Parallelepiped fit_box_along(const Eigen::Ref<const Eigen::Matrix3Xd>& points, const std::vector<std::uint32_t>& ids,
                             const Eigen::Matrix3d& directions, double padding) {
  const Eigen::Matrix3d dirs = axis_ordered(directions);
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
  for_each_point(points, ids, [&](const Eigen::Vector3d& p) {
    const Eigen::Vector3d q = dirs.transpose() * p;
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  });
  if (!(lo.array() <= hi.array()).all()) throw InputError("cannot fit a box to an empty set of points");
  const double largest = (hi - lo).maxCoeff();
  const double pad = largest > 0 ? padding * largest : (padding > 0 ? padding : 1e-6);
  const double min_extent = largest > 0 ? 1e-6 * largest : 1e-6;
  const Eigen::Vector3d size = ((hi - lo).array() + 2 * pad).max(min_extent);
  const Eigen::Vector3d centre = 0.5 * lo + 0.5 * hi;
  const Eigen::Vector3d origin = dirs * (centre - 0.5 * size);
  if (!origin.allFinite() || !size.allFinite())
    throw InputError("the fitted box is not finite (coordinates near the limits of double)");
  return Parallelepiped(origin, dirs * size.asDiagonal());
}

Parallelepiped fit_principal_box(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                                 const std::vector<std::uint32_t>& ids, double padding) {
  const std::size_t n = ids.empty() ? static_cast<std::size_t>(points.cols()) : ids.size();
  if (n < 4) return fit_aabb(points, ids, padding);
  // Centre and scale first: the covariance of coordinates in [-1, 1] cannot overflow.
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
  for_each_point(points, ids, [&](const Eigen::Vector3d& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  });
  const Eigen::Vector3d mid = 0.5 * lo + 0.5 * hi;
  const double half = (0.5 * hi - 0.5 * lo).maxCoeff();
  const double scale = half > 0 ? 1 / half : 1;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for_each_point(points, ids, [&](const Eigen::Vector3d& p) { mean += (p - mid) * scale; });
  mean /= static_cast<double>(n);
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for_each_point(points, ids, [&](const Eigen::Vector3d& p) {
    const Eigen::Vector3d d = (p - mid) * scale - mean;
    covariance += d * d.transpose();
  });
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance / static_cast<double>(n));
  Eigen::Matrix3d directions = eigen.eigenvectors();
  if (eigen.info() != Eigen::Success || !directions.allFinite()) directions = Eigen::Matrix3d::Identity();
  return fit_box_along(points, ids, directions, padding);
}

}  // namespace ffd
