// Boxes fitted to points (warp/box_fit.h): the principal-component box finds a rotated
// box's own axes, every fit contains its points, and no finite input (coordinates of
// 1e34 or 1e300) crashes a fit or yields a box that is not finite.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <random>

#include "common/errors.h"
#include "test_meshes.h"
#include "warp/box_fit.h"

namespace ffd {
namespace {

// The points of a w × h × d box's surface grid, rotated by `r` and moved to `t`.
Eigen::Matrix3Xd rotated_box_points(const Eigen::Matrix3d& r, const Eigen::Vector3d& t) {
  std::vector<Eigen::Vector3d> pts;
  const Eigen::Vector3d size(4, 2, 1);
  for (int i = 0; i <= 8; ++i)
    for (int j = 0; j <= 8; ++j)
      for (int k = 0; k <= 8; ++k)
        if (i % 8 == 0 || j % 8 == 0 || k % 8 == 0) pts.push_back(size.cwiseProduct(Eigen::Vector3d(i, j, k) / 8.0));
  Eigen::Matrix3Xd out(3, static_cast<Eigen::Index>(pts.size()));
  for (std::size_t i = 0; i < pts.size(); ++i) out.col(static_cast<Eigen::Index>(i)) = r * pts[i] + t;
  return out;
}

bool contains(const Parallelepiped& box, const Eigen::Matrix3Xd& points) {
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    const Eigen::Vector3d u = box.to_local(points.col(i));
    if (!(u.array() >= -1e-9).all() || !(u.array() <= 1 + 1e-9).all()) return false;
  }
  return true;
}

TEST(BoxFit, ThePrincipalBoxFindsARotatedBoxsAxes) {
  const Eigen::Matrix3d r = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Matrix3Xd points = rotated_box_points(r, Eigen::Vector3d(5, -2, 1));
  const Parallelepiped box = fit_principal_box(points, {}, 0);
  EXPECT_TRUE(contains(box, points));
  // Its edges are the rotated box's (4, 2, 1 along r's columns), up to order and sign.
  const Eigen::Vector3d extents = box.extents();
  EXPECT_NEAR(extents.maxCoeff(), 4, 1e-9);
  EXPECT_NEAR(extents.minCoeff(), 1, 1e-9);
  EXPECT_NEAR(std::abs(box.axes().determinant()), 8, 1e-8);
  // Right-handed, and the first axis lies closest to x.
  EXPECT_GT(box.axes().determinant(), 0);
  for (int a = 0; a < 3; ++a) EXPECT_GT(box.axes().col(a)[a], 0);
  // The least-volume box is the same box.
  const Parallelepiped least = fit_min_volume_box(points, {}, 0);
  EXPECT_TRUE(contains(least, points));
  EXPECT_NEAR(std::abs(least.axes().determinant()), 8, 1e-6);
}

TEST(BoxFit, EveryFitContainsTheBunnyAndPads) {
  const Mesh bunny = test::bunny();
  const Eigen::Matrix3Xd p = bunny.positions();
  for (const Parallelepiped& box : {fit_aabb(p, {}, 0.05), fit_principal_box(p, {}, 0.05), fit_min_volume_box(p, {}, 0.05)}) {
    EXPECT_TRUE(contains(box, p));
    const Eigen::Matrix3d axes = box.axes();
    EXPECT_NEAR((axes.transpose() * axes - Eigen::Matrix3d(axes.colwise().squaredNorm().asDiagonal())).norm(), 0,
                1e-9 * axes.squaredNorm());  // orthogonal edges
  }
  // The bunny's principal box is no larger than its axis-aligned one by much, and the
  // least-volume box is the smallest (within the genetic search's tolerance).
  const double aabb = std::abs(fit_aabb(p, {}, 0).axes().determinant());
  const double pca = std::abs(fit_principal_box(p, {}, 0).axes().determinant());
  const double least = std::abs(fit_min_volume_box(p, {}, 0).axes().determinant());
  EXPECT_LE(least, 1.01 * pca);
  EXPECT_LE(least, 1.01 * aabb);
}

TEST(BoxFit, HugeAndTinyFiniteCoordinatesNeitherCrashNorMisbehave) {
  const Mesh bunny = test::bunny();
  for (double scale : {1e34, 1e-30, 1e300}) {
    SCOPED_TRACE(scale);
    const Eigen::Matrix3Xd p = bunny.positions() * scale;
    for (int fit = 0; fit < 3; ++fit) {
      try {
        const Parallelepiped box = fit == 0 ? fit_aabb(p, {}, 0.05) : fit == 1 ? fit_principal_box(p, {}, 0.05)
                                                                               : fit_min_volume_box(p, {}, 0.05);
        EXPECT_TRUE(box.axes().allFinite() && box.origin().allFinite());
        EXPECT_TRUE(contains(box, p));
      } catch (const InputError& e) {
        // Only where the box itself would overflow double.
        EXPECT_EQ(scale, 1e300) << e.what();
      }
    }
  }
  // A flat set and a single point still get solid boxes.
  Eigen::Matrix3Xd flat = test::bunny().positions();
  flat.row(2).setZero();
  EXPECT_GT(std::abs(fit_principal_box(flat, {}, 0).axes().determinant()), 0);
  EXPECT_GT(std::abs(fit_principal_box(flat.leftCols(1), {}, 0).axes().determinant()), 0);
}

}  // namespace
}  // namespace ffd
