#include "mesh/surface_index.h"

#include <CGAL/AABB_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>

#include "mesh/halfedge_view_cgal.h"
#include "mesh/point_triangle.h"

#include <algorithm>

namespace ffd {

namespace {

// CGAL's primitive is a triangle's number; the tree keeps the two maps below once
// (external property maps), so a primitive costs 4 bytes.
struct TriangleMap {
  const SurfaceIndex* index = nullptr;
  using key_type = std::uint32_t;
  using value_type = Kernel::Triangle_3;
  using reference = value_type;
  using category = boost::readable_property_map_tag;
  friend value_type get(const TriangleMap& m, key_type t) {
    const std::array<std::uint32_t, 3>& v = m.index->triangle(t);
    return {to_point(m.index->point(v[0])), to_point(m.index->point(v[1])), to_point(m.index->point(v[2]))};
  }
};

struct CornerMap {
  const SurfaceIndex* index = nullptr;
  using key_type = std::uint32_t;
  using value_type = Point3;
  using reference = value_type;
  using category = boost::readable_property_map_tag;
  friend value_type get(const CornerMap& m, key_type t) { return to_point(m.index->point(m.index->triangle(t)[0])); }
};

using Primitive = CGAL::AABB_primitive<std::uint32_t, TriangleMap, CornerMap, CGAL::Tag_true, CGAL::Tag_false>;
using AabbTree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

// A closest-triangle search for CGAL's traversal_with_priority: the nearer child's box
// first, a box skipped when it lies no nearer than the best triangle so far; triangles
// measured with point_triangle_squared_distance, several times cheaper than CGAL's
// squared_distance(Point_3, Triangle_3) (which the tests compare it with).
class ClosestSearch {
public:
  using Priority = double;

  ClosestSearch(const SurfaceIndex& index, const Eigen::Vector3d& p) : index_(index), p_(p) {}

  bool go_further() const { return true; }
  void intersection(const Point3&, const Primitive& primitive) { visit(primitive.id()); }
  template <class Node>
  bool do_intersect(const Point3&, const Node& node) const {
    return box_squared_distance(node.bbox()) < best.squared;
  }
  template <class Node>
  std::pair<bool, double> do_intersect_with_priority(const Point3&, const Node& node) const {
    const double d = box_squared_distance(node.bbox());
    return {d < best.squared, -d};
  }

  void visit(std::uint32_t t) {
    const double d = index_.squared_distance(p_, t);
    if (d < best.squared) best = {d, t};
  }

  SurfaceIndex::Closest best;

private:
  double box_squared_distance(const CGAL::Bbox_3& box) const {
    double d = 0;
    for (int a = 0; a < 3; ++a) {
      const double e = std::max(box.min(a) - p_[a], 0.0) + std::max(p_[a] - box.max(a), 0.0);
      d += e * e;
    }
    return d;
  }

  const SurfaceIndex& index_;
  Eigen::Vector3d p_;
};

}  // namespace

struct SurfaceIndex::Tree {
  AabbTree tree;
};

namespace {

// x's low 21 bits spread to every third bit.
std::uint64_t spread_bits(std::uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

// The mesh's polygons fanned from their first corners, in mesh vertex numbers.
std::vector<std::array<std::uint32_t, 3>> fanned_polygons(const Mesh& mesh) {
  std::vector<std::array<std::uint32_t, 3>> out;
  const MeshElements& el = mesh.elements();
  for (std::size_t e = 0; e < el.size(); ++e) {
    if (el.kinds[e] != ElementKind::Polygon) continue;
    const std::uint32_t* v = el.vertices(e);
    for (std::uint32_t i = 1; i + 1 < el.degree(e); ++i) out.push_back({v[0], v[i], v[i + 1]});
  }
  return out;
}

// The order of `triangles` along a Morton curve through their centroids (21 bits an axis
// over the centroids' box; ties by place, so the order depends on the input only).
std::vector<std::uint32_t> morton_order(const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                        const ConstVec3Array& p) {
  const auto centroid = [&](std::size_t t) -> Eigen::Vector3d {
    return (p.col(triangles[t][0]) + p.col(triangles[t][1]) + p.col(triangles[t][2])) / 3;
  };
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    lo = lo.cwiseMin(centroid(t));
    hi = hi.cwiseMax(centroid(t));
  }
  const Eigen::Vector3d scale = 2097151.0 * (hi - lo).cwiseMax(1e-300).cwiseInverse();
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keys(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const Eigen::Vector3d q = (centroid(t) - lo).cwiseProduct(scale);
    std::uint64_t code = 0;
    for (int a = 0; a < 3; ++a) code |= spread_bits(static_cast<std::uint64_t>(std::clamp(q[a], 0.0, 2097151.0))) << a;
    keys[t] = {code, static_cast<std::uint32_t>(t)};
  }
  std::sort(keys.begin(), keys.end());
  std::vector<std::uint32_t> order(keys.size());
  for (std::size_t i = 0; i < keys.size(); ++i) order[i] = keys[i].second;
  return order;
}

}  // namespace

SurfaceIndex::SurfaceIndex(const Mesh& mesh) : positions_(mesh.positions()), point_of_vertex_(mesh.num_vertices(), kNone) {
  number_in_morton_order(mesh);
  tree_ = std::make_unique<Tree>();
  if (triangles_.empty()) return;
  std::vector<std::uint32_t> ids(triangles_.size());
  for (std::size_t t = 0; t < ids.size(); ++t) ids[t] = static_cast<std::uint32_t>(t);
  tree_->tree.insert(ids.begin(), ids.end(), TriangleMap{this}, CornerMap{this});
  tree_->tree.build();
}

void SurfaceIndex::number_in_morton_order(const Mesh& mesh) {
  const std::vector<std::array<std::uint32_t, 3>> fans = fanned_polygons(mesh);
  const ConstVec3Array p = mesh.positions();
  fan_index_ = morton_order(fans, p);
  triangle_at_fan_.resize(fans.size());
  triangles_.resize(fans.size());
  // Points numbered as the sorted triangles first use them.
  for (std::uint32_t t = 0; t < fans.size(); ++t) {
    triangle_at_fan_[fan_index_[t]] = t;
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t v = fans[fan_index_[t]][i];
      if (point_of_vertex_[v] == kNone) {
        point_of_vertex_[v] = static_cast<std::uint32_t>(mesh_vertex_.size());
        mesh_vertex_.push_back(v);
        point_triangle_.push_back(t);
      }
      triangles_[t][i] = point_of_vertex_[v];
    }
  }
}

SurfaceIndex::~SurfaceIndex() = default;

double SurfaceIndex::squared_distance(const Eigen::Vector3d& p, std::uint32_t t) const {
  const std::array<std::uint32_t, 3>& v = triangles_[t];
  return point_triangle_squared_distance(p, point(v[0]), point(v[1]), point(v[2]));
}

SurfaceIndex::Closest SurfaceIndex::closest(const Eigen::Vector3d& p, std::uint32_t hint) const {
  ClosestSearch search(*this, p);
  if (triangles_.empty()) return search.best;
  search.visit(hint != kNone ? hint : 0);
  if (triangles_.size() > 1) tree_->tree.traversal_with_priority(to_point(p), search);
  return search.best;
}

}  // namespace ffd
