// Boxes fitted to points (warp/box_fit.h): the principal-component box finds a rotated
// box's own axes, every fit contains its points, and no finite input (coordinates of
// 1e34 or 1e300) crashes a fit or yields a box that is not finite.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <random>

#include "common/errors.h"
#include "test_meshes.h"
#include "warp/box_fit.h"
#include "warp/lattice.h"

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

// The lattice step's vertices_inside() skips its count when the bounds' two corners lie in an
// axis-aligned box fitted around them. Box coordinates never decrease as a world coordinate
// grows, so then every point is inside: check it against the count, at padding 0 (the
// tightest) and where rounding puts extreme points outside (far from the origin, tiny).
TEST(BoxFit, EveryPointIsInsideAnAxisAlignedBoxHoldingItsBoundsCorners) {
  std::vector<Eigen::Matrix3Xd> sets;
  for (double scale : {1.0, 1e34, 1e-30}) sets.push_back(test::bunny().positions() * scale);
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> unit(0, 1);
  for (double offset : {1e8, -3e12, 0.1})
    for (double spread : {1e-3, 1e-7, 1.0}) {
      if (std::abs(offset) * 1e-16 > 1e-3 * spread) continue;  // no box: min and max round together
      Eigen::Matrix3Xd p(3, 2000);
      for (Eigen::Index i = 0; i < p.cols(); ++i)
        for (int a = 0; a < 3; ++a) p(a, i) = offset + spread * unit(random);
      sets.push_back(p);
    }
  int skipped = 0, counted = 0;
  for (const Eigen::Matrix3Xd& p : sets)
    for (double padding : {0.0, 1e-12, 0.05}) {
      const PointBounds bounds = point_bounds(p, {});
      const Parallelepiped box = aabb_around(bounds, padding);
      long inside = 0;
      for (Eigen::Index i = 0; i < p.cols(); ++i) inside += Lattice::inside(box.to_local(p.col(i)));
      if (Lattice::inside(box.to_local(bounds.lo)) && Lattice::inside(box.to_local(bounds.hi))) {
        ++skipped;
        EXPECT_EQ(inside, p.cols()) << "padding " << padding << ", first point " << p.col(0).transpose();
      } else {
        ++counted;
      }
    }
  EXPECT_GT(skipped, 0);
  EXPECT_GT(counted, 0);  // the far, tiny sets at padding 0 need the count
}

}  // namespace
}  // namespace ffd
