#include "mesh/surface_index.h"

#include <CGAL/AABB_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>

#include "mesh/halfedge_view_cgal.h"
#include "mesh/point_triangle.h"

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
    return {to_point(m.index->vertex(v[0])), to_point(m.index->vertex(v[1])), to_point(m.index->vertex(v[2]))};
  }
};

struct CornerMap {
  const SurfaceIndex* index = nullptr;
  using key_type = std::uint32_t;
  using value_type = Point3;
  using reference = value_type;
  using category = boost::readable_property_map_tag;
  friend value_type get(const CornerMap& m, key_type t) { return to_point(m.index->vertex(m.index->triangle(t)[0])); }
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

SurfaceIndex::SurfaceIndex(const Mesh& mesh) : mesh_(mesh), vertex_triangle_(mesh.num_vertices(), kNone) {
  const MeshElements& el = mesh.elements();
  for (std::size_t e = 0; e < el.size(); ++e) {
    if (el.kinds[e] != ElementKind::Polygon) continue;
    const std::uint32_t* v = el.vertices(e);
    for (std::uint32_t i = 1; i + 1 < el.degree(e); ++i) {
      const auto t = static_cast<std::uint32_t>(triangles_.size());
      triangles_.push_back({v[0], v[i], v[i + 1]});
      for (const std::uint32_t corner : triangles_.back())
        if (vertex_triangle_[corner] == kNone) vertex_triangle_[corner] = t;
    }
  }
  tree_ = std::make_unique<Tree>();
  if (triangles_.empty()) return;
  std::vector<std::uint32_t> ids(triangles_.size());
  for (std::size_t t = 0; t < ids.size(); ++t) ids[t] = static_cast<std::uint32_t>(t);
  tree_->tree.insert(ids.begin(), ids.end(), TriangleMap{this}, CornerMap{this});
  tree_->tree.build();
}

SurfaceIndex::~SurfaceIndex() = default;

double SurfaceIndex::squared_distance(const Eigen::Vector3d& p, std::uint32_t t) const {
  const std::array<std::uint32_t, 3>& v = triangles_[t];
  return point_triangle_squared_distance(p, vertex(v[0]), vertex(v[1]), vertex(v[2]));
}

SurfaceIndex::Closest SurfaceIndex::closest(const Eigen::Vector3d& p, std::uint32_t hint) const {
  ClosestSearch search(*this, p);
  if (triangles_.empty()) return search.best;
  search.visit(hint != kNone ? hint : 0);
  if (triangles_.size() > 1) tree_->tree.traversal_with_priority(to_point(p), search);
  return search.best;
}

}  // namespace ffd
