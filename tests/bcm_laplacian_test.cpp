// The discrete Laplacians (eq. 4), the k-harmonic system with the λ recursion (eq. 3/5),
// the anisotropic parameter domain and the supernodal Cholesky they are solved with.
#include <gtest/gtest.h>

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>

#include <cmath>
#include <random>

#include "common/errors.h"
#include "bcm/anisotropic_laplacian.h"
#include "bcm/bcm_options.h"
#include "bcm/cotan_laplacian.h"
#include "bcm/kharmonic_system.h"
#include "common/supernodal_cholesky.h"
#include "bcm_test_util.h"
#include "test_meshes.h"

namespace ffd {
namespace {

using Sparse = Eigen::SparseMatrix<double>;

double max_abs(const Sparse& a) {
  double m = 0;
  for (Eigen::Index c = 0; c < a.outerSize(); ++c)
    for (Sparse::InnerIterator it(a, c); it; ++it) m = std::max(m, std::abs(it.value()));
  return m;
}

// A regular hexagon of unit triangles around vertex 0.
void hexagon(Eigen::Matrix3Xd& positions, std::vector<Triangle>& triangles) {
  positions.resize(3, 7);
  positions.col(0).setZero();
  for (int i = 0; i < 6; ++i) positions.col(i + 1) << std::cos(i * M_PI / 3), std::sin(i * M_PI / 3), 0;
  triangles.clear();
  for (std::uint32_t i = 0; i < 6; ++i) triangles.push_back({0, i + 1, (i + 1) % 6 + 1});
}

TEST(CotanLaplacian, RegularHexagonWeightsAndVoronoiArea) {
  Eigen::Matrix3Xd p;
  std::vector<Triangle> t;
  hexagon(p, t);
  const Laplacian lap = cotan_laplacian(p, t);
  const double cot60 = 1 / std::sqrt(3.0);
  for (int i = 1; i <= 6; ++i) {
    EXPECT_NEAR(lap.weights.coeff(0, i), cot60, 1e-15);      // ½(cot 60° + cot 60°)
    EXPECT_NEAR(lap.weights.coeff(i, i % 6 + 1), cot60 / 2, 1e-15);  // boundary edge: one triangle
  }
  // The centre's Voronoi area is a third of the hexagon's area (6·√3/4).
  EXPECT_NEAR(lap.areas[0], 6 * std::sqrt(3.0) / 4 / 3, 1e-15);
  EXPECT_NEAR(lap.areas.sum(), 6 * std::sqrt(3.0) / 4, 1e-14);
  // Symmetric, rows summing to zero: a graph Laplacian.
  EXPECT_LT(max_abs(Sparse(lap.weights - Sparse(lap.weights.transpose()))), 1e-15);
  EXPECT_LT((lap.weights * Eigen::VectorXd::Ones(7)).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(CotanLaplacian, ObtuseTriangleMixedAreasAndClampedWeight) {
  // Angle at vertex 0 is 120°: its cotangent (−1/√3) makes edge 1–2 negative.
  Eigen::Matrix3Xd p(3, 3);
  p << 0, 1, -0.5, 0, 0, std::sqrt(3.0) / 2, 0, 0, 0;
  for (CotanWeights kind : {CotanWeights::Standard, CotanWeights::Positive}) {
    const Laplacian lap = cotan_laplacian(p, {{0, 1, 2}}, kind);
    const double area = std::sqrt(3.0) / 4;
    EXPECT_NEAR(lap.areas[0], area / 2, 1e-15);
    EXPECT_NEAR(lap.areas[1], area / 4, 1e-15);
    EXPECT_NEAR(lap.areas[2], area / 4, 1e-15);
    if (kind == CotanWeights::Positive)
      EXPECT_EQ(lap.weights.coeff(1, 2), 0.0);  // clamped from −1/(2√3)
    else
      EXPECT_NEAR(lap.weights.coeff(1, 2), -0.5 / std::sqrt(3.0), 1e-15);  // eq. 4 as printed
    EXPECT_NEAR(lap.weights.coeff(0, 1), 0.5 / std::tan(M_PI / 6), 1e-14);
    EXPECT_LT((lap.weights * Eigen::VectorXd::Ones(3)).cwiseAbs().maxCoeff(), 1e-15);
  }
}

TEST(CotanLaplacian, DegenerateTrianglesStayFinite) {
  // A needle and a zero-area triangle (collinear corners).
  Eigen::Matrix3Xd p(3, 5);
  p << 0, 1, 0.5, 2, 3, 0, 0, 1e-13, 0, 0, 0, 0, 0, 0, 0;
  const Laplacian lap = cotan_laplacian(p, {{0, 1, 2}, {1, 3, 4}});
  EXPECT_TRUE(Eigen::MatrixXd(lap.weights).allFinite());
  EXPECT_TRUE(lap.areas.allFinite());
  EXPECT_GT(lap.areas.minCoeff(), 0);
  EXPECT_LE(max_abs(lap.weights), kMaxCotangent);
}

TEST(CotanLaplacian, LinearPrecisionOnAPlanarMesh) {
  // Any planar triangulation (bcm_ground_truth_test has a non-Delaunay one):
  // Σ w_ij (p_j − p_i) = 0 inside.
  const Mesh grid = test::grid_mesh(12, [](double x, double y) { return 0.3 * x - 0.7 * y; });
  const Laplacian lap = cotan_laplacian(grid.positions(), test::all_triangles(grid));
  const Eigen::MatrixXd lp = lap.weights * grid.positions().transpose();
  for (int j = 1; j < 12; ++j)
    for (int i = 1; i < 12; ++i) EXPECT_LT(lp.row(j * 13 + i).norm(), 1e-13);
}

TEST(UniformLaplacian, ValenceAndUnitWeights) {
  Eigen::Matrix3Xd p;
  std::vector<Triangle> t;
  hexagon(p, t);
  const Laplacian lap = uniform_laplacian(7, t);
  EXPECT_EQ(lap.areas[0], 6);
  EXPECT_EQ(lap.areas[1], 3);
  EXPECT_EQ(lap.weights.coeff(0, 3), 1);
  EXPECT_EQ(lap.weights.coeff(0, 0), -6);
}

TEST(KHarmonicSystem, LambdaRecursionRamps) {
  EXPECT_EQ(smoothness_lambda(1, 0.0), 0.0);  // C^0: Δ of the boundary dropped
  EXPECT_EQ(smoothness_lambda(1, 0.25), 0.25);
  EXPECT_EQ(smoothness_lambda(1, 1.0), 1.0);
  EXPECT_EQ(smoothness_lambda(1, 2.0), 1.0);
  EXPECT_EQ(smoothness_lambda(2, 1.0), 0.0);
  EXPECT_EQ(smoothness_lambda(2, 1.5), 0.5);
  EXPECT_EQ(smoothness_lambda(2, 2.0), 1.0);
}

// The assembled rows equal (−1)^k M·(M⁻¹W)^k for C^(k−1), and the free block is symmetric
// exactly where the system says so.
TEST(KHarmonicSystem, MatchesThePowerOfTheLaplacianAndItsSymmetryFlag) {
  const Mesh mesh = test::sphere_mesh(2);
  const Eigen::Index n = static_cast<Eigen::Index>(mesh.num_vertices());
  // Local numbering: vertices with z > 0.2 free, the rest constrained.
  std::vector<Eigen::Index> order;
  for (Eigen::Index v = 0; v < n; ++v)
    if (mesh.positions()(2, v) > 0.2) order.push_back(v);
  const Eigen::Index free = static_cast<Eigen::Index>(order.size());
  for (Eigen::Index v = 0; v < n; ++v)
    if (mesh.positions()(2, v) <= 0.2) order.push_back(v);
  std::vector<std::uint32_t> local(static_cast<std::size_t>(n));
  Eigen::Matrix3Xd p(3, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    local[static_cast<std::size_t>(order[static_cast<std::size_t>(i)])] = static_cast<std::uint32_t>(i);
    p.col(i) = mesh.positions().col(order[static_cast<std::size_t>(i)]);
  }
  std::vector<Triangle> tris;
  for (const Triangle& t : test::all_triangles(mesh)) tris.push_back({local[t[0]], local[t[1]], local[t[2]]});
  const Laplacian lap = cotan_laplacian(p, tris);
  const Sparse l = Sparse(lap.areas.cwiseInverse().asDiagonal() * lap.weights);
  for (int k = 1; k <= 3; ++k) {
    SCOPED_TRACE("k = " + std::to_string(k));
    Sparse power = l;
    for (int i = 1; i < k; ++i) power = Sparse(power * l);
    const Eigen::MatrixXd expected =
        (k % 2 ? -1.0 : 1.0) * (lap.areas.head(free).asDiagonal() * Eigen::MatrixXd(power).topRows(free));
    const KHarmonicSystem system = kharmonic_system(lap, free, Eigen::VectorXd::Constant(n - free, k - 1), k);
    const double scale = expected.cwiseAbs().maxCoeff();
    EXPECT_LT((Eigen::MatrixXd(system.free_block) - expected.leftCols(free)).cwiseAbs().maxCoeff(), 1e-12 * scale);
    EXPECT_LT((Eigen::MatrixXd(system.constrained_block) - expected.rightCols(n - free)).cwiseAbs().maxCoeff(),
              1e-12 * scale);
    EXPECT_TRUE(system.symmetric);
    const Eigen::MatrixXd a(system.free_block);
    EXPECT_LT((a - a.transpose()).cwiseAbs().maxCoeff(), 1e-12 * scale);
  }
  // k = 3 with c = 1 blends λ_1 = 1, λ_2 = 0: unsymmetric, and the system says so.
  const KHarmonicSystem mixed = kharmonic_system(lap, free, Eigen::VectorXd::Constant(n - free, 1.0), 3);
  EXPECT_FALSE(mixed.symmetric);
  const Eigen::MatrixXd a(mixed.free_block);
  EXPECT_GT((a - a.transpose()).cwiseAbs().maxCoeff(), 1e-6 * a.cwiseAbs().maxCoeff());
  // k = 2 with any c stays symmetric (W Λ M⁻¹ W).
  const KHarmonicSystem blended = kharmonic_system(lap, free, Eigen::VectorXd::Constant(n - free, 0.4), 2);
  EXPECT_TRUE(blended.symmetric);
  const Eigen::MatrixXd b(blended.free_block);
  EXPECT_LT((b - b.transpose()).cwiseAbs().maxCoeff(), 1e-12 * b.cwiseAbs().maxCoeff());
}

TEST(AnisotropicLaplacian, EqualDiameterMapOfAnElongatedPatch) {
  // A 4:1 planar rectangle: its conformal map is a similarity, and the equal-diameter
  // stretch makes it square.
  const Mesh grid = test::grid_mesh(16, nullptr);
  Eigen::Matrix3Xd p = grid.positions();
  p.row(0) *= 4.0;
  const Eigen::Matrix3Xd map = equal_diameter_conformal_map(p, test::all_triangles(grid));
  EXPECT_TRUE((map.row(2).array() == 0).all());
  const Eigen::Vector3d extent = map.rowwise().maxCoeff() - map.rowwise().minCoeff();
  EXPECT_NEAR(extent[0], extent[1], 1e-9 * extent[0]);
  // The cotangent weights there are those of the square grid: 1 on axis edges, 0 on the
  // diagonals (up to the map's tiny conformal error).
  const Laplacian lap = anisotropic_laplacian(p, test::all_triangles(grid), test::all_triangles(grid));
  EXPECT_NEAR(lap.weights.coeff(7 * 17 + 7, 7 * 17 + 8), 1.0, 1e-6);
  EXPECT_NEAR(lap.weights.coeff(7 * 17 + 7, 8 * 17 + 7), 1.0, 1e-6);
}

TEST(AnisotropicLaplacian, RefusesAnAnnulus) {
  const Mesh grid = test::grid_mesh(10);
  std::vector<Triangle> ring;
  std::vector<std::uint32_t> ids;
  for (std::size_t f = 0; f < grid.num_faces(); ++f) {
    grid.face_vertices(f, ids);
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (std::uint32_t v : ids) c += grid.positions().col(v) / 3;
    if ((c - Eigen::Vector3d(0.5, 0.5, 0)).cwiseAbs().maxCoeff() > 0.2) ring.push_back({ids[0], ids[1], ids[2]});
  }
  // Keep only the vertices the ring uses (a precondition).
  std::vector<std::int64_t> slot(grid.num_vertices(), -1);
  std::vector<Eigen::Vector3d> kept;
  for (Triangle& t : ring)
    for (std::uint32_t& v : t) {
      if (slot[v] < 0) {
        slot[v] = static_cast<std::int64_t>(kept.size());
        kept.push_back(grid.positions().col(v));
      }
      v = static_cast<std::uint32_t>(slot[v]);
    }
  Eigen::Matrix3Xd positions(3, static_cast<Eigen::Index>(kept.size()));
  for (std::size_t i = 0; i < kept.size(); ++i) positions.col(static_cast<Eigen::Index>(i)) = kept[i];
  try {
    anisotropic_laplacian(positions, ring, ring);
    FAIL() << "an annulus was parametrized";
  } catch (const TopologyError& e) {
    EXPECT_EQ(e.subject().argument, "laplacian");
    EXPECT_NE(std::string(e.what()).find("2 boundary loops"), std::string::npos) << e.what();
  }
}

// The supernodal factorization against Eigen's and CHOLMOD's own, on a k = 3 system.
TEST(SupernodalCholesky, AgreesWithCholmodAndEigenOnAKHarmonicSystem) {
  const Mesh mesh = test::bunny();
  const Laplacian lap = cotan_laplacian(mesh.positions(), test::all_triangles(mesh));
  const Eigen::Index n = static_cast<Eigen::Index>(mesh.num_vertices()), free = n - 60;
  const KHarmonicSystem system = kharmonic_system(lap, free, Eigen::VectorXd::Constant(n - free, 2), 3);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(-1, 1);
  Eigen::MatrixXd b(free, 7);
  for (Eigen::Index i = 0; i < b.size(); ++i) b.data()[i] = unit(rng);
  SupernodalCholesky ours;
  ASSERT_TRUE(ours.compute(system.free_block));
  const Eigen::MatrixXd x = ours.solve(b);
  Eigen::CholmodSupernodalLLT<Sparse, Eigen::Lower> cholmod(system.free_block);
  ASSERT_EQ(cholmod.info(), Eigen::Success);
  const Eigen::MatrixXd y = cholmod.solve(b);
  Eigen::SimplicialLDLT<Sparse, Eigen::Lower> ldlt(system.free_block);
  const Eigen::MatrixXd z = ldlt.solve(b);
  const double scale = y.cwiseAbs().maxCoeff();
  EXPECT_LT((x - y).cwiseAbs().maxCoeff(), 1e-8 * scale);
  EXPECT_LT((x - z).cwiseAbs().maxCoeff(), 1e-8 * scale);
  const Eigen::MatrixXd residual = system.free_block.selfadjointView<Eigen::Lower>() * x - b;
  // Backward stable: the residual is rounding-sized against ‖A‖·‖x‖.
  EXPECT_LT(residual.cwiseAbs().maxCoeff(), 1e-12 * max_abs(system.free_block) * x.cwiseAbs().maxCoeff());
  EXPECT_GT(ours.factor_nonzeros(), static_cast<std::size_t>(system.free_block.nonZeros() / 2));
  // Bit-identical on a second factorization.
  SupernodalCholesky again;
  ASSERT_TRUE(again.compute(system.free_block));
  EXPECT_TRUE(again.solve(b) == x);
}

TEST(SupernodalCholesky, ReportsAMatrixThatIsNotPositiveDefinite) {
  Sparse a(3, 3);
  a.insert(0, 0) = 1;
  a.insert(1, 1) = -2;
  a.insert(2, 2) = 1;
  a.insert(1, 0) = 0.5;
  SupernodalCholesky solver;
  EXPECT_FALSE(solver.compute(a));
}

}  // namespace
}  // namespace ffd
