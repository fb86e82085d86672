// The least-volume box through CGAL's Optimal_bounding_box package, on an exact-predicates
// kernel (its convex hull needs exact orientation tests: an inexact kernel corrupted the
// heap on coordinates of 1e34), run on normalized coordinates.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/optimal_bounding_box.h>

#include "warp/box_fit.h"

namespace ffd {

Parallelepiped fit_min_volume_box(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                                  const std::vector<std::uint32_t>& ids, double padding) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  std::vector<std::uint32_t> all;
  const std::vector<std::uint32_t>* picked = &ids;
  if (ids.empty()) {
    all.resize(static_cast<std::size_t>(points.cols()));
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<std::uint32_t>(i);
    picked = &all;
  }
  if (picked->size() < 4) return fit_aabb(points, ids, padding);
  // The search runs on the points moved and scaled into [-1, 1]^3, where its squares and
  // products cannot overflow (they did at 1e300, and GMP then raised SIGFPE); the box's
  // directions do not change with that.
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
  for (std::uint32_t i : *picked) {
    lo = lo.cwiseMin(points.col(i));
    hi = hi.cwiseMax(points.col(i));
  }
  const Eigen::Vector3d mid = 0.5 * lo + 0.5 * hi;
  const double half = (0.5 * hi - 0.5 * lo).maxCoeff();
  const double scale = half > 0 ? 1 / half : 1;
  std::vector<K::Point_3> pts;
  pts.reserve(picked->size());
  for (std::uint32_t i : *picked) {
    const Eigen::Vector3d q = (Eigen::Vector3d(points.col(i)) - mid) * scale;
    pts.emplace_back(q.x(), q.y(), q.z());
  }
  // The affine map taking the box to an axis-aligned one; the rows of its rotation part
  // are the box's directions. A fixed seed makes the genetic search deterministic.
  CGAL::Aff_transformation_3<K> to_aligned;
  CGAL::oriented_bounding_box(pts, to_aligned, CGAL::parameters::use_convex_hull(true).random_seed(20261122));
  Eigen::Matrix3d directions;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) directions(c, r) = CGAL::to_double(to_aligned.m(r, c));
  return fit_box_along(points, ids, directions, padding);
}

}  // namespace ffd
