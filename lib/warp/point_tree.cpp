#include "warp/point_tree.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <nanoflann.hpp>

namespace ffd {
namespace {

/// nanoflann's dataset interface over a vector of points.
struct Cloud {
  const std::vector<Eigen::Vector3d>& points;
  std::size_t kdtree_get_point_count() const { return points.size(); }
  double kdtree_get_pt(std::size_t i, std::size_t axis) const { return points[i][static_cast<Eigen::Index>(axis)]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const { return false; }
};

using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Cloud>, Cloud, 3, std::uint32_t>;

}  // namespace

struct PointTree::Impl {
  explicit Impl(const std::vector<Eigen::Vector3d>& points)
      : cloud{points}, tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {
    tree.buildIndex();
  }
  Cloud cloud;
  Tree tree;
};

PointTree::PointTree(const std::vector<Eigen::Vector3d>& points) : impl_(std::make_unique<Impl>(points)) {}
PointTree::~PointTree() = default;

void PointTree::within(const Eigen::Vector3d& x, double radius, std::vector<std::uint32_t>& ids) const {
  ids.clear();
  if (impl_->cloud.points.empty()) return;
  // nanoflann's radius is squared for L2 and its ball is open; widen it by one ulp-scale
  // step, then keep exactly the closed ball.
  const double r2 = radius * radius;
  thread_local std::vector<std::pair<std::uint32_t, double>> found;
  found.clear();
  impl_->tree.radiusSearch(x.data(), std::nextafter(r2, std::numeric_limits<double>::infinity()), found,
                           nanoflann::SearchParams(32, 0, false));
  for (const auto& [i, d2] : found)
    if (d2 <= r2) ids.push_back(i);
  std::sort(ids.begin(), ids.end());
}

std::pair<std::size_t, double> PointTree::nearest_other(std::size_t i) const {
  const std::vector<Eigen::Vector3d>& points = impl_->cloud.points;
  // The nearest two or more: i itself is among them unless other points share its place.
  std::size_t k = std::min<std::size_t>(points.size(), 2);
  while (true) {
    std::vector<std::uint32_t> ids(k);
    std::vector<double> d2(k);
    const std::size_t found = impl_->tree.knnSearch(points[i].data(), k, ids.data(), d2.data());
    std::pair<std::size_t, double> best{i, std::numeric_limits<double>::infinity()};
    for (std::size_t j = 0; j < found; ++j)
      if (ids[j] != i && (d2[j] < best.second || (d2[j] == best.second && ids[j] < best.first)))
        best = {ids[j], d2[j]};
    // Ties at the kth distance could hide a lower index: widen until the last found is farther.
    if (found < k || k == points.size() || d2[found - 1] > best.second) return {best.first, std::sqrt(best.second)};
    k = std::min(points.size(), 2 * k);
  }
}

}  // namespace ffd
