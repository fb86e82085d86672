// Warp stack composition, the bit index, drag, and normals against the deformed mesh.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "mesh/vertex_normals.h"
#include "test_meshes.h"
#include "warp/bernstein_lattice.h"
#include "warp/bspline_lattice.h"
#include "warp/drag.h"
#include "warp/warp_stack.h"

namespace ffd {
namespace {

Parallelepiped box_around(const Mesh& mesh, double padding) { return fit_aabb(mesh.positions(), {}, padding); }

TEST(WarpStack, ComposesInCreationOrder) {
  Mesh mesh = test::sphere_mesh(3);
  WarpStack stack;
  auto first = std::make_unique<BSplineLattice>(box_around(mesh, 0.1), Index3{6, 6, 6}, 3);
  BSplineLattice* a = first.get();
  stack.push(mesh, "a", std::move(first));
  a->move_point({2, 2, 3}, a->point({2, 2, 3}) + Eigen::Vector3d(0, 0, 0.4));
  stack.update(mesh, "a");
  const Eigen::Matrix3Xd after_a = mesh.positions();

  // The second lattice is fitted to the deformed mesh and acts on it.
  auto second = std::make_unique<BernsteinLattice>(box_around(mesh, 0.05), Index3{3, 3, 3});
  BernsteinLattice* b = second.get();
  stack.push(mesh, "b", std::move(second));
  b->move_point({1, 2, 1}, b->point({1, 2, 1}) + Eigen::Vector3d(0.3, 0, 0));
  stack.update(mesh, "b");
  for (std::uint32_t v = 0; v < mesh.num_vertices(); ++v) {
    const Eigen::Vector3d expect = b->apply(a->apply(mesh.rest_positions().col(v), nullptr), nullptr);
    EXPECT_LT((mesh.positions().col(v) - expect).norm(), 1e-13);
    EXPECT_LT((stack.evaluate(mesh.rest_positions().col(v), nullptr) - expect).norm(), 1e-13);
  }

  // Changing the lower lattice again re-evaluates through the upper one.
  a->move_point({2, 3, 2}, a->point({2, 3, 2}) + Eigen::Vector3d(-0.2, 0.1, 0));
  stack.update(mesh, "a");
  for (std::uint32_t v = 0; v < mesh.num_vertices(); ++v) {
    const Eigen::Vector3d expect = b->apply(a->apply(mesh.rest_positions().col(v), nullptr), nullptr);
    EXPECT_LT((mesh.positions().col(v) - expect).norm(), 1e-13);
  }
  (void)after_a;
}

TEST(WarpStack, UpdateTouchesOnlyVerticesInAlteredCells) {
  Mesh mesh = test::sphere_mesh(4);
  WarpStack stack;
  const Parallelepiped box = box_around(mesh, 0.05);
  auto owned = std::make_unique<BSplineLattice>(box, Index3{8, 8, 8}, 3);
  BSplineLattice* lattice = owned.get();
  stack.push(mesh, "l", std::move(owned));
  const Eigen::Matrix3Xd before = mesh.positions();
  lattice->move_point({2, 2, 2}, lattice->point({2, 2, 2}) + Eigen::Vector3d(0.05, 0.05, 0.05));
  const WarpStack::Update update = stack.update(mesh, "l");
  // Point 2 (cubic) influences cells 0..3 along each axis: u < 4/8.
  std::size_t expected = 0;
  for (std::uint32_t v = 0; v < mesh.num_vertices(); ++v) {
    const Eigen::Vector3d u = box.to_local(mesh.rest_positions().col(v));
    const bool in_cells = (u.array() < 0.5).all();
    expected += in_cells;
    if (!in_cells) {
      EXPECT_EQ(mesh.positions().col(v), before.col(v)) << v;
    }
  }
  EXPECT_EQ(update.moved, expected);
  EXPECT_GT(update.moved, 0u);
}

TEST(WarpStack, NewVerticesAreEvaluatedFromRestSpace) {
  Mesh mesh = test::sphere_mesh(2);
  WarpStack stack;
  auto owned = std::make_unique<BSplineLattice>(box_around(mesh, 0.1), Index3{4, 4, 4}, 3);
  BSplineLattice* lattice = owned.get();
  stack.push(mesh, "l", std::move(owned));
  lattice->move_point({2, 2, 2}, lattice->point({2, 2, 2}) + Eigen::Vector3d(0.1, 0.2, 0.3));
  stack.update(mesh, "l");
  const Eigen::Matrix3Xd expected = mesh.positions();
  const Eigen::Matrix3Xd expected_n = mesh.normals();
  mesh.positions().setZero();
  for (std::uint32_t v = 0; v < mesh.num_vertices(); ++v) stack.evaluate_vertex(mesh, v);
  EXPECT_LT((mesh.positions() - expected).cwiseAbs().maxCoeff(), 1e-13);
  EXPECT_LT((mesh.normals() - expected_n).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(WarpStack, BakeFreezesTheDeformation) {
  Mesh mesh = test::sphere_mesh(2);
  WarpStack stack;
  auto owned = std::make_unique<BSplineLattice>(box_around(mesh, 0.1), Index3{4, 4, 4}, 3);
  BSplineLattice* lattice = owned.get();
  stack.push(mesh, "l", std::move(owned));
  lattice->move_point({2, 2, 2}, lattice->point({2, 2, 2}) + Eigen::Vector3d(0.1, 0.2, 0.3));
  stack.update(mesh, "l");
  const Eigen::Matrix3Xd deformed = mesh.positions();
  const auto dropped = stack.bake(mesh);
  ASSERT_EQ(dropped.size(), 1u);
  EXPECT_EQ(stack.size(), 0u);
  EXPECT_EQ(mesh.rest_positions(), deformed);
  EXPECT_EQ(mesh.positions(), deformed);
}

TEST(Drag, PutsObjectPointsOnTheirTargets) {
  const Parallelepiped box = Parallelepiped::from_min_max(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones());
  for (int degree = 1; degree <= 3; ++degree) {
    BSplineLattice lattice(box, {7, 7, 7}, degree);
    std::vector<Eigen::Vector3d> at = {{0.5, 0.5, 0.5}, {0.3, 0.6, 0.45}, {0.62, 0.35, 0.55}};
    std::vector<Eigen::Vector3d> to = {{0.52, 0.55, 0.5}, {0.28, 0.6, 0.5}, {0.62, 0.3, 0.58}};
    const DragResult r = drag(lattice, at, to);
    EXPECT_LE(r.max_residual, 1e-9) << degree;
    EXPECT_EQ(r.unreachable, 0u);
    EXPECT_GT(r.points_changed, 0u);
    for (std::size_t i = 0; i < at.size(); ++i) EXPECT_LE((lattice.apply(at[i], nullptr) - to[i]).norm(), 1e-9);
  }
}

TEST(Drag, IsTheLeastNormChange) {
  // The minimum-norm solution of B ΔP = E lies in the row space of B: ΔP = Bᵀ y. So any
  // change δ with B δ = 0 (here: a random one projected onto B's null space) added to it
  // reaches the same targets with a larger norm.
  const Parallelepiped box = Parallelepiped::from_min_max(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones());
  BernsteinLattice lattice(box, {3, 3, 3});
  const std::vector<Eigen::Vector3d> at = {{0.4, 0.5, 0.5}, {0.7, 0.2, 0.3}};
  const std::vector<Eigen::Vector3d> to = {{0.45, 0.5, 0.5}, {0.7, 0.25, 0.3}};
  drag(lattice, at, to);
  Eigen::MatrixXd B(2, lattice.num_points());
  Eigen::MatrixXd dP(lattice.num_points(), 3);
  for (std::size_t f = 0; f < lattice.num_points(); ++f) dP.row(f) = lattice.displacement(f).transpose();
  std::vector<std::pair<std::size_t, double>> w;
  B.setZero();
  for (int i = 0; i < 2; ++i) {
    lattice.movable_weights(at[i], w);
    for (auto [f, weight] : w) B(i, f) = weight;
  }
  // Residual of projecting dP onto the row space of B.
  const Eigen::MatrixXd y = (B * B.transpose()).ldlt().solve(B * dP);
  EXPECT_LT((dP - B.transpose() * y).norm(), 1e-12);
}

TEST(Drag, ReportsPointsNoMovablePointReaches) {
  const Parallelepiped box = Parallelepiped::from_min_max(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones());
  BSplineLattice lattice(box, {6, 6, 6}, 3);
  const DragResult r = drag(lattice, {{0.0, 0.5, 0.5}, {2.0, 0.5, 0.5}}, {{0.1, 0.5, 0.5}, {2.1, 0.5, 0.5}});
  // On the box face every movable point's weight is zero (their supports end there);
  // 2.0 is outside the box.
  EXPECT_EQ(r.unreachable, 2u);
  EXPECT_EQ(r.points_changed, 0u);
  EXPECT_NEAR(r.max_residual, 0.1, 1e-12);
}

// Largest angle (radians) between the transformed normals and the normals of the deformed
// mesh (angle-weighted, from the deformed polygons).
double normal_error(const Mesh& mesh) {
  const Eigen::Matrix3Xd mesh_normals = vertex_normals(mesh, mesh.positions());
  double worst = 0;
  for (Eigen::Index v = 0; v < mesh_normals.cols(); ++v)
    worst = std::max(worst, std::acos(std::clamp(mesh_normals.col(v).dot(mesh.normals().col(v)), -1.0, 1.0)));
  return worst;
}

TEST(Normals, CovariantNormalsConvergeToTheDeformedMeshNormals) {
  // The covariant rule gives the true deformed surface's normal; the polygon normals of
  // the deformed mesh approach it as the mesh is refined (error ~ edge length).
  std::vector<double> errors;
  for (int level = 2; level <= 6; ++level) {
    Mesh mesh = test::sphere_mesh(level);
    WarpStack stack;
    const Parallelepiped box = Parallelepiped::from_min_max(Eigen::Vector3d::Constant(-1.2), Eigen::Vector3d::Constant(1.2));
    auto owned = std::make_unique<BSplineLattice>(box, Index3{6, 6, 6}, 3);
    BSplineLattice* lattice = owned.get();
    stack.push(mesh, "l", std::move(owned));
    lattice->move_point({3, 3, 4}, lattice->point({3, 3, 4}) + Eigen::Vector3d(0.2, 0.1, 0.5));
    lattice->move_point({2, 4, 3}, lattice->point({2, 4, 3}) + Eigen::Vector3d(-0.3, 0.2, 0.0));
    stack.update(mesh, "l");
    errors.push_back(normal_error(mesh));
  }
  for (std::size_t i = 1; i < errors.size(); ++i) {
    EXPECT_LT(errors[i], 0.7 * errors[i - 1]) << "level " << i + 2;
  }
  EXPECT_LT(errors.back(), 0.01);  // radians, at 40k faces
}

}  // namespace
}  // namespace ffd
