#include "warp/parallelepiped.h"

#include <algorithm>
#include <cmath>

#include "common/errors.h"

namespace ffd {

Parallelepiped::Parallelepiped(const Eigen::Vector3d& origin, const Eigen::Matrix3d& axes)
    : origin_(origin), axes_(axes) {
  const Eigen::Vector3d lengths = axes.colwise().norm();
  const double volume = std::abs(axes.determinant());
  if (!(lengths.minCoeff() > 0) || !(volume > 1e-12 * lengths.prod()))
    throw InputError("the box's axes are degenerate (zero length or not linearly independent)");
  inverse_ = axes.inverse();
}

bool Parallelepiped::segment_meets(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double tolerance) const {
  const Eigen::Vector3d ua = to_local(a), ub = to_local(b);
  double t0 = 0, t1 = 1;
  for (int axis = 0; axis < 3; ++axis) {
    const double lo = -tolerance, hi = 1 + tolerance, delta = ub[axis] - ua[axis];
    if (delta == 0) {
      if (!(ua[axis] >= lo && ua[axis] <= hi)) return false;
      continue;
    }
    double ta = (lo - ua[axis]) / delta, tb = (hi - ua[axis]) / delta;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (!(t0 <= t1)) return false;
  }
  return true;
}

Parallelepiped Parallelepiped::from_min_max(const Eigen::Vector3d& min, const Eigen::Vector3d& max) {
  const Eigen::Vector3d size = max - min;
  if (!(size.minCoeff() > 0)) throw InputError("the box's max must exceed its min on every axis");
  return Parallelepiped(min, size.asDiagonal());
}

PointBounds point_bounds(const Eigen::Ref<const Eigen::Matrix3Xd>& points, const std::vector<std::uint32_t>& ids) {
  PointBounds b{Eigen::Vector3d::Constant(INFINITY), Eigen::Vector3d::Constant(-INFINITY)};
  const auto grow = [&](Eigen::Index i) {
    b.lo = b.lo.cwiseMin(points.col(i));
    b.hi = b.hi.cwiseMax(points.col(i));
  };
  if (ids.empty())
    for (Eigen::Index i = 0; i < points.cols(); ++i) grow(i);
  else
    for (std::uint32_t i : ids) grow(i);
  if (!(b.lo.array() <= b.hi.array()).all()) throw InputError("cannot fit a box to an empty set of points");
  return b;
}

Parallelepiped aabb_around(const PointBounds& bounds, double padding) {
  const Eigen::Vector3d& lo = bounds.lo;
  const Eigen::Vector3d& hi = bounds.hi;
  const double largest = (hi - lo).maxCoeff();
  // A single point or a degenerate set gets a unit-free minimum so the box is solid.
  const double pad = largest > 0 ? padding * largest : (padding > 0 ? padding : 1e-6);
  const double min_extent = largest > 0 ? 1e-6 * largest : 1e-6;
  Eigen::Vector3d size = (hi - lo).array() + 2 * pad;
  size = size.cwiseMax(min_extent);
  const Eigen::Vector3d centre = 0.5 * (lo + hi);
  return Parallelepiped::from_min_max(centre - 0.5 * size, centre + 0.5 * size);
}

Parallelepiped fit_aabb(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                        const std::vector<std::uint32_t>& ids, double padding) {
  return aabb_around(point_bounds(points, ids), padding);
}

}  // namespace ffd
