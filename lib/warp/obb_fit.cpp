// Oriented bounding boxes through CGAL's Optimal_bounding_box package.
#include <CGAL/Simple_cartesian.h>
#include <CGAL/optimal_bounding_box.h>

#include <array>
#include <numeric>

#include "common/errors.h"
#include "warp/parallelepiped.h"

namespace ffd {

Parallelepiped fit_obb(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                       const std::vector<std::uint32_t>& ids, double padding) {
  using K = CGAL::Simple_cartesian<double>;
  std::vector<K::Point_3> pts;
  if (ids.empty())
    for (Eigen::Index i = 0; i < points.cols(); ++i) pts.emplace_back(points(0, i), points(1, i), points(2, i));
  else
    for (std::uint32_t i : ids) pts.emplace_back(points(0, i), points(1, i), points(2, i));
  if (pts.size() < 4) return fit_aabb(points, ids, padding);

  // The affine transformation that maps the OBB to an axis-aligned box; its rotation part
  // gives the box's axes. A fixed seed makes the genetic search deterministic.
  CGAL::Aff_transformation_3<K> to_aligned;
  CGAL::oriented_bounding_box(pts, to_aligned,
                              CGAL::parameters::use_convex_hull(true).random_seed(20261122));
  Eigen::Matrix3d R;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) R(r, c) = to_aligned.m(r, c);
  // Rows of R are the box directions in world space. Order them to match x, y, z as
  // closely as possible (greedy on |cos|), sign them positive along their axis.
  Eigen::Matrix3d dirs;
  std::array<bool, 3> used{false, false, false};
  for (int axis = 0; axis < 3; ++axis) {
    int best = -1;
    for (int r = 0; r < 3; ++r)
      if (!used[r] && (best < 0 || std::abs(R(r, axis)) > std::abs(R(best, axis)))) best = r;
    used[best] = true;
    Eigen::Vector3d d = R.row(best).transpose().normalized();
    if (d[axis] < 0) d = -d;
    dirs.col(axis) = d;
  }
  if (dirs.determinant() < 0) dirs.col(2) = -dirs.col(2);

  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
  for (const K::Point_3& p : pts) {
    const Eigen::Vector3d q = dirs.transpose() * Eigen::Vector3d(p.x(), p.y(), p.z());
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  const double largest = (hi - lo).maxCoeff();
  const double pad = padding * largest;
  Eigen::Vector3d size = ((hi - lo).array() + 2 * pad).max(1e-6 * largest);
  const Eigen::Vector3d centre = 0.5 * (lo + hi);
  const Eigen::Vector3d origin = dirs * (centre - 0.5 * size);
  return Parallelepiped(origin, dirs * size.asDiagonal());
}

}  // namespace ffd
