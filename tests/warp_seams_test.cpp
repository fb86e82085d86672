// The Warp interface the ops use instead of casting to a lattice (where a warp acts, its
// feature size), checked against independent computations; and the remesher leaving only
// the mesh's declared attributes behind.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "mesh/halfedge_view_cgal.h"
#include "remesh/adaptive_remesher.h"
#include "test_meshes.h"
#include "warp/bernstein_lattice.h"
#include "warp/bspline_lattice.h"
#include "warp/warp_stack.h"

namespace ffd {
namespace {

using test::skewed_box;

// Box coordinates by a QR solve of axes · u = x − origin (not the box's cached inverse).
Eigen::Vector3d box_coordinates(const Parallelepiped& box, const Eigen::Vector3d& x) {
  return box.axes().colPivHouseholderQr().solve(x - box.origin());
}

// Distance in box coordinates from u to the unit cube grown by kBoxTolerance.
double distance_to_grown_cube(const Eigen::Vector3d& u) {
  const Eigen::Vector3d lo = Eigen::Vector3d::Constant(-kBoxTolerance);
  const Eigen::Vector3d hi = Eigen::Vector3d::Constant(1 + kBoxTolerance);
  return (u - u.cwiseMax(lo).cwiseMin(hi)).norm();
}

// Whether segment [a, b] meets the grown box: the distance to a convex set is convex along
// the segment, so a ternary search finds its minimum; the segment meets the box where it
// is zero (to rounding far below the tolerance).
bool segment_meets_box(const Parallelepiped& box, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d ua = box_coordinates(box, a), ub = box_coordinates(box, b);
  const auto distance = [&](double t) { return distance_to_grown_cube(ua + t * (ub - ua)); };
  double lo = 0, hi = 1;
  for (int i = 0; i < 200; ++i) {
    const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
    if (distance(m1) <= distance(m2))
      hi = m2;
    else
      lo = m1;
  }
  return std::min({distance(0), distance(1), distance(0.5 * (lo + hi))}) < 1e-13;
}

struct SegmentCase {
  const char* what;
  Eigen::Vector3d a, b;  // box coordinates
  bool meets;
};

// Segments given in box coordinates: inside, crossing, outside, and touching a face or
// lying in a face's plane just within (or just beyond) the tolerance.
std::vector<SegmentCase> segment_cases() {
  const double within = 0.5 * kBoxTolerance, beyond = 20 * kBoxTolerance;
  using V = Eigen::Vector3d;
  return {
      {"inside", V(0.2, 0.3, 0.4), V(0.8, 0.7, 0.6), true},
      {"one point inside", V(0.5, 0.5, 0.5), V(0.5, 0.5, 0.5), true},
      {"one end inside", V(0.5, 0.5, 0.5), V(2.0, 0.4, 0.6), true},
      {"crossing through", V(-0.5, 0.5, 0.5), V(1.5, 0.5, 0.5), true},
      {"cutting a corner", V(-0.2, 0.3, 0.5), V(0.3, -0.2, 0.5), true},
      {"outside, one side", V(1.5, 0.5, 0.5), V(3.0, 0.2, 0.5), false},
      {"outside, line would cross", V(-2.0, 0.5, 0.5), V(-0.5, 0.5, 0.5), false},
      {"outside, past a corner", V(-0.5, 1.2, 0.5), V(0.5, 2.0, 0.5), false},
      {"one point outside", V(1.5, 1.5, 1.5), V(1.5, 1.5, 1.5), false},
      {"ends on a face, within", V(0.5, 0.5, 2.0), V(0.5, 0.5, 1 + within), true},
      {"ends near a face, beyond", V(0.5, 0.5, 2.0), V(0.5, 0.5, 1 + beyond), false},
      {"in a face's plane, within", V(0.1, 0.2, -within), V(0.9, 0.7, -within), true},
      {"in a face's plane, beyond", V(0.1, 0.2, -beyond), V(0.9, 0.7, -beyond), false},
      {"along an edge, within", V(1 + within, -0.5, 1 + within), V(1 + within, 1.5, 1 + within), true},
      {"along an edge, beyond", V(1 + within, -0.5, 1 + beyond), V(1 + within, 1.5, 1 + beyond), false},
      {"onto a corner, within", V(2.0, 3.0, 1.5), V(1 + within, 1 + within, 1 + within), true},
      {"slanting past a face, beyond", V(0.5, -0.5, 1 + beyond), V(0.5, 1.5, 1 + 2 * beyond), false},
  };
}

void expect_segments(const Lattice& lattice) {
  const Parallelepiped& box = lattice.box();
  for (const SegmentCase& c : segment_cases()) {
    const Eigen::Vector3d a = box.to_world(c.a), b = box.to_world(c.b);
    EXPECT_EQ(segment_meets_box(box, a, b), c.meets) << "independent check: " << c.what;
    EXPECT_EQ(lattice.can_act_on_segment(a, b), c.meets) << c.what;
    EXPECT_EQ(lattice.can_act_on_segment(b, a), c.meets) << c.what << ", reversed";
  }
}

// Random segments around the box agree with the independent test, and where the lattice
// says it cannot act, a deformed lattice leaves the segment's points alone bit for bit.
void expect_random_segments(Lattice& lattice) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uniform(-0.6, 1.6), offset(-0.1, 0.1);
  for (std::size_t f = 0; f < lattice.num_points(); ++f) {
    const Index3 ijk = lattice.index(f);
    if (lattice.movable(ijk)) lattice.move_point(ijk, lattice.point(ijk) + Eigen::Vector3d(offset(rng), offset(rng), offset(rng)));
  }
  lattice.prepare();
  int outside = 0, inside = 0;
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d a = lattice.box().to_world(Eigen::Vector3d(uniform(rng), uniform(rng), uniform(rng)));
    const Eigen::Vector3d b = a + 0.3 * lattice.box().axes() * Eigen::Vector3d(offset(rng), offset(rng), offset(rng)) / 0.1;
    const bool acts = lattice.can_act_on_segment(a, b);
    ASSERT_EQ(acts, segment_meets_box(lattice.box(), a, b)) << "segment " << i;
    (acts ? inside : outside) += 1;
    if (acts) continue;
    for (int s = 0; s <= 20; ++s) {
      const Eigen::Vector3d x = a + (s / 20.0) * (b - a);
      ASSERT_EQ(lattice.apply(x, nullptr), x) << "segment " << i << " sample " << s;
    }
  }
  EXPECT_GT(inside, 100);
  EXPECT_GT(outside, 100);
}

// min over the axes of |edge vector| / cells, from the box's axes.
double expected_feature_size(const Parallelepiped& box, const Index3& cells) {
  double smallest = INFINITY;
  for (int a = 0; a < 3; ++a) {
    const Eigen::Vector3d edge = box.axes().col(a);
    smallest = std::min(smallest, std::sqrt(edge.x() * edge.x() + edge.y() * edge.y() + edge.z() * edge.z()) / cells[a]);
  }
  return smallest;
}

TEST(WarpSeams, BSplineLatticeActsWhereSegmentsMeetItsBox) {
  for (int degree : {1, 2, 3}) {
    BSplineLattice lattice(skewed_box(), Index3{5, 6, 4}, degree);
    SCOPED_TRACE("degree " + std::to_string(degree));
    expect_segments(lattice);
    expect_random_segments(lattice);
  }
}

TEST(WarpSeams, BernsteinLatticeActsWhereSegmentsMeetItsBox) {
  BernsteinLattice lattice(skewed_box(), Index3{3, 5, 2});
  expect_segments(lattice);
  expect_random_segments(lattice);
}

TEST(WarpSeams, FeatureSizeIsTheSmallestCellExtent) {
  const Parallelepiped skewed = skewed_box();
  const Parallelepiped flat = Parallelepiped::from_min_max(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(3, 2, 0.5));
  for (const Parallelepiped& box : {skewed, flat}) {
    for (const Index3& cells : {Index3{5, 6, 4}, Index3{8, 4, 4}, Index3{4, 4, 9}}) {
      const BSplineLattice bspline(box, cells, 3);
      EXPECT_NEAR(bspline.feature_size(), expected_feature_size(box, cells), 1e-15);
    }
    const BernsteinLattice bernstein(box, Index3{3, 5, 2});
    EXPECT_NEAR(bernstein.feature_size(), expected_feature_size(box, Index3{3, 5, 2}), 1e-15);
  }
  // The flat box: 3/5, 2/6, 0.5/4 for the B-spline; 3/3, 2/5, 0.5/2 for Bernstein.
  EXPECT_NEAR(BSplineLattice(flat, Index3{5, 6, 4}, 3).feature_size(), 0.125, 1e-15);
  EXPECT_NEAR(BernsteinLattice(flat, Index3{3, 5, 2}).feature_size(), 0.25, 1e-15);
}

// A warp that bounds nothing: the Warp defaults (acts everywhere, no feature size).
class Everywhere : public Warp {
public:
  Eigen::Vector3d apply(const Eigen::Vector3d& x, Eigen::Matrix3d* jacobian) const override {
    if (jacobian) jacobian->setIdentity();
    return x;
  }
  void apply(const Eigen::Ref<const Eigen::Matrix3Xd>&, const Eigen::Ref<const Eigen::Matrix3Xd>&,
             const std::vector<std::uint32_t>&, Eigen::Ref<Eigen::Matrix3Xd>, Eigen::Ref<Eigen::Matrix3Xd>,
             WarpCounts&) const override {}
  void changed_points(const Eigen::Ref<const Eigen::Matrix3Xd>&, std::vector<std::uint32_t>&) const override {}
  bool has_changes() const override { return false; }
  void clear_changes() override {}
};

TEST(WarpSeams, StackLmaxIsTheSmallestFeatureSizeOfItsWarps) {
  Mesh mesh = test::grid_mesh(4);
  WarpStack stack;
  EXPECT_EQ(smallest_cell_extent(stack), 0);
  stack.push(mesh, "any", std::make_unique<Everywhere>());
  EXPECT_TRUE(stack.warp(0).can_act_on_segment(Eigen::Vector3d(100, 0, 0), Eigen::Vector3d(200, 0, 0)));
  EXPECT_EQ(smallest_cell_extent(stack), 0);  // no scale: not a zero Lmax
  const Parallelepiped box = Parallelepiped::from_min_max(Eigen::Vector3d(-0.1, -0.1, -1), Eigen::Vector3d(1.1, 1.1, 1));
  stack.push(mesh, "coarse", std::make_unique<BernsteinLattice>(box, Index3{2, 2, 2}));
  stack.push(mesh, "fine", std::make_unique<BSplineLattice>(box, Index3{6, 8, 4}, 3));
  EXPECT_NEAR(smallest_cell_extent(stack), 1.2 / 8, 1e-15);
}

// What a mesh may carry after a remesh step besides what it had before: the refinement
// levels, and the cached halfedge view with its standard properties, the declared
// face starts and a copy of each vec3 attribute; scratch data is none of these.
std::set<std::string> declared_after_remesh(const Mesh& mesh, const std::set<std::string>& before) {
  std::set<std::string> names = before;
  names.insert({mesh_attribute::kVertexLevel, mesh_attribute::kEdgeLevel});
  for (const std::string& n : view_property_names(HalfedgeView())) names.insert("view " + n);
  for (const std::string& n : mesh.vec3_attribute_names()) names.insert("view v:attr:" + n);
  return names;
}

// Every name of `names` is in `allowed`.
void expect_only(const std::vector<std::string>& names, const std::set<std::string>& allowed) {
  for (const std::string& n : names) EXPECT_TRUE(allowed.count(n)) << "undeclared attribute " << n;
}

TEST(WarpSeams, RemeshLeavesOnlyTheDeclaredAttributes) {
  Mesh mesh = test::grid_mesh(12, nullptr, true);  // quads: the triangulation's scratch too
  WarpStack stack;
  const Parallelepiped box = Parallelepiped::from_min_max(Eigen::Vector3d(-0.01, -0.01, -0.5), Eigen::Vector3d(1.01, 1.01, 0.5));
  auto lower = std::make_unique<BSplineLattice>(box, Index3{6, 6, 4}, 3);
  BSplineLattice* a = lower.get();
  stack.push(mesh, "a", std::move(lower));
  auto upper = std::make_unique<BernsteinLattice>(box, Index3{3, 3, 2});
  BernsteinLattice* b = upper.get();
  stack.push(mesh, "b", std::move(upper));
  a->move_point({3, 3, 2}, a->point({3, 3, 2}) + Eigen::Vector3d(0, 0, 0.4));
  b->move_point({1, 2, 1}, b->point({1, 2, 1}) + Eigen::Vector3d(0, 0, 0.2));
  stack.update(mesh, "a");
  stack.update(mesh, "b");

  HalfedgeCache cache;
  const std::vector<std::string> names = attribute_names(mesh, cache);
  const std::set<std::string> allowed = declared_after_remesh(mesh, {names.begin(), names.end()});
  const RemeshStats stats = adaptive_remesh(mesh, cache, stack, RemeshOptions{});
  ASSERT_GT(stats.triangulated_faces, 0u);
  ASSERT_GT(stats.refinements, 0u);
  const std::vector<std::string> after = attribute_names(mesh, cache);
  expect_only(after, allowed);
  for (const char* n : {mesh_attribute::kVertexLevel, mesh_attribute::kEdgeLevel, "view f:start"})
    EXPECT_TRUE(std::count(after.begin(), after.end(), n)) << n;

  // Back at rest: decimation reads the persisted levels and unwinds every refinement.
  a->move_point({3, 3, 2}, a->rest_point({3, 3, 2}));
  b->move_point({1, 2, 1}, b->rest_point({1, 2, 1}));
  stack.update(mesh, "a");
  stack.update(mesh, "b");
  const RemeshStats back = adaptive_remesh(mesh, cache, stack, RemeshOptions{});
  EXPECT_EQ(back.decimations, stats.refinements);
  expect_only(attribute_names(mesh, cache), allowed);
  const std::vector<int> levels = vertex_levels(mesh);
  EXPECT_EQ(*std::max_element(levels.begin(), levels.end()), 0);
}

}  // namespace
}  // namespace ffd
