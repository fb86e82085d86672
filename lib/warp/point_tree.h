// PointTree: a k-d tree over a fixed list of points (nanoflann), for the scattered
// deformers' neighbour searches: the points within a radius (compact kernels) and each
// point's nearest other point (spacing). nanoflann stays inside point_tree.cpp.
#pragma once

#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include <Eigen/Dense>

namespace ffd {

class PointTree {
public:
  /// Indexes `points`, which must outlive the tree and stay unchanged.
  explicit PointTree(const std::vector<Eigen::Vector3d>& points);
  ~PointTree();
  PointTree(const PointTree&) = delete;
  PointTree& operator=(const PointTree&) = delete;

  /// The indices of the points within distance `radius` of x (closed ball), ascending, so
  /// results do not depend on the tree's traversal.
  void within(const Eigen::Vector3d& x, double radius, std::vector<std::uint32_t>& ids) const;
  /// The nearest point to `points[i]` other than i itself (ties: the lowest index), and the
  /// distance to it; (i, inf) for a single point.
  std::pair<std::size_t, double> nearest_other(std::size_t i) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ffd
