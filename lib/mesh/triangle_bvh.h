// A bounding volume hierarchy over triangles for closest-point queries: what the
// Hausdorff compare (mesh/hausdorff.h) spends its time in. CGAL's AABB_tree answers the
// same queries (and is the oracle in mesh_compare_test.cpp), but its 64-byte nodes over
// one triangle each and its recursive traversal made a 1M-vertex compare spend 2 s
// building trees and 0.75 µs per query; this one keeps both children's float boxes
// (rounded outward) in one 64-byte node, leaves of up to four triangles, and visits the
// nearer child first in a loop.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Core>

namespace ffd {

class TriangleBvh {
public:
  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

  TriangleBvh() = default;
  /// Builds over `triangles` (vertex ids into `xyz`, three doubles a vertex), which must
  /// both outlive the tree unchanged. The tree depends on the input only.
  TriangleBvh(const double* xyz, const std::vector<std::array<std::uint32_t, 3>>* triangles);

  struct Closest {
    double squared = std::numeric_limits<double>::infinity();
    std::uint32_t triangle = kNone;
  };
  /// The triangle closest to p: the smallest squared distance (ties: the triangle met
  /// first), starting from `hint`'s distance when it is a triangle.
  Closest closest(const Eigen::Vector3d& p, std::uint32_t hint) const;

  /// The squared distance from p to triangle t.
  double squared_distance(const Eigen::Vector3d& p, std::uint32_t t) const;

  /// The triangles in the order of the tree's leaves, depth first: nearby triangles
  /// together, the order that keeps a run of queries in cache.
  const std::vector<std::uint32_t>& leaf_order() const { return order_; }


private:
  // An inner node with its two children's boxes (rounded outward: a box holds its
  // triangles), so a step down the tree reads one cache line.
  struct alignas(64) Node {
    std::array<std::array<float, 3>, 2> lo, hi;
    std::array<std::uint32_t, 2> child;  // an inner node's index, or a leaf (see triangle_bvh.cpp)
  };
  struct Build;

  Eigen::Map<const Eigen::Vector3d> vertex(std::uint32_t v) const { return Eigen::Map<const Eigen::Vector3d>(xyz_ + 3 * std::size_t{v}); }

  const double* xyz_ = nullptr;
  const std::vector<std::array<std::uint32_t, 3>>* triangles_ = nullptr;
  std::vector<Node> nodes_;
  std::uint32_t root_ = 0;
  std::vector<std::uint32_t> order_;  // triangle ids, each leaf's contiguous
};

}  // namespace ffd
