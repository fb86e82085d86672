// The boundary-constraint editor's setup phases, each on its own (bcm_editor.h): regions
// and rings, operator, system, factorization, basis and detail, and that running them one
// by one is bcm_precompute().
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "bcm/bcm_editor.h"
#include "bcm_test_util.h"
#include "test_meshes.h"

namespace ffd {
namespace {

struct SphereCap {
  Mesh mesh = test::sphere_mesh(3);
  std::vector<std::uint32_t> support;
  std::vector<BcmHandle> handles;
  BcmOptions options;
  SphereCap() {
    support = test::pick(mesh, [](const Eigen::Vector3d& p) { return p.z() > -0.3; });
    handles = {{"top", test::pick(mesh, [](const Eigen::Vector3d& p) { return p.z() > 0.8; })}};
    options.k = 3;
  }
};

TEST(BcmPhases, RegionsAndRingsSplitTheSupportAndFindKRings) {
  SphereCap s;
  BcmData data;
  bcm_regions_and_rings(data, s.mesh, s.support, s.handles, s.options);
  EXPECT_EQ(data.regions.free.size() + s.handles[0].vertices.size(), s.support.size());
  EXPECT_EQ(data.stencil.num_free, data.regions.free.size());
  // Rings 1..k: every constrained vertex is within k edges of a free one, and the fixed
  // ones all lie outside the support.
  for (std::size_t i = data.stencil.num_free; i < data.stencil.vertices.size(); ++i) {
    EXPECT_GE(data.stencil.ring[i], 1);
    EXPECT_LE(data.stencil.ring[i], 3);
    if (data.stencil.handle[i] < 0) {
      EXPECT_FALSE(std::binary_search(s.support.begin(), s.support.end(), data.stencil.vertices[i]));
    }
  }
  EXPECT_EQ(data.options.outer_continuity, 2);  // k − 1 where not given
  EXPECT_EQ(data.options.inner_continuity, 2);
  // Relative to the stencil's centroid.
  EXPECT_LT(data.stencil_setup.rowwise().mean().norm(), 1e-12);
}

TEST(BcmPhases, TheOperatorsRowsSumToZeroAndTheSystemIsSymmetricForClampedBoundaries) {
  SphereCap s;
  BcmData data;
  bcm_regions_and_rings(data, s.mesh, s.support, s.handles, s.options);
  const Laplacian laplacian = bcm_operator(data, s.mesh);
  ASSERT_EQ(laplacian.weights.rows(), static_cast<Eigen::Index>(data.stencil.vertices.size()));
  const Eigen::VectorXd row_sums = laplacian.weights * Eigen::VectorXd::Ones(laplacian.weights.cols());
  // Rows within k − 1 rings are complete, so they sum to zero.
  for (std::size_t i = 0; i < data.stencil.vertices.size(); ++i)
    if (i < data.stencil.num_free || data.stencil.ring[i] <= 2) {
      EXPECT_NEAR(row_sums[static_cast<Eigen::Index>(i)], 0, 1e-12);
    }
  const KHarmonicSystem system = bcm_system(data, laplacian);
  EXPECT_TRUE(system.symmetric);
  const Eigen::SparseMatrix<double> asymmetry = system.free_block - Eigen::SparseMatrix<double>(system.free_block.transpose());
  EXPECT_LT(asymmetry.cwiseAbs().sum(), 1e-9 * system.free_block.cwiseAbs().sum());
  EXPECT_EQ(data.constrained_block.rows(), static_cast<Eigen::Index>(data.stencil.num_free));
  EXPECT_EQ(data.constrained_block.cols(), static_cast<Eigen::Index>(data.stencil.num_constrained()));
}

TEST(BcmPhases, FactorizationThenBasisReproduceTheDirectSolve) {
  SphereCap s;
  BcmData data;
  bcm_regions_and_rings(data, s.mesh, s.support, s.handles, s.options);
  bcm_factorize(data, bcm_system(data, bcm_operator(data, s.mesh)));
  EXPECT_STREQ(data.stats.solver, "supernodal Cholesky");
  bcm_basis(data);
  ASSERT_EQ(data.basis.rows(), 4);
  ASSERT_EQ(data.constant.cols(), static_cast<Eigen::Index>(data.regions.free.size()));
  // At a random pose, const + B·frame (eq. 6) equals the factorization's own solve.
  std::mt19937 rng(7);
  const test::Pose pose = test::random_pose(rng, data.centroid[0], 0.3);
  bcm_set_pose(data, 0, pose.linear, pose.translation);
  const Eigen::Matrix3Xd direct = bcm_solve_free(data);
  for (std::size_t i = 0; i < data.regions.free.size(); ++i) {
    const Eigen::Index c = static_cast<Eigen::Index>(i);
    const Eigen::Vector3d eq6 = data.constant.col(c) + data.frame[0] * data.basis.col(c);
    EXPECT_LT((eq6 - direct.col(c)).norm(), 1e-12);
  }
}

TEST(BcmPhases, DetailAtTheSetupPoseGivesTheSurfaceBack) {
  SphereCap s;
  BcmData data;
  bcm_regions_and_rings(data, s.mesh, s.support, s.handles, s.options);
  bcm_factorize(data, bcm_system(data, bcm_operator(data, s.mesh)));
  bcm_basis(data);
  bcm_detail(data);
  ASSERT_EQ(data.detail.size(), data.regions.free.size());
  Eigen::Matrix3Xd positions = s.mesh.positions();
  bcm_pose(data, positions);
  EXPECT_LT((positions - s.mesh.positions()).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(BcmPhases, ThePhasesInTurnAreBcmPrecompute) {
  SphereCap s;
  BcmData a = bcm_precompute(s.mesh, s.support, s.handles, s.options);
  BcmData b;
  bcm_regions_and_rings(b, s.mesh, s.support, s.handles, s.options);
  bcm_factorize(b, bcm_system(b, bcm_operator(b, s.mesh)));
  bcm_basis(b);
  bcm_detail(b);
  EXPECT_EQ(a.constant, b.constant);
  EXPECT_EQ(a.basis, b.basis);
  std::mt19937 rng(3);
  const test::Pose pose = test::random_pose(rng, a.centroid[0], 0.3);
  bcm_set_pose(a, 0, pose.linear, pose.translation);
  bcm_set_pose(b, 0, pose.linear, pose.translation);
  Eigen::Matrix3Xd pa = s.mesh.positions(), pb = s.mesh.positions();
  bcm_pose(a, pa);
  bcm_pose(b, pb);
  EXPECT_EQ(pa, pb);
}

}  // namespace
}  // namespace ffd
