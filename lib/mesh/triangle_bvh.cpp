#include "mesh/triangle_bvh.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "mesh/point_triangle.h"

namespace ffd {

namespace {

constexpr std::uint32_t kLeafSize = 4;
constexpr std::uint32_t kLeafFlag = 0x80000000u;

float round_down(double x) {
  const auto f = static_cast<float>(x);
  return static_cast<double>(f) > x ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}

float round_up(double x) {
  const auto f = static_cast<float>(x);
  return static_cast<double>(f) < x ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

// A child reference: an inner node's index, or a leaf's first entry of order_ and count.
std::uint32_t leaf_code(std::uint32_t first, std::uint32_t count) { return kLeafFlag | first << 3 | count; }
bool is_leaf(std::uint32_t code) { return code & kLeafFlag; }
std::uint32_t leaf_first(std::uint32_t code) { return (code & ~kLeafFlag) >> 3; }
std::uint32_t leaf_count(std::uint32_t code) { return code & 7; }

}  // namespace

// The top-down build: each node's triangles split at the median of their centroids
// along the longest axis of the centroids' box (ties by triangle id, so the tree depends
// on the input only); boxes from the leaves up.
struct TriangleBvh::Build {
  struct Item {
    std::array<double, 3> centroid;
    std::uint32_t id;
  };
  using Box = std::pair<std::array<float, 3>, std::array<float, 3>>;
  TriangleBvh& tree;
  std::vector<Item> items;  // moved by the splits themselves: the selection reads them in order
  std::map<std::uint32_t, std::size_t> nodes_of;  // subtree_nodes' answers (two sizes a level)

  // The inner nodes of a subtree over `count` triangles (split in halves down to leaves).
  std::size_t subtree_nodes(std::uint32_t count) {
    if (count <= kLeafSize) return 0;
    const auto known = nodes_of.find(count);
    if (known != nodes_of.end()) return known->second;
    return nodes_of[count] = 1 + subtree_nodes(count / 2) + subtree_nodes(count - count / 2);
  }

  // Puts items[first, first + count)'s lower half by centroid before its upper half.
  void split(std::uint32_t first, std::uint32_t count) {
    std::array<double, 3> lo = items[first].centroid, hi = lo;
    for (std::uint32_t i = first + 1; i < first + count; ++i)
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], items[i].centroid[a]);
        hi[a] = std::max(hi[a], items[i].centroid[a]);
      }
    int axis = 0;
    for (int a = 1; a < 3; ++a)
      if (hi[a] - lo[a] > hi[axis] - lo[axis]) axis = a;
    const auto begin = items.begin() + first;
    std::nth_element(begin, begin + count / 2, begin + count, [axis](const Item& a, const Item& b) {
      return a.centroid[axis] < b.centroid[axis] || (a.centroid[axis] == b.centroid[axis] && a.id < b.id);
    });
  }

  // The subtree over items[first, first + count) placed at node `index` (when inner):
  // its code and box.
  std::pair<std::uint32_t, Box> subtree(std::size_t index, std::uint32_t first, std::uint32_t count) {
    if (count <= kLeafSize) return {leaf_code(first, count), leaf_box(first, count)};
    split(first, count);
    // Depth first: the left child follows its parent, the right one the left's subtree.
    const std::uint32_t half = count / 2;
    Node node;
    const auto [left, left_box] = subtree(index + 1, first, half);
    const auto [right, right_box] = subtree(index + 1 + subtree_nodes(half), first + half, count - half);
    node.child = {left, right};
    node.lo = {left_box.first, right_box.first};
    node.hi = {left_box.second, right_box.second};
    tree.nodes_[index] = node;
    Box box;
    for (int a = 0; a < 3; ++a) {
      box.first[a] = std::min(left_box.first[a], right_box.first[a]);
      box.second[a] = std::max(left_box.second[a], right_box.second[a]);
    }
    return {static_cast<std::uint32_t>(index), box};
  }

  Box leaf_box(std::uint32_t first, std::uint32_t count) const {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (std::uint32_t i = first; i < first + count; ++i)
      for (const std::uint32_t v : (*tree.triangles_)[items[i].id]) {
        lo = lo.cwiseMin(tree.vertex(v));
        hi = hi.cwiseMax(tree.vertex(v));
      }
    Box box;
    for (int a = 0; a < 3; ++a) {
      box.first[a] = round_down(lo[a]);
      box.second[a] = round_up(hi[a]);
    }
    return box;
  }
};

TriangleBvh::TriangleBvh(const double* xyz, const std::vector<std::array<std::uint32_t, 3>>* triangles)
    : xyz_(xyz), triangles_(triangles) {
  const auto n = static_cast<std::uint32_t>(triangles->size());
  if (n == 0) return;
  if (n >= kLeafFlag >> 3) throw std::length_error("more than 2^28 triangles for one tree");
  Build build{*this, std::vector<Build::Item>(n), {}};
  for (std::uint32_t t = 0; t < n; ++t) {
    const std::array<std::uint32_t, 3>& v = (*triangles)[t];
    const Eigen::Vector3d c = (vertex(v[0]) + vertex(v[1]) + vertex(v[2])) / 3;
    build.items[t] = {{c.x(), c.y(), c.z()}, t};
  }
  nodes_.resize(build.subtree_nodes(n));
  root_ = build.subtree(0, 0, n).first;
  order_.resize(n);
  for (std::uint32_t i = 0; i < n; ++i) order_[i] = build.items[i].id;
}

double TriangleBvh::squared_distance(const Eigen::Vector3d& p, std::uint32_t t) const {
  const std::array<std::uint32_t, 3>& v = (*triangles_)[t];
  return point_triangle_squared_distance(p, vertex(v[0]), vertex(v[1]), vertex(v[2]));
}

namespace {

double box_squared_distance(const std::array<float, 3>& lo, const std::array<float, 3>& hi, const double* p) {
  double d = 0;
  for (int a = 0; a < 3; ++a) {
    // At most one of the two is positive.
    const double e = std::max(double(lo[a]) - p[a], 0.0) + std::max(p[a] - double(hi[a]), 0.0);
    d += e * e;
  }
  return d;
}

}  // namespace

TriangleBvh::Closest TriangleBvh::closest(const Eigen::Vector3d& p, std::uint32_t hint) const {
  Closest best;
  if (order_.empty()) return best;
  if (hint != kNone) best = {squared_distance(p, hint), hint};
  // Subtrees still to visit with their box distances; the nearer child goes first.
  std::array<std::pair<std::uint32_t, double>, 64> stack;
  std::size_t top = 0;
  stack[top++] = {root_, 0.0};
  while (top) {
    const auto [code, box] = stack[--top];
    if (box >= best.squared) continue;
    if (is_leaf(code)) {
      for (std::uint32_t i = leaf_first(code); i < leaf_first(code) + leaf_count(code); ++i) {
        const double d = squared_distance(p, order_[i]);
        if (d < best.squared) best = {d, order_[i]};
      }
      continue;
    }
    const Node& node = nodes_[code];
    const double a = box_squared_distance(node.lo[0], node.hi[0], p.data()),
                 b = box_squared_distance(node.lo[1], node.hi[1], p.data());
    const int near = a <= b ? 0 : 1;
    const double dn = near ? b : a, df = near ? a : b;
    if (df < best.squared) stack[top++] = {node.child[1 - near], df};
    if (dn < best.squared) stack[top++] = {node.child[near], dn};
  }
  return best;
}

}  // namespace ffd
