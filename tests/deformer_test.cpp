// The Deformer seam and what it gives every kind: sensitivities dx/dp against central
// finite differences (one lattice of each kind, an octree level after moves at coarser
// levels, a lattice followed by another), their linearity, the identity of an unmoved
// deformer, and drag through the weights.
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <sstream>

#include "multires/octree_lattice.h"
#include "test_meshes.h"
#include "warp/bernstein_lattice.h"
#include "warp/box_fit.h"
#include "warp/bspline_lattice.h"
#include "warp/cage_deformer.h"
#include "warp/drag.h"
#include "warp/idw_deformer.h"
#include "warp/rbf_deformer.h"
#include "warp/sensitivity.h"
#include "warp/warp_stack.h"

namespace ffd {
namespace {

/// A Matrix Market coordinate matrix read back: (row, column) -> value, 0-based, and the
/// header's sizes and point comments.
struct Market {
  std::size_t rows = 0, cols = 0, entries = 0;
  std::map<std::pair<std::size_t, std::size_t>, double> values;
  std::vector<std::string> points;  // "% point m index ..." lines
};

Market parse_market(const std::string& text) {
  Market m;
  std::istringstream is(text);
  std::string line;
  std::getline(is, line);
  EXPECT_EQ(line, "%%MatrixMarket matrix coordinate real general");
  while (std::getline(is, line) && line[0] == '%')
    if (line.rfind("% point ", 0) == 0) m.points.push_back(line);
  std::istringstream(line) >> m.rows >> m.cols >> m.entries;
  std::size_t r, c;
  double v;
  while (is >> r >> c >> v) m.values[{r - 1, c - 1}] = v;
  EXPECT_EQ(m.values.size(), m.entries);
  return m;
}

Market sensitivity(const WarpStack& stack, std::size_t k, const Deformer& d, int level, const Mesh& mesh) {
  std::ostringstream os;
  const SensitivityCounts counts = write_sensitivity(os, stack, k, d, level, mesh);
  Market m = parse_market(os.str());
  EXPECT_EQ(m.rows, counts.rows);
  EXPECT_EQ(m.cols, counts.columns);
  EXPECT_EQ(m.rows, 3 * mesh.num_vertices());
  return m;
}

/// The movable ids of a level, in net order (column m is the m-th).
std::vector<std::size_t> movable_ids(const Deformer& d, int level) {
  std::vector<std::size_t> ids;
  for (std::size_t id = 0; id < d.num_points(level); ++id)
    if (d.point_movable(level, id)) ids.push_back(id);
  return ids;
}

void set_point(Deformer& d, int level, std::size_t id, const Eigen::Vector3d& p, WarpStack& stack, Mesh& mesh,
               const std::string& name) {
  d.move_points(level, {id}, {p});
  stack.update(mesh, name);
}

/// Checks columns of dx/dp against central differences with h = 1e-6 of the deformer's
/// scale, for `count` movable points with non-empty columns (spread over the net).
void expect_matches_finite_differences(WarpStack& stack, const std::string& name, int level, Mesh& mesh,
                                       std::size_t count) {
  const std::size_t k = stack.index_of(name);
  Deformer& d = dynamic_cast<Deformer&>(stack.warp(k));
  const Market m = sensitivity(stack, k, d, level, mesh);
  std::map<std::size_t, std::vector<std::pair<std::size_t, double>>> by_column;
  for (const auto& [rc, v] : m.values) by_column[rc.second].push_back({rc.first, v});
  const std::vector<std::size_t> ids = movable_ids(d, level);
  ASSERT_EQ(m.cols, 3 * ids.size());
  std::vector<std::size_t> used;
  for (std::size_t mi = 0; mi < ids.size(); ++mi)
    if (by_column.count(3 * mi)) used.push_back(mi);
  ASSERT_FALSE(used.empty()) << "no point of lattice " << name << " reaches a vertex";
  const double h = 1e-6 * d.scale();
  const std::size_t step = std::max<std::size_t>(1, used.size() / count);
  for (std::size_t u = 0; u < used.size(); u += step) {
    const std::size_t mi = used[u], id = ids[mi];
    const Eigen::Vector3d p = d.points(level, {id}).col(0);
    for (int a = 0; a < 3; ++a) {
      set_point(d, level, id, p + h * Eigen::Vector3d::Unit(a), stack, mesh, name);
      const Eigen::Matrix3Xd plus = mesh.positions();
      set_point(d, level, id, p - h * Eigen::Vector3d::Unit(a), stack, mesh, name);
      const Eigen::Matrix3Xd minus = mesh.positions();
      set_point(d, level, id, p, stack, mesh, name);
      const Eigen::Matrix3Xd fd = (plus - minus) / (2 * h);
      Eigen::Matrix3Xd exact = Eigen::Matrix3Xd::Zero(3, fd.cols());
      for (const auto& [row, v] : by_column[3 * mi + static_cast<std::size_t>(a)])
        exact(static_cast<Eigen::Index>(row % 3), static_cast<Eigen::Index>(row / 3)) = v;
      const double scale = std::max(exact.cwiseAbs().maxCoeff(), 1e-300);
      EXPECT_LE((fd - exact).cwiseAbs().maxCoeff() / scale, 1e-7) << name << " point " << id << " axis " << a;
    }
  }
}

Parallelepiped box_of(const Mesh& mesh, double padding) { return fit_aabb(mesh.positions(), {}, padding); }

/// Pushes `warp` on `stack` as `name`; returns it.
template <class W>
W& push(WarpStack& stack, Mesh& mesh, const std::string& name, std::unique_ptr<W> warp) {
  W& raw = *warp;
  stack.push(mesh, name, std::move(warp));
  return raw;
}

/// Moves lattice point `ijk` by `d` and re-evaluates the mesh.
void nudge(Lattice& l, const Index3& ijk, const Eigen::Vector3d& d, WarpStack& stack, Mesh& mesh,
           const std::string& name) {
  l.move_point(ijk, l.point(ijk) + d);
  stack.update(mesh, name);
}

TEST(Sensitivity, BSplineLatticeMatchesFiniteDifferences) {
  Mesh mesh = test::bunny();
  WarpStack stack;
  auto& l = push(stack, mesh, "L", std::make_unique<BSplineLattice>(box_of(mesh, 0.05), Index3{6, 5, 7}, 3));
  nudge(l, {3, 3, 3}, Eigen::Vector3d(0.4, 0.7, -0.2), stack, mesh, "L");
  expect_matches_finite_differences(stack, "L", 0, mesh, 8);
}

TEST(Sensitivity, BernsteinLatticeMatchesFiniteDifferences) {
  Mesh mesh = test::bunny();
  WarpStack stack;
  auto& l = push(stack, mesh, "L", std::make_unique<BernsteinLattice>(box_of(mesh, 0.05), Index3{3, 4, 3}));
  nudge(l, {1, 2, 1}, Eigen::Vector3d(0.5, -0.3, 0.2), stack, mesh, "L");
  expect_matches_finite_differences(stack, "L", 0, mesh, 8);
}

TEST(Sensitivity, OctreeLevelAfterCoarserMovesMatchesFiniteDifferences) {
  Mesh mesh = test::bunny();
  WarpStack stack;
  OctreeOptions options;
  options.levels = 3;
  auto& l = push(stack, mesh, "O",
                 std::make_unique<OctreeLattice>(fit_principal_box(mesh.positions(), {}, 0.02),
                                                 Eigen::Matrix3Xd(mesh.positions()), options));
  const double s = l.scale();
  l.move_level_points(0, std::vector<std::int32_t>{l.point_index(0, {1, 1, 1})},
                {l.points(0).col(l.point_index(0, {1, 1, 1})) + Eigen::Vector3d(0.02, 0.03, 0) * s});
  stack.update(mesh, "O");
  const std::int32_t p1 = l.point_index(1, {1, 2, 1});
  ASSERT_GE(p1, 0);
  l.move_level_points(1, std::vector<std::int32_t>{p1}, {l.points(1).col(p1) + Eigen::Vector3d(0, -0.02, 0.02) * s});
  stack.update(mesh, "O");
  expect_matches_finite_differences(stack, "O", 2, mesh, 6);
}

TEST(Sensitivity, ChainRuleThroughALaterLattice) {
  Mesh mesh = test::bunny();
  WarpStack stack;
  auto& a = push(stack, mesh, "A", std::make_unique<BSplineLattice>(box_of(mesh, 0.05), Index3{5, 5, 5}, 3));
  nudge(a, {2, 3, 2}, Eigen::Vector3d(0.3, 0.5, 0), stack, mesh, "A");
  auto& b = push(stack, mesh, "B", std::make_unique<BernsteinLattice>(box_of(mesh, 0.02), Index3{2, 3, 2}));
  nudge(b, {1, 2, 1}, Eigen::Vector3d(1.0, 0.4, -0.6), stack, mesh, "B");
  nudge(b, {1, 1, 1}, Eigen::Vector3d(-0.5, 0.2, 0.8), stack, mesh, "B");
  // Off-diagonal entries: the later lattice mixes the axes.
  const Market m = sensitivity(stack, 0, a, 0, mesh);
  std::size_t off = 0;
  for (const auto& [rc, v] : m.values) off += rc.first % 3 != rc.second % 3;
  EXPECT_GT(off, 0u);
  expect_matches_finite_differences(stack, "A", 0, mesh, 8);
}

/// Every 90th bunny vertex as an RBF's control points.
std::vector<Eigen::Vector3d> rbf_points(const Mesh& mesh) {
  std::vector<Eigen::Vector3d> points;
  for (Eigen::Index v = 0; v < mesh.positions().cols(); v += 90) points.push_back(mesh.positions().col(v));
  return points;
}

TEST(Sensitivity, RbfAfterALatticeMatchesFiniteDifferences) {
  Mesh mesh = test::bunny();
  WarpStack stack;
  auto& a = push(stack, mesh, "A", std::make_unique<BSplineLattice>(box_of(mesh, 0.05), Index3{5, 5, 5}, 3));
  nudge(a, {2, 3, 2}, Eigen::Vector3d(0.3, 0.5, 0), stack, mesh, "A");
  RbfOptions options;
  options.kernel = RbfKernel::ThinPlate;
  options.radius = 3;
  auto& r = push(stack, mesh, "R", std::make_unique<RbfDeformer>(rbf_points(mesh), options));
  r.move_points(0, {2, 5}, {r.points(0).col(2) + Eigen::Vector3d(0.2, 0.4, 0), r.points(0).col(5) - Eigen::Vector3d(0, 0.3, 0.1)});
  stack.update(mesh, "R");
  expect_matches_finite_differences(stack, "R", 0, mesh, 6);
  expect_matches_finite_differences(stack, "A", 0, mesh, 6);  // the lattice through the RBF
}

/// A quad cage: the bunny's box grown by `pad`.
std::unique_ptr<CageDeformer> bunny_cage(const Mesh& mesh, double pad) {
  const Eigen::Vector3d lo = mesh.positions().rowwise().minCoeff().array() - pad;
  const Eigen::Vector3d hi = mesh.positions().rowwise().maxCoeff().array() + pad;
  std::vector<Eigen::Vector3d> corners;
  for (int i = 0; i < 8; ++i) corners.emplace_back((i & 1) ? hi[0] : lo[0], (i & 2) ? hi[1] : lo[1], (i & 4) ? hi[2] : lo[2]);
  return std::make_unique<CageDeformer>(
      corners, std::vector<std::vector<std::uint32_t>>{{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}});
}

TEST(Sensitivity, IdwAndCageAfterALatticeMatchFiniteDifferences) {
  Mesh mesh = test::bunny();
  WarpStack stack;
  auto& a = push(stack, mesh, "A", std::make_unique<BSplineLattice>(box_of(mesh, 0.05), Index3{5, 5, 5}, 3));
  nudge(a, {2, 3, 2}, Eigen::Vector3d(0.3, 0.5, 0), stack, mesh, "A");
  auto& w = push(stack, mesh, "W", std::make_unique<IdwDeformer>(rbf_points(mesh), 2.0));
  w.move_points(0, {2, 5}, {w.points(0).col(2) + Eigen::Vector3d(0.2, 0.4, 0), w.points(0).col(5) - Eigen::Vector3d(0, 0.3, 0.1)});
  stack.update(mesh, "W");
  auto& c = push(stack, mesh, "C", bunny_cage(mesh, 1.0));
  c.move_points(0, {3, 6}, {c.points(0).col(3) + Eigen::Vector3d(0.5, 0.4, 0), c.points(0).col(6) - Eigen::Vector3d(0, 0.3, 0.6)});
  stack.update(mesh, "C");
  expect_matches_finite_differences(stack, "C", 0, mesh, 6);
  expect_matches_finite_differences(stack, "W", 0, mesh, 6);  // through the cage
  expect_matches_finite_differences(stack, "A", 0, mesh, 6);  // through the IDW and the cage
}

TEST(Sensitivity, ALoneLinearDeformerIsItsOwnLinearization) {
  Mesh mesh = test::bunny();
  WarpStack stack;
  auto& l = push(stack, mesh, "L", std::make_unique<BSplineLattice>(box_of(mesh, 0.05), Index3{6, 6, 6}, 3));
  const Eigen::Matrix3Xd before = mesh.positions();
  const Market m = sensitivity(stack, 0, l, 0, mesh);
  const std::vector<std::size_t> ids = movable_ids(l, 0);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::VectorXd delta(static_cast<Eigen::Index>(3 * ids.size()));
  for (Eigen::Index i = 0; i < delta.size(); ++i) delta[i] = u(rng);
  std::vector<Eigen::Vector3d> targets;
  const Eigen::Matrix3Xd now = l.points(0, ids);
  for (std::size_t i = 0; i < ids.size(); ++i)
    targets.push_back(now.col(static_cast<Eigen::Index>(i)) + delta.segment<3>(static_cast<Eigen::Index>(3 * i)));
  l.move_points(0, ids, targets);
  stack.update(mesh, "L");
  Eigen::VectorXd predicted = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(m.rows));
  for (const auto& [rc, v] : m.values) predicted[static_cast<Eigen::Index>(rc.first)] += v * delta[static_cast<Eigen::Index>(rc.second)];
  const Eigen::Matrix3Xd moved = mesh.positions() - before;
  const Eigen::Map<const Eigen::VectorXd> actual(moved.data(), moved.size());
  EXPECT_LE((actual - predicted).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_GT(actual.cwiseAbs().maxCoeff(), 0.1);
}

TEST(Sensitivity, HeaderNamesEveryMovablePointInNetOrder) {
  Mesh mesh = test::bunny();
  WarpStack stack;
  const auto& l = push(stack, mesh, "L", std::make_unique<BSplineLattice>(box_of(mesh, 0.05), Index3{5, 5, 5}, 2));
  const Market m = sensitivity(stack, 0, l, 0, mesh);
  const std::vector<std::size_t> ids = movable_ids(l, 0);
  ASSERT_EQ(m.points.size(), ids.size());
  const Index3 first = l.index(ids[0]);
  EXPECT_EQ(m.points[0], "% point 0 index " + std::to_string(first[0]) + " " + std::to_string(first[1]) + " " +
                             std::to_string(first[2]));
  // An unmoved lattice is the identity, bit for bit.
  EXPECT_EQ((mesh.positions() - mesh.rest_positions()).cwiseAbs().maxCoeff(), 0.0);
}

TEST(Deformer, DragThroughTheSeamReachesTargetsOnEveryKind) {
  Mesh mesh = test::bunny();
  OctreeOptions options;
  options.levels = 2;
  std::vector<std::unique_ptr<Deformer>> kinds;
  kinds.push_back(std::make_unique<BSplineLattice>(box_of(mesh, 0.05), Index3{6, 6, 6}, 3));
  kinds.push_back(std::make_unique<BernsteinLattice>(box_of(mesh, 0.05), Index3{3, 3, 3}));
  kinds.push_back(std::make_unique<OctreeLattice>(fit_principal_box(mesh.positions(), {}, 0.02),
                                                  Eigen::Matrix3Xd(mesh.positions()), options));
  RbfOptions gaussian;
  gaussian.radius = 3;
  kinds.push_back(std::make_unique<RbfDeformer>(rbf_points(mesh), gaussian));
  kinds.push_back(std::make_unique<IdwDeformer>(rbf_points(mesh), 2.0));
  kinds.push_back(bunny_cage(mesh, 1.0));
  for (auto& d : kinds) {
    const std::vector<Eigen::Vector3d> at = {mesh.positions().col(10), mesh.positions().col(900)};
    const std::vector<Eigen::Vector3d> to = {at[0] + Eigen::Vector3d(0.2, 0.1, 0), at[1] - Eigen::Vector3d(0, 0.3, 0.1)};
    for (const Eigen::Vector3d& x : at) EXPECT_EQ(d->apply(x, nullptr), x) << d->kind() << ": unmoved is the identity";
    const DragResult r = drag(*d, at, to);
    EXPECT_LT(r.max_residual, 1e-10) << d->kind();
    EXPECT_GT(r.points_changed, 0u) << d->kind();
  }
}

}  // namespace
}  // namespace ffd
