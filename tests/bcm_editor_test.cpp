// The BCM editor (bcm_precompute / bcm_pose) against an independent direct solve of
// Δ^k p = 0 (eq. 5), the precomputed basis (eq. 6) for random 9-dof poses, multiple
// handles, and a valid mesh throughout.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "bcm/basis_rows.h"
#include "bcm/bcm_editor.h"
#include "bcm_test_util.h"
#include "test_meshes.h"

namespace ffd {
namespace {

using test::Pose;

// The mesh positions with each handle moved by its pose (what eq. 5's right side holds).
Eigen::Matrix3Xd posed(const Mesh& mesh, const std::vector<BcmHandle>& handles, const std::vector<Pose>& poses) {
  Eigen::Matrix3Xd out = mesh.positions();
  for (std::size_t h = 0; h < handles.size(); ++h)
    for (std::uint32_t v : handles[h].vertices) out.col(v) = poses[h](mesh.positions().col(v));
  return out;
}

double max_free_difference(const BcmData& editor, const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& reference) {
  double worst = 0;
  const auto& free = editor.regions.free;
  for (std::size_t i = 0; i < free.size(); ++i)
    worst = std::max(worst, (positions.col(free[i]) - reference.col(static_cast<Eigen::Index>(i))).cwiseAbs().maxCoeff());
  return worst;
}

void expect_valid(const Mesh& mesh, const Eigen::Matrix3Xd& positions) {
  EXPECT_EQ(positions.cols(), static_cast<Eigen::Index>(mesh.num_vertices()));
  EXPECT_TRUE(positions.allFinite());
}

// Eq. 5 with C^(k−1) boundaries on a curved surface: the editor's basis result and its
// own direct solve equal the reference solve of the whole mesh's (M⁻¹W)^k, k = 1, 2, 3.
TEST(BcmEditor, EqualsDirectSolveOfKHarmonicSystemOnSphere) {
  const Mesh mesh = test::sphere_mesh(3);
  const std::vector<std::uint32_t> support = test::pick(mesh, [](const Eigen::Vector3d& p) { return p.z() > -0.3; });
  const std::vector<BcmHandle> handles = {{"top", test::pick(mesh, [](const Eigen::Vector3d& p) { return p.z() > 0.8; })}};
  for (int k = 1; k <= 3; ++k) {
    SCOPED_TRACE("k = " + std::to_string(k));
    BcmOptions options;
    options.k = k;
    options.detail = false;
    BcmData editor = bcm_precompute(mesh, support, handles, options);
    EXPECT_TRUE(editor.stats.symmetric);
    std::mt19937 rng(42 + k);
    for (int trial = 0; trial < 4; ++trial) {
      const Pose pose = test::random_pose(rng, editor.centroid.at(0), 0.3);
      bcm_set_pose(editor, 0, pose.linear, pose.translation);
      Eigen::Matrix3Xd positions = mesh.positions();
      bcm_pose(editor, positions);
      expect_valid(mesh, positions);
      const Eigen::Matrix3Xd target = posed(mesh, handles, {pose});
      const Eigen::Matrix3Xd reference = test::direct_kharmonic(mesh, mesh.positions(), editor.regions.free, target, k);
      EXPECT_LT(max_free_difference(editor, positions, reference), 1e-9);
      EXPECT_LT(max_free_difference(editor, positions, bcm_solve_free(editor)), 1e-12);
      // Handles follow their pose exactly; fixed vertices stay.
      for (std::uint32_t v : handles[0].vertices) EXPECT_LT((positions.col(v) - target.col(v)).norm(), 1e-12);
      for (Eigen::Index v = 0; v < positions.cols(); ++v) {
        if (!std::binary_search(support.begin(), support.end(), static_cast<std::uint32_t>(v))) {
          ASSERT_EQ(positions.col(v), mesh.positions().col(v));
        }
      }
    }
  }
}

// The same on the bunny (irregular triangles, obtuse angles) with two handles.
TEST(BcmEditor, EqualsDirectSolveOnBunnyWithTwoHandles) {
  const Mesh mesh = test::bunny();
  const Eigen::Vector3d ear(-2.0, 8.5, -1.0);
  const auto support = test::pick(mesh, [](const Eigen::Vector3d& p) { return p.y() > 4.0; });
  const std::vector<BcmHandle> handles = {
      {"top", test::pick(mesh, [](const Eigen::Vector3d& p) { return p.y() > 8.0; })},
      {"side", test::pick(mesh, [](const Eigen::Vector3d& p) { return p.y() > 4.5 && p.y() < 5.5 && p.x() > 3.0; })}};
  ASSERT_FALSE(handles[0].vertices.empty());
  ASSERT_FALSE(handles[1].vertices.empty());
  for (int k = 1; k <= 3; ++k) {
    SCOPED_TRACE("k = " + std::to_string(k));
    BcmOptions options;
    options.k = k;
    options.detail = false;
    BcmData editor = bcm_precompute(mesh, support, handles, options);
    std::mt19937 rng(7 * k);
    for (int trial = 0; trial < 3; ++trial) {
      const std::vector<Pose> poses = {test::random_pose(rng, editor.centroid.at(0), 1.0),
                                       test::random_pose(rng, editor.centroid.at(1), 1.0)};
      for (std::size_t h = 0; h < 2; ++h) bcm_set_pose(editor, h, poses[h].linear, poses[h].translation);
      Eigen::Matrix3Xd positions = mesh.positions();
      bcm_pose(editor, positions);
      expect_valid(mesh, positions);
      const Eigen::Matrix3Xd reference =
          test::direct_kharmonic(mesh, mesh.positions(), editor.regions.free, posed(mesh, handles, poses), k);
      EXPECT_LT(max_free_difference(editor, positions, reference), 1e-9);
    }
  }
}

// Blended smoothness (c between 0 and k−1) through the λ recursion, solved densely over
// the whole mesh: Δ̄^3 = Δ(λ_2 Δ(λ_1 Δ)), with c = 1.3 at the outer and 0.6 at the inner
// boundary (an unsymmetric system: the editor's LU path).
TEST(BcmEditor, BlendedContinuityEqualsTheLambdaRecursionSolvedDirectly) {
  const Mesh mesh = test::sphere_mesh(2);
  const auto support = test::pick(mesh, [](const Eigen::Vector3d& p) { return p.z() > -0.4; });
  const std::vector<BcmHandle> handles = {{"top", test::pick(mesh, [](const Eigen::Vector3d& p) { return p.z() > 0.75; })}};
  BcmOptions options;
  options.k = 3;
  options.outer_continuity = 1.3;
  options.inner_continuity = 0.6;
  options.detail = false;
  BcmData editor = bcm_precompute(mesh, support, handles, options);
  EXPECT_FALSE(editor.stats.symmetric);
  std::mt19937 rng(11);
  const Pose pose = test::random_pose(rng, editor.centroid.at(0), 0.3);
  bcm_set_pose(editor, 0, pose.linear, pose.translation);
  Eigen::Matrix3Xd positions = mesh.positions();
  bcm_pose(editor, positions);
  expect_valid(mesh, positions);

  const Eigen::Index n = static_cast<Eigen::Index>(mesh.num_vertices());
  const Laplacian lap = cotan_laplacian(mesh.positions(), test::all_triangles(mesh));
  const Eigen::MatrixXd w(lap.weights);
  std::vector<int> kind(static_cast<std::size_t>(n), 0);  // 0 fixed, 1 free, 2 handle
  for (std::uint32_t v : editor.regions.free) kind[v] = 1;
  for (std::uint32_t v : handles[0].vertices) kind[v] = 2;
  const auto lambda = [&](int j) {
    Eigen::VectorXd d(n);
    for (Eigen::Index v = 0; v < n; ++v) {
      const int t = kind[static_cast<std::size_t>(v)];
      const double c = t == 1 ? 1e9 : t == 2 ? 0.6 : 1.3;
      d[v] = std::clamp(c - (j - 1), 0.0, 1.0) / lap.areas[v];
    }
    return d;
  };
  const Eigen::MatrixXd a = w * lambda(2).asDiagonal() * w * lambda(1).asDiagonal() * w;
  const Eigen::Matrix3Xd target = posed(mesh, handles, {pose});
  const auto& free = editor.regions.free;
  const Eigen::Index p = static_cast<Eigen::Index>(free.size());
  Eigen::MatrixXd app(p, p), rhs = Eigen::MatrixXd::Zero(p, 3);
  for (Eigen::Index i = 0; i < p; ++i) {
    for (Eigen::Index j = 0; j < p; ++j) app(i, j) = a(free[static_cast<std::size_t>(i)], free[static_cast<std::size_t>(j)]);
    for (Eigen::Index v = 0; v < n; ++v)
      if (kind[static_cast<std::size_t>(v)] != 1) rhs.row(i) -= a(free[static_cast<std::size_t>(i)], v) * target.col(v).transpose();
  }
  const Eigen::Matrix3Xd reference = Eigen::MatrixXd(app.fullPivLu().solve(rhs)).transpose();
  EXPECT_LT(max_free_difference(editor, positions, reference), 1e-9);
  // And it differs from the C^2 solution: the blend does something.
  BcmOptions clamped = options;
  clamped.outer_continuity = clamped.inner_continuity = 2;
  BcmData c2 = bcm_precompute(mesh, support, handles, clamped);
  bcm_set_pose(c2, 0, pose.linear, pose.translation);
  Eigen::Matrix3Xd other = mesh.positions();
  bcm_pose(c2, other);
  EXPECT_GT((other - positions).cwiseAbs().maxCoeff(), 1e-3);
}

// Eq. 6 row by row (basis_rows.h): the sum of the handles' frames times their weights, to
// 1e-15 of an independent product, and bit for bit the fusions the header writes out. The
// products kept apart go through volatile, so that no compiler fuses them here; the plain
// form differs from the fused one on these numbers, so the test can fail. 133 vertices:
// two whole runs of 64 and a partial one, from an offset.
TEST(BasisRows, IsEquationSixWithTheFusionsWrittenOut) {
  constexpr int kHandles = 3;
  constexpr long kStride = 140, kBegin = 5, kEnd = 138;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> value(-1, 1);
  std::vector<double> constant(3 * kStride), weights(4 * kHandles * kStride), frames(12 * kHandles);
  for (auto* v : {&constant, &weights, &frames})
    for (double& x : *v) x = value(rng);
  std::vector<double> out(3 * kStride, 0.0);
  basis_rows(constant.data(), weights.data(), kStride, frames.data(), kHandles, kBegin, kEnd, nullptr, 3, out.data());
  int plain_differs = 0;
  for (long i = kBegin; i < kEnd; ++i) {
    Eigen::Vector3d product(constant[i], constant[kStride + i], constant[2 * kStride + i]);
    for (int h = 0; h < kHandles; ++h) {
      const Eigen::Map<const Eigen::Matrix<double, 3, 4>> f(frames.data() + 12 * h);
      Eigen::Vector4d w;
      for (int k = 0; k < 4; ++k) w[k] = weights[(4 * h + k) * kStride + i];
      product += f * w;
    }
    for (int r = 0; r < 3; ++r) {
      double x = constant[r * kStride + i], plain = x;
      for (int h = 0; h < kHandles; ++h) {
        const double* f = frames.data() + 12 * h;
        const auto w = [&](int k) { return weights[(4 * h + k) * kStride + i]; };
        volatile double p0 = w(0) * f[r], p1 = w(1) * f[3 + r], p2 = w(2) * f[6 + r], p3 = w(3) * f[9 + r];
        if (r < 2) {
          x = x + std::fma(w(3), f[9 + r], std::fma(w(2), f[6 + r], std::fma(w(1), f[3 + r], p0)));
        } else {
          x = x + (std::fma(w(3), f[9 + r], p2) + std::fma(w(1), f[3 + r], p0));
        }
        volatile double s01 = p0 + p1, s012 = s01 + p2;
        plain = plain + (s012 + p3);
      }
      const double got = out[static_cast<std::size_t>(3 * i + r)];
      EXPECT_EQ(got, x) << "vertex " << i << " row " << r;
      EXPECT_NEAR(got, product[r], 1e-13);
      plain_differs += got != plain;
    }
  }
  EXPECT_GT(plain_differs, 0);
  // Outside [begin, end) nothing is written.
  for (long i = 0; i < kBegin; ++i) EXPECT_EQ(out[static_cast<std::size_t>(3 * i)], 0.0);
}

}  // namespace
}  // namespace ffd
