// Lattice FFD: bases, identity, Jacobians, continuity at the box, batch = single point.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <random>

#include <omp.h>

#include "test_meshes.h"
#include "warp/bernstein_lattice.h"
#include "warp/bspline_lattice.h"
#include "warp/warp_points.h"

namespace ffd {
namespace {

using test::skewed_box;

struct LatticeCase {
  std::string name;
  std::function<std::unique_ptr<Lattice>(const Parallelepiped&)> make;
};

std::vector<LatticeCase> all_lattices() {
  return {
      {"bspline1", [](const Parallelepiped& b) { return std::make_unique<BSplineLattice>(b, Index3{3, 4, 2}, 1); }},
      {"bspline2", [](const Parallelepiped& b) { return std::make_unique<BSplineLattice>(b, Index3{4, 3, 5}, 2); }},
      {"bspline3", [](const Parallelepiped& b) { return std::make_unique<BSplineLattice>(b, Index3{5, 6, 4}, 3); }},
      {"bernstein", [](const Parallelepiped& b) { return std::make_unique<BernsteinLattice>(b, Index3{3, 5, 2}); }},
      // Degree 3 on every axis has kernels of its own (the degree known when compiled).
      {"bernstein_cubic", [](const Parallelepiped& b) { return std::make_unique<BernsteinLattice>(b, Index3{3, 3, 3}); }},
      {"bernstein_high", [](const Parallelepiped& b) { return std::make_unique<BernsteinLattice>(b, Index3{9, 1, 12}); }},
  };
}

// Moves every movable point by a random offset of up to `size`.
void perturb(Lattice& lattice, double size, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1, 1);
  for (std::size_t f = 0; f < lattice.num_points(); ++f) {
    const Index3 ijk = lattice.index(f);
    if (lattice.movable(ijk))
      lattice.move_point(ijk, lattice.point(ijk) + size * Eigen::Vector3d(uniform(rng), uniform(rng), uniform(rng)));
  }
}

// Unit vectors (materialized first: a Random expression re-evaluates per access).
Eigen::Matrix3Xd random_unit(Eigen::Index n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  Eigen::Matrix3Xd m(3, n);
  for (Eigen::Index i = 0; i < n; ++i) m.col(i) = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
  return m;
}

Eigen::Matrix3Xd random_inside(const Parallelepiped& box, int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(0, 1);
  Eigen::Matrix3Xd p(3, n);
  for (int i = 0; i < n; ++i) p.col(i) = box.to_world(Eigen::Vector3d(uniform(rng), uniform(rng), uniform(rng)));
  return p;
}

TEST(Lattice, PartitionOfUnityAndLinearPrecisionPerAxis) {
  for (const LatticeCase& c : all_lattices()) {
    auto lattice = c.make(skewed_box());
    for (int axis = 0; axis < 3; ++axis)
      for (int s = 0; s <= 200; ++s) {
        const double u = s / 200.0;
        int first;
        double w[32], dw[32];
        lattice->axis_weights(axis, u, first, w, dw);
        double sum = 0, moment = 0, dsum = 0, dmoment = 0;
        for (int i = 0; i < lattice->order(axis); ++i) {
          Index3 ijk{0, 0, 0};
          ijk[axis] = first + i;
          // Node position along this axis, read back from the rest point in box coordinates.
          const double node = lattice->box().to_local(lattice->rest_point(ijk))[axis];
          sum += w[i];
          moment += w[i] * node;
          dsum += dw[i];
          dmoment += dw[i] * node;
        }
        EXPECT_NEAR(sum, 1.0, 1e-12) << c.name << " axis " << axis << " u " << u;
        EXPECT_NEAR(moment, u, 1e-12) << c.name << " axis " << axis << " u " << u;
        EXPECT_NEAR(dsum, 0.0, 1e-10) << c.name;
        EXPECT_NEAR(dmoment, 1.0, 1e-10) << c.name;
      }
  }
}

TEST(Lattice, RestLatticeIsIdentityInFullForm) {
  // Eq. 1 with the rest control points (not the displacement form): sum_ijk B B B P° = x.
  for (const LatticeCase& c : all_lattices()) {
    auto lattice = c.make(skewed_box());
    const Eigen::Matrix3Xd pts = random_inside(lattice->box(), 200, 3);
    for (int v = 0; v < pts.cols(); ++v) {
      const Eigen::Vector3d u = lattice->box().to_local(pts.col(v));
      int first[3];
      double w[3][32], dw[3][32];
      for (int a = 0; a < 3; ++a) lattice->axis_weights(a, u[a], first[a], w[a], dw[a]);
      Eigen::Vector3d x = Eigen::Vector3d::Zero();
      for (int i = 0; i < lattice->order(0); ++i)
        for (int j = 0; j < lattice->order(1); ++j)
          for (int k = 0; k < lattice->order(2); ++k)
            x += w[0][i] * w[1][j] * w[2][k] * lattice->rest_point({first[0] + i, first[1] + j, first[2] + k});
      EXPECT_LT((x - pts.col(v)).norm(), 1e-12 * lattice->box().extents().norm()) << c.name;
    }
  }
}

TEST(Lattice, UnmovedLatticeIsExactIdentity) {
  for (const LatticeCase& c : all_lattices()) {
    auto lattice = c.make(skewed_box());
    const Eigen::Matrix3Xd pts = random_inside(lattice->box(), 500, 4);
    const Eigen::Matrix3Xd nrm = random_unit(pts.cols(), 40);
    for (int v = 0; v < pts.cols(); ++v) {
      Eigen::Matrix3d J;
      EXPECT_EQ(lattice->apply(pts.col(v), &J), Eigen::Vector3d(pts.col(v))) << c.name;
      EXPECT_TRUE(J.isIdentity(0.0)) << c.name;
    }
    std::vector<std::uint32_t> ids(pts.cols());
    std::iota(ids.begin(), ids.end(), 0u);
    Eigen::Matrix3Xd out_pos(3, pts.cols()), out_nrm(3, pts.cols());
    WarpCounts counts;
    lattice->apply(pts, nrm, ids, out_pos, out_nrm, counts);
    EXPECT_EQ(out_pos, pts) << c.name;
    EXPECT_LT((out_nrm - nrm).cwiseAbs().maxCoeff(), 1e-15) << c.name;
  }
}

TEST(Lattice, JacobianMatchesCentralDifferences) {
  for (const LatticeCase& c : all_lattices()) {
    auto lattice = c.make(skewed_box());
    perturb(*lattice, 0.15, 5);
    // Stay away from cell boundaries of the degree-1 spline (its derivative jumps there).
    const Eigen::Matrix3Xd pts = random_inside(lattice->box(), 200, 6);
    const double h = 1e-6;
    for (int v = 0; v < pts.cols(); ++v) {
      Eigen::Matrix3d J;
      lattice->apply(pts.col(v), &J);
      Eigen::Matrix3d fd;
      for (int a = 0; a < 3; ++a) {
        const Eigen::Vector3d e = Eigen::Vector3d::Unit(a) * h;
        fd.col(a) = (lattice->apply(pts.col(v) + e, nullptr) - lattice->apply(pts.col(v) - e, nullptr)) / (2 * h);
      }
      if (c.name == "bspline1" && (J - fd).norm() > 1e-3) continue;  // straddles a knot plane
      EXPECT_LT((J - fd).norm(), 1e-6 * std::max(1.0, J.norm())) << c.name << " point " << v;
    }
  }
}

TEST(Lattice, BatchEvaluationMatchesSinglePoint) {
  // The B-spline batch path evaluates per-cell power coefficients by Horner's rule; the
  // single-point path contracts basis weights: two independent formulas.
  for (const LatticeCase& c : all_lattices()) {
    auto lattice = c.make(skewed_box());
    perturb(*lattice, 0.1, 8);
    lattice->prepare();
    Eigen::Matrix3Xd pts = random_inside(lattice->box(), 1000, 9);
    pts.col(0) = lattice->box().origin() - Eigen::Vector3d(0.3, 0, 0);  // outside
    const Eigen::Matrix3Xd nrm = random_unit(pts.cols(), 40);
    std::vector<std::uint32_t> ids(pts.cols());
    std::iota(ids.begin(), ids.end(), 0u);
    Eigen::Matrix3Xd out_pos(3, pts.cols()), out_nrm(3, pts.cols());
    WarpCounts counts;
    lattice->apply(pts, nrm, ids, out_pos, out_nrm, counts);
    for (int v = 0; v < pts.cols(); ++v) {
      Eigen::Matrix3d J;
      const Eigen::Vector3d x = lattice->apply(pts.col(v), &J);
      EXPECT_LT((x - out_pos.col(v)).norm(), 1e-12) << c.name << " " << v;
      const Eigen::Vector3d n = cofactor_times(J, nrm.col(v)).normalized();
      EXPECT_LT((n - out_nrm.col(v)).norm(), 1e-11) << c.name << " " << v;
    }
    EXPECT_EQ(out_pos.col(0), pts.col(0));
    EXPECT_EQ(out_nrm.col(0), nrm.col(0));
  }
}

TEST(Lattice, PositionsKernelsAgreeWithTheBatchPathAtAnyThreadCount) {
  // warp_points (the Python module's d(points)) uses the lattices' positions-only kernels:
  // the Bernstein one sums as apply() does, block by block; both agree with the batch
  // path to 1e-14 of the box, leave points outside untouched, and give the same bits for
  // one thread and two, with or without Jacobians.
  for (const LatticeCase& c : all_lattices()) {
    auto lattice = c.make(skewed_box());
    perturb(*lattice, 0.1, 12);
    lattice->prepare();
    Eigen::Matrix3Xd pts = random_inside(lattice->box(), 1001, 13);  // not a whole number of blocks
    pts.col(5) = lattice->box().origin() - Eigen::Vector3d(0.3, 0, 0);
    std::vector<std::uint32_t> ids(pts.cols());
    std::iota(ids.begin(), ids.end(), 0u);
    Eigen::Matrix3Xd batch(3, pts.cols()), nrm = random_unit(pts.cols(), 14), out_n(3, pts.cols());
    WarpCounts counts;
    lattice->apply(pts, nrm, ids, batch, out_n, counts);
    const int threads = omp_get_max_threads();
    Eigen::Matrix3Xd one(3, pts.cols()), two(3, pts.cols()), with_jacobians(3, pts.cols());
    std::vector<double> jacobians(9 * pts.cols());
    omp_set_num_threads(1);
    warp_points(*lattice, pts, one);
    omp_set_num_threads(2);
    warp_points(*lattice, pts, two);
    warp_points(*lattice, pts, with_jacobians, jacobians.data());
    omp_set_num_threads(threads);
    EXPECT_EQ(one, two) << c.name;
    EXPECT_EQ(one, with_jacobians) << c.name;
    EXPECT_EQ(one.col(5), pts.col(5)) << c.name;
    EXPECT_LT((one - batch).cwiseAbs().maxCoeff(), 1e-14 * lattice->box().extents().norm()) << c.name;
    Eigen::Matrix3d J;
    lattice->apply(pts.col(7), &J);
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) EXPECT_EQ(jacobians[9 * 7 + 3 * r + k], J(r, k)) << c.name;
  }
}

TEST(Lattice, PointsWithoutNormalsSkipTheJacobianOnlyWhereNothingCanFold) {
  // Zero normals (a point cloud, or a run that needs none) and a lattice whose derivative
  // bound rules out folds (fold_free): positions only. The positions are the Jacobian
  // path's bit for bit, the normals stay zero, and the fold count is the same: zero where
  // the bound holds, and where it does not the Jacobian path runs and counts.
  for (const LatticeCase& c : all_lattices())
    for (double size : {0.01, 0.6}) {
      auto lattice = c.make(skewed_box());
      perturb(*lattice, size, 21);
      lattice->prepare();
      const Eigen::Matrix3Xd pts = random_inside(lattice->box(), 2001, 22);
      std::vector<std::uint32_t> ids(pts.cols());
      std::iota(ids.begin(), ids.end(), 0u);
      const Eigen::Matrix3Xd zero = Eigen::Matrix3Xd::Zero(3, pts.cols()), nrm = random_unit(pts.cols(), 23);
      Eigen::Matrix3Xd fast(3, pts.cols()), fast_n(3, pts.cols()), full(3, pts.cols()), full_n(3, pts.cols());
      WarpCounts without, with;
      lattice->apply(pts, zero, ids, fast, fast_n, without);
      lattice->apply(pts, nrm, ids, full, full_n, with);
      EXPECT_EQ(fast, full) << c.name << " " << size;
      EXPECT_TRUE(fast_n.isZero(0.0)) << c.name << " " << size;
      EXPECT_EQ(without.folded, with.folded) << c.name << " " << size;
      EXPECT_EQ(without.evaluated, with.evaluated) << c.name << " " << size;
      std::size_t folds = 0;
      for (Eigen::Index v = 0; v < pts.cols(); ++v) {
        Eigen::Matrix3d J;
        lattice->apply(pts.col(v), &J);
        folds += J.determinant() <= 0;
      }
      EXPECT_EQ(with.folded, folds) << c.name << " " << size;
      if (size < 0.05) {
        EXPECT_TRUE(lattice->fold_free()) << c.name;  // the fast path ran
      }
      if (lattice->fold_free()) {
        EXPECT_EQ(folds, 0u) << c.name;  // the bound is sound
      }
      // A run that needs no normals (WarpStack, Mesh::normals_deferred): positions without
      // normals, the zero-normal apply's bit for bit with its counts. A B-spline lattice
      // counts its folds from det J there; a Bernstein one declines where it can fold and
      // writes nothing.
      Eigen::Matrix3Xd alone = Eigen::Matrix3Xd::Constant(3, pts.cols(), 7.0);
      WarpCounts alone_counts;
      const bool took = lattice->apply_without_normals(pts, ids, alone, alone_counts);
      const bool bspline = dynamic_cast<const BSplineLattice*>(lattice.get()) != nullptr;
      EXPECT_EQ(took, bspline || lattice->fold_free()) << c.name << " " << size;
      if (took) {
        EXPECT_EQ(alone, fast) << c.name << " " << size;
        EXPECT_EQ(alone_counts.folded, without.folded) << c.name << " " << size;
        EXPECT_EQ(alone_counts.evaluated, without.evaluated) << c.name << " " << size;
      } else {
        EXPECT_TRUE((alone.array() == 7.0).all()) << c.name << " " << size;
      }
    }
}

TEST(Lattice, BatchIsBitIdenticalForAnyThreadCount) {
  BSplineLattice lattice(skewed_box(), {6, 6, 6}, 3);
  perturb(lattice, 0.1, 10);
  const Eigen::Matrix3Xd pts = random_inside(lattice.box(), 20000, 11);
  const Eigen::Matrix3Xd nrm = random_unit(pts.cols(), 40);
  std::vector<std::uint32_t> ids(pts.cols());
  std::iota(ids.begin(), ids.end(), 0u);
  Eigen::Matrix3Xd p1(3, pts.cols()), n1(3, pts.cols()), p2(3, pts.cols()), n2(3, pts.cols());
  WarpCounts counts;
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  lattice.apply(pts, nrm, ids, p1, n1, counts);
  omp_set_num_threads(2);
  lattice.apply(pts, nrm, ids, p2, n2, counts);
  omp_set_num_threads(threads);
  EXPECT_EQ(p1, p2);
  EXPECT_EQ(n1, n2);
}

// One move's update both ways on a skewed box, with points inside and around it: what
// apply_changed() writes and lists is what changed_points() then apply() (or
// apply_without_normals()) would, bit for bit, at one thread and two; columns it does not
// list keep what was there.
void expect_apply_changed_matches(const Lattice& lattice, const Eigen::Matrix3Xd& pts,
                                  const Eigen::Matrix3Xd& nrm, bool normals) {
  std::vector<std::uint32_t> listed;
  lattice.changed_points(pts, listed);
  const Eigen::Matrix3Xd before = pts.array() + 7.0;  // what an output held before the move
  Eigen::Matrix3Xd p(before), n(before);
  WarpCounts counts;
  if (normals)
    lattice.apply(pts, nrm, listed, p, n, counts);
  else
    ASSERT_TRUE(lattice.apply_without_normals(pts, listed, p, counts));
  const int threads = omp_get_max_threads();
  for (int t : {1, 2}) {
    omp_set_num_threads(t);
    std::vector<std::uint32_t> found;
    Eigen::Matrix3Xd pf(before), nf(before);
    WarpCounts fused;
    const Eigen::Ref<const Eigen::Matrix3Xd> in_nrm = nrm;
    Eigen::Ref<Eigen::Matrix3Xd> out_nrm = nf;
    ASSERT_TRUE(lattice.apply_changed(pts, normals ? &in_nrm : nullptr, found, pf, normals ? &out_nrm : nullptr, fused));
    EXPECT_EQ(found, listed) << t << " threads";
    EXPECT_EQ(pf, p) << t << " threads";
    EXPECT_EQ(nf, n) << t << " threads";
    EXPECT_EQ(fused.evaluated, counts.evaluated);
    EXPECT_EQ(fused.folded, counts.folded);
  }
  omp_set_num_threads(threads);
}

TEST(BSplineLattice, ApplyChangedIsChangedPointsThenApply) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> around(-0.2, 1.2);
  for (const Index3 cells : {Index3{4, 4, 4}, Index3{8, 7, 9}})
    for (int degree : {1, 2, 3}) {
      SCOPED_TRACE(testing::Message() << "degree " << degree << ", cells " << cells[0]);
      BSplineLattice lattice(skewed_box(), cells, degree);
      Eigen::Matrix3Xd pts(3, 30000);
      for (Eigen::Index i = 0; i < pts.cols(); ++i)
        pts.col(i) = lattice.box().to_world(Eigen::Vector3d(around(rng), around(rng), around(rng)));
      const Eigen::Matrix3Xd nrm = random_unit(pts.cols(), 41);
      int lo[3], hi[3];
      for (int a = 0; a < 3; ++a) lattice.movable_span(a, lo[a], hi[a]);
      // A first move (every cell changed on the 4^3 lattice), then one elsewhere.
      for (const Index3 ijk : {Index3{lo[0], lo[1], lo[2]}, Index3{hi[0], lo[1], hi[2]}}) {
        lattice.move_point(ijk, lattice.point(ijk) + Eigen::Vector3d(0.05, -0.08, 0.03));
        lattice.prepare();
        expect_apply_changed_matches(lattice, pts, nrm, true);
        expect_apply_changed_matches(lattice, pts, Eigen::Matrix3Xd::Zero(3, pts.cols()), false);
        lattice.clear_changes();
      }
    }
}

// The Bernstein lattice fuses the scan only where it evaluates positions alone (no
// normals, no fold possible); with normals it leaves the two calls to the stack.
TEST(BernsteinLattice, ApplyChangedIsChangedPointsThenApplyWithoutNormals) {
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> around(-0.2, 1.2);
  for (const Index3 degree : {Index3{3, 3, 3}, Index3{2, 4, 3}}) {
    BernsteinLattice lattice(skewed_box(), degree);
    Eigen::Matrix3Xd pts(3, 20000);
    for (Eigen::Index i = 0; i < pts.cols(); ++i)
      pts.col(i) = lattice.box().to_world(Eigen::Vector3d(around(rng), around(rng), around(rng)));
    const Index3 ijk{1, 1, 1};
    lattice.move_point(ijk, lattice.point(ijk) + Eigen::Vector3d(0.01, -0.02, 0.015));
    lattice.prepare();
    ASSERT_TRUE(lattice.fold_free());
    expect_apply_changed_matches(lattice, pts, Eigen::Matrix3Xd::Zero(3, pts.cols()), false);
    std::vector<std::uint32_t> ids;
    Eigen::Matrix3Xd p(pts), n(pts);
    const Eigen::Matrix3Xd nrm = random_unit(pts.cols(), 42);
    const Eigen::Ref<const Eigen::Matrix3Xd> in_nrm = nrm;
    Eigen::Ref<Eigen::Matrix3Xd> out_nrm = n;
    WarpCounts counts;
    EXPECT_FALSE(lattice.apply_changed(pts, &in_nrm, ids, p, &out_nrm, counts));
    EXPECT_TRUE(ids.empty());
    EXPECT_EQ(p, pts);
  }
}

TEST(BSplineLattice, MovableZonesFollowTheDegree) {
  const Parallelepiped box = skewed_box();
  int lo, hi;
  BSplineLattice cubic(box, {6, 7, 4}, 3);
  cubic.movable_span(0, lo, hi);
  EXPECT_EQ(lo, 2);
  EXPECT_EQ(hi, 4);
  cubic.movable_span(2, lo, hi);
  EXPECT_EQ(lo, 2);
  EXPECT_EQ(hi, 2);
  EXPECT_EQ(cubic.first_index(0), -1);
  EXPECT_EQ(cubic.last_index(0), 7);
  BSplineLattice quadratic(box, {5, 5, 5}, 2);
  quadratic.movable_span(0, lo, hi);
  EXPECT_EQ(lo, 1);
  EXPECT_EQ(hi, 3);
  EXPECT_EQ(quadratic.first_index(0), -1);
  EXPECT_EQ(quadratic.last_index(0), 5);
  BSplineLattice linear(box, {5, 5, 5}, 1);
  linear.movable_span(0, lo, hi);
  EXPECT_EQ(lo, 1);
  EXPECT_EQ(hi, 4);
  EXPECT_THROW(cubic.move_point({1, 3, 2}, Eigen::Vector3d::Zero()), std::logic_error);
  EXPECT_NO_THROW(cubic.move_point({2, 3, 2}, Eigen::Vector3d::Zero()));
  EXPECT_EQ(cubic.movable_range(), "i in [2, 4], j in [2, 5], k in [2, 2]");
}

TEST(BSplineLattice, OutsideTheBoxIsUntouchedBitForBit) {
  BSplineLattice lattice(skewed_box(), {6, 6, 6}, 3);
  perturb(lattice, 0.3, 12);
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> uniform(-1, 2);
  int outside = 0;
  for (int i = 0; i < 5000; ++i) {
    const Eigen::Vector3d u(uniform(rng), uniform(rng), uniform(rng));
    if (Lattice::inside(u)) continue;
    ++outside;
    const Eigen::Vector3d x = lattice.box().to_world(u);
    EXPECT_EQ(lattice.apply(x, nullptr), x);
  }
  EXPECT_GT(outside, 1000);
}

// Displacement D = F(x) - x at distance eps inside a box face, along the face's inward
// normal direction in box coordinates.
double displacement_near_face(const Lattice& lattice, int axis, bool high, double eps, const Eigen::Vector2d& at) {
  Eigen::Vector3d u;
  int k = 0;
  for (int a = 0; a < 3; ++a) u[a] = a == axis ? (high ? 1 - eps : eps) : at[k++];
  const Eigen::Vector3d x = lattice.box().to_world(u);
  return (lattice.apply(x, nullptr) - x).norm();
}

TEST(BSplineLattice, ContinuityAcrossTheBoxFacesMatchesTheDegree) {
  // C^(d-1) with the identity outside means D and its first d-1 derivatives vanish on the
  // faces, so |D| = O(eps^d) at distance eps inside. Measure the order numerically.
  for (int degree = 1; degree <= 3; ++degree) {
    BSplineLattice lattice(skewed_box(), {6, 6, 6}, degree);
    perturb(lattice, 0.3, 14 + degree);
    for (int axis = 0; axis < 3; ++axis)
      for (bool high : {false, true}) {
        const Eigen::Vector2d at(0.37, 0.61);
        const double d1 = displacement_near_face(lattice, axis, high, 1e-2, at);
        const double d2 = displacement_near_face(lattice, axis, high, 1e-3, at);
        ASSERT_GT(d1, 0);
        const double order = std::log10(d1 / d2);
        EXPECT_NEAR(order, degree, 0.05) << "degree " << degree << " axis " << axis << " high " << high;
        EXPECT_LT(displacement_near_face(lattice, axis, high, 0.0, at), 1e-15 * lattice.box().extents().norm());
      }
  }
}

TEST(BernsteinLattice, MatchesSederbergParryDirectFormula) {
  // X_ffd = sum_i C(l,i)(1-s)^(l-i) s^i [sum_j C(m,j) ... [sum_k C(n,k) ... P_ijk]],
  // evaluated with pow and binomials, P_ijk = X0 + (i/l) S + (j/m) T + (k/n) U + moves.
  const Parallelepiped box = skewed_box();
  const Index3 deg{4, 3, 5};
  BernsteinLattice lattice(box, deg);
  perturb(lattice, 0.2, 20);
  lattice.prepare();
  const auto binomial = [](int n, int k) { return std::tgamma(n + 1.0) / (std::tgamma(k + 1.0) * std::tgamma(n - k + 1.0)); };
  const Eigen::Matrix3Xd pts = random_inside(box, 300, 21);
  std::vector<std::uint32_t> ids(pts.cols());
  std::iota(ids.begin(), ids.end(), 0u);
  Eigen::Matrix3Xd out(3, pts.cols()), nrm = Eigen::Matrix3Xd::Zero(3, pts.cols()), out_n(3, pts.cols());
  WarpCounts counts;
  lattice.apply(pts, nrm, ids, out, out_n, counts);
  for (int v = 0; v < pts.cols(); ++v) {
    const Eigen::Vector3d stu = box.to_local(pts.col(v));
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (int i = 0; i <= deg[0]; ++i)
      for (int j = 0; j <= deg[1]; ++j)
        for (int k = 0; k <= deg[2]; ++k) {
          const double b = binomial(deg[0], i) * std::pow(1 - stu[0], deg[0] - i) * std::pow(stu[0], i) *
                           binomial(deg[1], j) * std::pow(1 - stu[1], deg[1] - j) * std::pow(stu[1], j) *
                           binomial(deg[2], k) * std::pow(1 - stu[2], deg[2] - k) * std::pow(stu[2], k);
          const Eigen::Vector3d P = box.origin() + box.axes().col(0) * (double(i) / deg[0]) +
                                    box.axes().col(1) * (double(j) / deg[1]) +
                                    box.axes().col(2) * (double(k) / deg[2]) + lattice.displacement(lattice.flat({i, j, k}));
          x += b * P;
        }
    EXPECT_LT((x - out.col(v)).norm(), 1e-12 * box.extents().norm()) << v;
    EXPECT_LT((x - lattice.apply(pts.col(v), nullptr)).norm(), 1e-12 * box.extents().norm()) << v;
  }
}

TEST(BernsteinLattice, ContinuousAtTheBoxOnlyWhileFacePointsStay) {
  const Parallelepiped box = skewed_box();
  BernsteinLattice lattice(box, {3, 3, 3});
  lattice.move_point({1, 2, 1}, lattice.point({1, 2, 1}) + Eigen::Vector3d(0.2, -0.1, 0.3));
  EXPECT_EQ(lattice.boundary_continuity(), 0);
  for (int axis = 0; axis < 3; ++axis)
    EXPECT_LT(displacement_near_face(lattice, axis, true, 0.0, Eigen::Vector2d(0.3, 0.6)), 1e-15);
  lattice.move_point({3, 1, 1}, lattice.point({3, 1, 1}) + Eigen::Vector3d(0.2, 0, 0));
  EXPECT_EQ(lattice.boundary_continuity(), -1);
  EXPECT_GT(displacement_near_face(lattice, 0, true, 0.0, Eigen::Vector2d(0.3, 0.4)), 1e-3);
}

TEST(Lattice, TangentsAndNormalsStayOrthogonal) {
  // Covariant normal n' = cof(J) n and contravariant tangent t' = J t (eq. 2-3):
  // n'·t' = det(J) n·t = 0 for every tangent t of the rest surface.
  BSplineLattice lattice(skewed_box(), {5, 5, 5}, 3);
  perturb(lattice, 0.2, 30);
  const Eigen::Matrix3Xd pts = random_inside(lattice.box(), 200, 31);
  std::mt19937 rng(32);
  std::normal_distribution<double> g;
  for (int v = 0; v < pts.cols(); ++v) {
    Eigen::Matrix3d J;
    lattice.apply(pts.col(v), &J);
    const Eigen::Vector3d n = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    const Eigen::Vector3d t = n.cross(Eigen::Vector3d(g(rng), g(rng), g(rng))).normalized();
    const Eigen::Vector3d n2 = cofactor_times(J, n), t2 = transform_tangent(J, t);
    EXPECT_LT(std::abs(n2.dot(t2)), 1e-12 * n2.norm() * t2.norm());
  }
}

}  // namespace
}  // namespace ffd
