// Octree lattices and Catmull-Clark subdivision volumes (lib/multires): the properties of
// Ono et al.'s multiresolution FFD that could fail.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numeric>
#include <random>

#include "multires/cell_complex.h"
#include "multires/cell_coordinates.h"
#include "multires/octree_lattice.h"
#include "multires/trilinear_lanes.h"
#include "multires/volume_subdivision.h"
#include "support/eigen_lu.h"
#include "test_meshes.h"
#include "warp/box_fit.h"
#include "warp/bspline_lattice.h"
#include "warp/warp_stack.h"

namespace ffd {
namespace {

/// Points filling the unit cube on an m^3 grid of cell centres (no cell is cut).
Eigen::Matrix3Xd filling_points(int m) {
  Eigen::Matrix3Xd p(3, m * m * m);
  int n = 0;
  for (int k = 0; k < m; ++k)
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) p.col(n++) = (Eigen::Vector3d(i, j, k) + Eigen::Vector3d::Constant(0.5)) / m;
  return p;
}

Parallelepiped unit_box() { return Parallelepiped::from_min_max(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()); }

OctreeOptions options(int levels, int cc_steps) {
  OctreeOptions o;
  o.levels = levels;
  o.cc_steps = cc_steps;
  return o;
}

/// The bunny's vertices, and an octree lattice around them on their principal box.
struct BunnyLattice {
  Mesh mesh = test::bunny();
  Eigen::Matrix3Xd x = mesh.positions();
  Parallelepiped box = fit_principal_box(x, {}, 0.05);
};

void move_one(OctreeLattice& lattice, int level, const GridIndex& node, const Eigen::Vector3d& by) {
  const std::int32_t id = lattice.point_index(level, node);
  ASSERT_GE(id, 0);
  lattice.move_level_points(level, {id}, {Eigen::Vector3d(lattice.points(level).col(id) + by)});
}

/// The matrices a Newton step of inverse_trilinear solves with, and harder ones: random
/// entries over many magnitudes, entries tied in magnitude (the first row keeps the
/// pivot), zeros below a pivot, rows in every order, and nearly singular matrices.
std::vector<Eigen::Matrix3d> solve_cases() {
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  std::uniform_int_distribution<int> small(-2, 2), exponent(-30, 30);
  std::vector<Eigen::Matrix3d> cases;
  for (int n = 0; n < 200000; ++n) {
    Eigen::Matrix3d A;
    for (int e = 0; e < 9; ++e) A(e) = normal(rng);
    switch (n % 4) {
      case 1: A *= std::ldexp(1.0, exponent(rng)); break;
      case 2:
        for (int e = 0; e < 9; ++e) A(e) = small(rng);  // ties and zeros
        break;
      case 3: A.col(2) = A.col(0) + 1e-12 * A.col(1); break;  // nearly singular
      default: break;
    }
    cases.push_back(A);
  }
  return cases;
}

TEST(CellCoordinates, PivotedSolveIsEigensPartialPivLuBitForBit) {
  std::mt19937 rng(11);
  std::normal_distribution<double> normal;
  std::size_t compared = 0;
  for (const Eigen::Matrix3d& A : solve_cases()) {
    if (!(std::abs(A.determinant()) > 1e-300)) continue;  // inverse_trilinear solves no other
    const Eigen::Vector3d b(normal(rng), normal(rng), normal(rng));
    Eigen::Vector3d eigen;
    eigen_partial_pivot_solve(A.data(), b.data(), eigen.data());
    const Eigen::Vector3d ours = pivoted_solve(A, b);
    ASSERT_EQ(std::memcmp(ours.data(), eigen.data(), sizeof(double) * 3), 0)
        << "A =\n" << A << "\nb = " << b.transpose() << "\nours " << ours.transpose() << "\nEigen's "
        << eigen.transpose();
    ++compared;
  }
  EXPECT_GT(compared, 150000u);
}

TEST(CellCoordinates, TheLanesLocateBitForBitAsInverseTrilinear) {
  // Cells from nearly regular (the octree's subdivided rest cells, one Newton step or two)
  // to bent by a third of their edge, scaled over 2^-12..2^12, a few flat or collapsed;
  // points inside and outside, guesses exact to far. Where the lanes decide, the scalar
  // inverse_trilinear returns true with the same bits of u and dx_du.
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> unit(0.0, 1.0), around(-0.3, 1.3);
  std::size_t decided = 0, total = 0;
  for (int n = 0; n < 40000; ++n) {
    TrilinearLanes lanes;
    CellCorners Q[TrilinearLanes::kLanes];
    Eigen::Vector3d x[TrilinearLanes::kLanes], guess[TrilinearLanes::kLanes];
    const int lanes_used = 1 + n % TrilinearLanes::kLanes;
    for (int lane = 0; lane < lanes_used; ++lane) {
      const int kind = (n + lane) % 8;
      const double size = std::ldexp(1.0, static_cast<int>(rng() % 25) - 12);
      const double bend = kind < 4 ? std::ldexp(1.0, -4 * kind - 6) : kind < 7 ? 1.0 / 3 : 0.0;
      std::uniform_real_distribution<double> offset(-bend, bend);
      const Eigen::Vector3d origin(around(rng), around(rng), around(rng));
      for (int c = 0; c < 8; ++c) {
        const Eigen::Vector3d corner((c & 1) ? 1.0 : 0.0, (c & 2) ? 1.0 : 0.0, (c & 4) ? 1.0 : 0.0);
        Q[lane].col(c) = size * (origin + corner + Eigen::Vector3d(offset(rng), offset(rng), offset(rng)));
      }
      if (kind == 7) Q[lane].col(rng() % 8) = Q[lane].col(rng() % 8);  // a collapsed edge, or none
      if (n % 97 == 0) Q[lane].row(2).setConstant(size);               // flat: singular
      const Eigen::Vector3d u(around(rng), around(rng), around(rng));
      x[lane] = trilinear(Q[lane], u, nullptr);
      guess[lane] = n % 3 == 0 ? Eigen::Vector3d(unit(rng), unit(rng), unit(rng))
                               : (u + Eigen::Vector3d::Constant(std::ldexp(1.0, -(n % 40)))).cwiseMax(0.0).cwiseMin(1.0);
      const std::int32_t corner[8] = {0, 1, 2, 3, 4, 5, 6, 7};
      lanes.set_cell(lane, Q[lane], corner);
      lanes.set_point(lane, x[lane], guess[lane]);
    }
    lanes.pad(lanes_used);
    inverse_trilinear(lanes);
    for (int lane = 0; lane < lanes_used; ++lane) {
      Eigen::Vector3d u;
      Eigen::Matrix3d J;
      const bool converged = inverse_trilinear(Q[lane], x[lane], u, guess[lane], &J);
      ++total;
      if (!lanes.decided[lane]) continue;
      ++decided;
      ASSERT_TRUE(converged) << n << " lane " << lane;
      const Eigen::Vector3d lane_u = lanes.u_of(lane);
      Eigen::Matrix3d lane_J;
      lanes.get_dx_du(lane, lane_J);
      ASSERT_EQ(std::memcmp(u.data(), lane_u.data(), sizeof(double) * 3), 0)
          << n << " lane " << lane << "\nQ =\n" << Q[lane] << "\nscalar " << u.transpose() << "\nlanes  "
          << lane_u.transpose();
      ASSERT_EQ(std::memcmp(J.data(), lane_J.data(), sizeof(double) * 9), 0)
          << n << " lane " << lane << "\nscalar\n" << J << "\nlanes\n" << lane_J;
    }
  }
  std::printf("[lanes] decided %zu of %zu\n", decided, total);
  EXPECT_GT(decided, total * 3 / 4);
}

TEST(CellCoordinates, SetCellsWritesWhatSetCellWritesLaneByLane) {
  // set_cells transposes four lanes' corners at once; it must be a copy, bit for bit, of
  // set_cell's lane by lane, with corners anywhere in the matrix (its last column too, which
  // a four-wide load would overrun) and lanes that share corners.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> value(-1e3, 1e3);
  for (const Eigen::Index n : {Eigen::Index{1}, Eigen::Index{9}, Eigen::Index{4913}}) {
    Eigen::Matrix3Xd positions(3, n);
    for (Eigen::Index p = 0; p < n; ++p) positions.col(p) << value(rng), value(rng), value(rng);
    for (int trial = 0; trial < 50; ++trial) {
      std::int32_t corner[TrilinearLanes::kLanes][8];
      TrilinearLanes one_by_one, all;
      for (int lane = 0; lane < TrilinearLanes::kLanes; ++lane) {
        for (int c = 0; c < 8; ++c)
          corner[lane][c] = static_cast<std::int32_t>(trial % 5 == 0 ? n - 1 : static_cast<Eigen::Index>(rng() % n));
        one_by_one.set_cell(lane, positions, corner[lane]);
      }
      all.set_cells(positions, corner);
      ASSERT_EQ(std::memcmp(one_by_one.corners, all.corners, sizeof all.corners), 0) << n << " trial " << trial;
    }
  }
}

TEST(CellCoordinates, TheDisplacementGradientBoundHoldsAnywhereInTheCell) {
  // Bent cells (cubes with corners moved by up to a third of their edge) and corner
  // displacements from small to folding; at random points, the bound is at least the
  // 2-norm of the gradient the octree's Jacobian part computes, (dD/du)(dx/du)^-1.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0), offset(-1.0 / 3, 1.0 / 3);
  std::vector<double> ratios;
  for (int n = 0; n < 20000; ++n) {
    CellCorners Q, D;
    const double size = std::ldexp(1.0, n % 7 - 3), reach = std::ldexp(size, n % 5 - 4);
    for (int c = 0; c < 8; ++c) {
      const Eigen::Vector3d corner((c & 1) ? 1.0 : 0.0, (c & 2) ? 1.0 : 0.0, (c & 4) ? 1.0 : 0.0);
      Q.col(c) = size * (corner + Eigen::Vector3d(offset(rng), offset(rng), offset(rng)));
      D.col(c) = reach * Eigen::Vector3d(offset(rng), offset(rng), offset(rng));
    }
    const Eigen::Vector3d u(unit(rng), unit(rng), unit(rng));
    double w[8];
    Eigen::Matrix<double, 8, 3> dw;
    trilinear_weights(u, w, &dw);
    const Eigen::Matrix3d dx_du = Q * dw;
    if (!(std::abs(dx_du.determinant()) > 0)) continue;
    const double gradient = (D * dw * dx_du.inverse()).jacobiSvd().singularValues()[0];
    const double bound = std::sqrt(squared_gradient_bound(D, dx_du));
    ASSERT_GE(bound, gradient) << n;
    ratios.push_back(bound / gradient);
  }
  ASSERT_GT(ratios.size(), 19000u);
  // And it is tight enough to decide: within a small factor of the gradient.
  std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
  std::printf("[bound] median bound / gradient %.2f\n", ratios[ratios.size() / 2]);
  EXPECT_LT(ratios[ratios.size() / 2], 6.0);
}

TEST(VolumeSubdivision, StencilsAreAffineCombinations) {
  const GridComplex g = make_grid_complex(4, {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {2, 1, 1}, {3, 3, 3}, {2, 2, 2}});
  const GridComplex fine = refine(g);
  Stencil s;
  for (SubdivisionRule rule : {SubdivisionRule::Octree, SubdivisionRule::CatmullClark})
    for (const GridIndex& node : fine.points) {
      subdivision_stencil(g, node, rule, s);
      double sum = 0;
      for (const auto& [p, w] : s) {
        ASSERT_GE(p, 0);
        sum += w;
      }
      EXPECT_NEAR(sum, 1.0, 1e-15);
    }
}

TEST(VolumeSubdivision, TheSparseAndOnePassSubdivisionsAreSubdivideFieldsBitForBit) {
  // The octree's moves subdivide a field that is zero but near the moved points, skipping
  // the new points that read only zeros; its small levels take the field and the matrix
  // from one pass. Both must be subdivide_field's values exactly.
  BunnyLattice b;
  OctreeLattice lattice(b.box, b.x, options(3, 1));
  const GridComplex& g = lattice.complex(3);
  const GridComplex fine = refine(g);
  Eigen::MatrixXd rest = lattice.rest_points(3), field = Eigen::MatrixXd::Zero(3, rest.cols());
  std::vector<std::uint8_t> nonzero(g.num_points(), 0);
  for (std::size_t p : {std::size_t{0}, g.num_points() / 2, g.num_points() - 1}) {
    field.col(static_cast<Eigen::Index>(p)) = Eigen::Vector3d(0.3, -0.1, 0.2);
    nonzero[p] = 1;
  }
  const auto cc = SubdivisionRule::CatmullClark;
  const Eigen::MatrixXd sparse = subdivide_sparse_field(g, fine, field, nonzero, cc);
  EXPECT_TRUE((sparse.array() == subdivide_field(g, fine, field, cc).array()).all());
  EXPECT_GT((sparse.array() != 0).count(), 0);
  Eigen::SparseMatrix<double, Eigen::RowMajor> S;
  const Eigen::MatrixXd both = subdivide_field_and_matrix(g, fine, rest, cc, S);
  EXPECT_TRUE((both.array() == subdivide_field(g, fine, rest, cc).array()).all());
  // subdivide_field sums most new points from fixed stencils (no rule branches, 3-row
  // fields in registers); the one-pass path keeps each stencil and sums it as Eigen does.
  // Both rules, a 3-row and a 4-row field, over a level with cuts (boundary rules too).
  Eigen::MatrixXd four(4, rest.cols());
  four.topRows(3) = rest;
  four.row(3) = rest.row(0).array() * rest.row(1).array() - 0.1;
  for (const auto rule : {SubdivisionRule::Octree, cc})
    for (const Eigen::MatrixXd* X : {&rest, &four}) {
      Eigen::SparseMatrix<double, Eigen::RowMajor> matrix;
      EXPECT_TRUE((subdivide_field_and_matrix(g, fine, *X, rule, matrix).array() ==
                   subdivide_field(g, fine, *X, rule).array()).all())
          << X->rows() << " rows, rule " << static_cast<int>(rule);
    }
  // The matrices merge each stencil into its row; Eigen's setFromTriplets, which sums
  // duplicates in the order given, is the reference: same entries, same bits.
  std::vector<Eigen::Triplet<double>> triplets;
  Stencil stencil;
  for (std::size_t f = 0; f < fine.num_points(); ++f) {
    subdivision_stencil(g, fine.points[f], cc, stencil);
    for (const auto& [p, w] : stencil) triplets.emplace_back(static_cast<int>(f), p, w);
  }
  Eigen::SparseMatrix<double, Eigen::RowMajor> reference(S.rows(), S.cols());
  reference.setFromTriplets(triplets.begin(), triplets.end());
  const Eigen::SparseMatrix<double, Eigen::RowMajor> listed = subdivision_matrix(g, fine.points, cc);
  using Matrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;
  for (const Matrix* M : std::array<const Matrix*, 2>{&S, &listed}) {
    ASSERT_EQ(M->nonZeros(), reference.nonZeros());
    EXPECT_TRUE(std::equal(M->outerIndexPtr(), M->outerIndexPtr() + M->rows() + 1, reference.outerIndexPtr()));
    EXPECT_TRUE(std::equal(M->innerIndexPtr(), M->innerIndexPtr() + M->nonZeros(), reference.innerIndexPtr()));
    EXPECT_TRUE(std::equal(M->valuePtr(), M->valuePtr() + M->nonZeros(), reference.valuePtr()));
  }
}

TEST(VolumeSubdivision, ARegularBoxLatticeStaysRegular) {
  // Linear precision: every rule (interior, boundary surface, sharp edges and points,
  // corners) reproduces a regular grid, so C^k of a box is the finer grid.
  const OctreeLattice lattice(unit_box(), filling_points(8), options(2, 3));
  for (int k = 0; k <= 3; ++k) {
    const GridComplex& g = lattice.subdivided(2, k);
    const Eigen::Matrix3Xd& x = lattice.subdivided_rest(2, k);
    double worst = 0;
    for (std::size_t p = 0; p < g.num_points(); ++p)
      worst = std::max(worst, (x.col(static_cast<Eigen::Index>(p)) -
                               Eigen::Vector3d(g.points[p][0], g.points[p][1], g.points[p][2]) / g.resolution)
                                  .norm());
    EXPECT_LT(worst, 1e-14) << "k = " << k;
  }
}

TEST(OctreeLattice, CutCellsHoldNoVertexAndEveryVertexLiesInACell) {
  BunnyLattice b;
  for (double shrink : {-1.0, 0.002}) {
    OctreeOptions o = options(4, 2);
    o.shrink = shrink;
    const OctreeLattice lattice(b.box, b.x, o);
    for (int l = 0; l <= 4; ++l) {
      const GridComplex& g = lattice.complex(l);
      const Eigen::Matrix3Xd& rest = lattice.rest_points(l);
      std::vector<int> holds(g.num_cells(), 0);
      std::size_t outside = 0;
      for (Eigen::Index v = 0; v < b.x.cols(); ++v) {
        // Geometrically: the vertex's coordinates in some cell of the rest lattice.
        bool found = false;
        const Eigen::Vector3d t = b.box.to_local(b.x.col(v));
        GridIndex c;
        for (int a = 0; a < 3; ++a) c[a] = std::clamp(static_cast<int>(std::floor(t[a] * g.resolution)), 0, g.resolution - 1);
        for (int dk = -1; dk <= 1 && !found; ++dk)
          for (int dj = -1; dj <= 1 && !found; ++dj)
            for (int di = -1; di <= 1 && !found; ++di) {
              const std::int32_t cell = g.cell(c[0] + di, c[1] + dj, c[2] + dk);
              if (cell < 0) continue;
              CellCorners Q;
              for (int q = 0; q < 8; ++q) Q.col(q) = rest.col(g.corner(static_cast<std::size_t>(cell), q));
              Eigen::Vector3d u;
              const bool ok = inverse_trilinear(Q, b.x.col(v), u);
              if (ok && in_unit_cube(u, 1e-9)) found = true, holds[cell] = 1;
            }
        outside += !found;
      }
      EXPECT_EQ(outside, 0u) << "level " << l << " shrink " << shrink;
      // Cut cells are not in the complex; every kept cell holds a vertex.
      EXPECT_EQ(std::count(holds.begin(), holds.end(), 0), 0) << "level " << l;
      if (l > 0) {
        EXPECT_EQ(g.num_cells() + lattice.cut_cells(l), 8 * lattice.complex(l - 1).num_cells());
      }
    }
    EXPECT_GT(lattice.cut_cells(4), 0u);
  }
}

TEST(OctreeLattice, AnUnmovedLatticeIsTheIdentity) {
  BunnyLattice b;
  for (int n = 0; n <= 3; ++n) {
    OctreeLattice lattice(b.box, b.x, options(3, n));
    // A zero move builds every subdivision and displacement; still the identity, exactly.
    move_one(lattice, 3, lattice.complex(3).points[40], Eigen::Vector3d::Zero());
    double worst = 0;
    std::size_t changed = 0;
    for (Eigen::Index v = 0; v < b.x.cols(); ++v) {
      const Eigen::Vector3d y = lattice.apply(b.x.col(v), nullptr);
      worst = std::max(worst, (y - b.x.col(v)).norm());
      changed += (y.array() != b.x.col(v).array()).any();
    }
    std::printf("[identity] cc_steps %d: max |F(x) - x| = %g over %td vertices\n", n, worst, b.x.cols());
    EXPECT_EQ(changed, 0u);
  }
}

TEST(OctreeLattice, ConvergesToTheCubicBSplineFfdAboutFourTimesPerStep) {
  // A regular 8^3 lattice: the volume rules are the tricubic B-spline subdivision masks,
  // so C^n of a moved interior point tends to the cubic B-spline FFD of the same points.
  const Parallelepiped box = unit_box();
  BSplineLattice bspline(box, {8, 8, 8}, 3);
  bspline.move_point({4, 4, 4}, bspline.point({4, 4, 4}) + Eigen::Vector3d(0.05, -0.03, 0.04));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> near(0.5 - 0.15, 0.5 + 0.15);
  std::vector<Eigen::Vector3d> samples(500);
  for (auto& s : samples) s = Eigen::Vector3d(near(rng), near(rng), near(rng));
  std::vector<double> error;
  // The region fills the central 6^3 cells: the point's image (cells 2..5) and the ring
  // its rules read (cells 1 and 6) are all interior; the outer cells are cut, which keeps
  // C^4 of the level at 216 x 4096 cells.
  Eigen::Matrix3Xd region = filling_points(8);
  std::vector<Eigen::Index> central;
  for (Eigen::Index i = 0; i < region.cols(); ++i)
    if ((region.col(i).array() > 0.125).all() && (region.col(i).array() < 0.875).all()) central.push_back(i);
  Eigen::Matrix3Xd inner(3, static_cast<Eigen::Index>(central.size()));
  for (std::size_t i = 0; i < central.size(); ++i) inner.col(static_cast<Eigen::Index>(i)) = region.col(central[i]);
  for (int n = 1; n <= 4; ++n) {
    OctreeOptions o = options(3, n);
    o.whole_level_cells = 0;  // no step matrices for C^4's 884,736 cells
    OctreeLattice lattice(box, inner, o);
    move_one(lattice, 3, {4, 4, 4}, Eigen::Vector3d(0.05, -0.03, 0.04));
    double worst = 0;
    for (const Eigen::Vector3d& s : samples)
      worst = std::max(worst, (lattice.apply(s, nullptr) - bspline.apply(s, nullptr)).norm());
    error.push_back(worst);
    std::printf("[convergence] cc_steps %d: max |C^n FFD - B-spline FFD| = %.3e%s\n", n, worst,
                n > 1 ? (" (ratio " + std::to_string(error[n - 2] / worst) + ")").c_str() : "");
  }
  for (std::size_t i = 1; i < error.size(); ++i) {
    EXPECT_GT(error[i - 1] / error[i], 3.0);
    EXPECT_LT(error[i - 1] / error[i], 5.5);
  }
}

TEST(OctreeLattice, MovingOnePointChangesOnlyVerticesInItsNeighbourhood) {
  BunnyLattice b;
  OctreeOptions o = options(4, 2);
  o.whole_level_cells = 0;  // always N_{S,4}
  OctreeLattice lattice(b.box, b.x, o);
  const GridComplex& g = lattice.complex(4);
  const GridIndex node = g.points[g.num_points() / 2];
  move_one(lattice, 4, node, Eigen::Vector3d(0.01, 0.02, -0.01));
  std::vector<std::uint32_t> marked;
  lattice.changed_points(b.x, marked);
  std::vector<char> in_marked(static_cast<std::size_t>(b.x.cols()), 0);
  for (std::uint32_t v : marked) in_marked[v] = 1;
  std::size_t moved = 0, moved_unmarked = 0, outside_ring = 0;
  for (Eigen::Index v = 0; v < b.x.cols(); ++v) {
    const Eigen::Vector3d y = lattice.apply(b.x.col(v), nullptr);
    const bool same = (y.array() == b.x.col(v).array()).all();
    moved += !same;
    moved_unmarked += !same && !in_marked[static_cast<std::size_t>(v)];
    // N_{p,3}: the cells within 2 cells of those around p.
    const Eigen::Vector3d t = b.box.to_local(b.x.col(v)) * g.resolution;
    bool near = true;
    for (int a = 0; a < 3; ++a) near = near && std::floor(t[a]) >= node[a] - 3 && std::floor(t[a]) <= node[a] + 2;
    outside_ring += !same && !near;
  }
  std::printf("[locality] %zu vertices moved, %zu marked of %td\n", moved, marked.size(), b.x.cols());
  EXPECT_GT(moved, 0u);
  EXPECT_EQ(moved_unmarked, 0u);
  EXPECT_EQ(outside_ring, 0u);
  EXPECT_LT(marked.size(), static_cast<std::size_t>(b.x.cols()) / 4);
}

// A run that needs no normals (Mesh::normals_deferred) applies the octree without them:
// the zero-normal apply's positions bit for bit and its counts, over first and later
// moves at coarse and fine levels, one of them large enough to fold the lattice.
TEST(OctreeLattice, WithoutNormalsGivesTheZeroNormalApplysPositionsAndCounts) {
  BunnyLattice b;
  OctreeLattice with(b.box, b.x, options(4, 2)), without(b.box, b.x, options(4, 2));
  std::vector<std::uint32_t> ids(static_cast<std::size_t>(b.x.cols()));
  std::iota(ids.begin(), ids.end(), 0u);
  const Eigen::Matrix3Xd zero = Eigen::Matrix3Xd::Zero(3, b.x.cols());
  std::size_t folded = 0;
  for (const auto& [level, by] : {std::pair{0, 0.01}, {2, 0.02}, {0, 0.02}, {4, 0.01}, {1, 0.9}}) {
    for (OctreeLattice* lattice : {&with, &without}) {
      const GridComplex& g = lattice->complex(level);
      move_one(*lattice, level, g.points[g.num_points() / 2], Eigen::Vector3d(by, -by, by / 2) * b.box.axes().colwise().norm().maxCoeff());
    }
    Eigen::Matrix3Xd p_with(3, b.x.cols()), n_with(3, b.x.cols());
    Eigen::Matrix3Xd p_without = Eigen::Matrix3Xd::Constant(3, b.x.cols(), 7.0);
    WarpCounts counts_with, counts_without;
    with.apply(b.x, zero, ids, p_with, n_with, counts_with);
    ASSERT_TRUE(without.apply_without_normals(b.x, ids, p_without, counts_without));
    EXPECT_TRUE((p_with.array() == p_without.array()).all()) << level;
    EXPECT_TRUE(n_with.isZero(0.0));
    EXPECT_EQ(counts_with.folded, counts_without.folded) << level;
    EXPECT_EQ(counts_with.evaluated, counts_without.evaluated) << level;
    folded += counts_with.folded;
  }
  EXPECT_GT(folded, 0u);  // the large move folded some cells: the counts compared are not all zero
}

TEST(OctreeLattice, AppliesWithAndWithoutNormalsShareTheirTags) {
  // One lattice applied with normals after some moves and without after others (its tags
  // then hold a Jacobian part or only its bound) gives what a lattice always applied with
  // normals gives, positions, normals and counts, at every step.
  BunnyLattice b;
  OctreeLattice mixed(b.box, b.x, options(4, 2)), with(b.box, b.x, options(4, 2));
  std::vector<std::uint32_t> ids(static_cast<std::size_t>(b.x.cols()));
  std::iota(ids.begin(), ids.end(), 0u);
  const Eigen::Matrix3Xd normals = b.mesh.rest_normals();
  const double size = b.box.axes().colwise().norm().maxCoeff();
  int step = 0;
  std::size_t folded = 0;
  for (const auto& [level, by] : {std::pair{0, 0.01}, {1, 0.3}, {2, 0.02}, {0, 0.02}, {4, 0.01}, {1, 0.02}, {2, 0.5}}) {
    for (OctreeLattice* lattice : {&mixed, &with}) {
      const GridComplex& g = lattice->complex(level);
      move_one(*lattice, level, g.points[g.num_points() / 3], Eigen::Vector3d(by, -by, by / 2) * size);
    }
    Eigen::Matrix3Xd p_with(3, b.x.cols()), n_with(3, b.x.cols()), p_mixed(3, b.x.cols()), n_mixed(3, b.x.cols());
    WarpCounts counts_with, counts_mixed;
    with.apply(b.x, normals, ids, p_with, n_with, counts_with);
    if (step % 3 == 1) {
      mixed.apply(b.x, normals, ids, p_mixed, n_mixed, counts_mixed);
      EXPECT_TRUE((n_with.array() == n_mixed.array()).all()) << step;
    } else {
      ASSERT_TRUE(mixed.apply_without_normals(b.x, ids, p_mixed, counts_mixed));
    }
    EXPECT_TRUE((p_with.array() == p_mixed.array()).all()) << step;
    EXPECT_EQ(counts_with.folded, counts_mixed.folded) << step;
    EXPECT_EQ(counts_with.evaluated, counts_mixed.evaluated) << step;
    folded += counts_with.folded;
    ++step;
  }
  EXPECT_GT(folded, 0u);  // the large moves fold: the bounds could not decide every vertex
}

TEST(OctreeLattice, TheBatchApplyLocatesAsThePointApplyBitForBit) {
  // The batch apply locates a level's new tags four at a time (TrilinearLanes), walking
  // from cell to cell where a vertex lies outside the cell of its grid position; the point
  // apply locates one vertex at a time with the scalar inverse_trilinear. After a first
  // move at every level, on lattices with cut cells, shrunk or not, both give every vertex
  // the same bits, and the batch's counts are the points'. Some walks reach cells whose rest
  // lattice no move subdivided: the batch parks those vertices, subdivides their cells
  // together and applies them last (checked to happen, before the point apply).
  BunnyLattice b;
  std::vector<std::uint32_t> ids(static_cast<std::size_t>(b.x.cols()));
  std::iota(ids.begin(), ids.end(), 0u);
  const double size = b.box.axes().colwise().norm().maxCoeff();
  int walked_on = 0;  // level moves whose batch apply subdivided cells beyond the move's
  for (const double shrink : {-1.0, 0.002}) {
    OctreeOptions o = options(4, 2);
    o.shrink = shrink;
    OctreeLattice lattice(b.box, b.x, o);
    for (int level = 0; level <= 4; ++level) {
      const GridComplex& g = lattice.complex(level);
      move_one(lattice, level, g.points[g.num_points() / 2], Eigen::Vector3d(0.02, -0.02, 0.01) * size);
      Eigen::Matrix3Xd p(3, b.x.cols());
      WarpCounts counts;
      const std::size_t ready = lattice.rest_cells_subdivided(level);
      ASSERT_TRUE(lattice.apply_without_normals(b.x, ids, p, counts));
      walked_on += lattice.rest_cells_subdivided(level) > ready;
      std::size_t differ = 0, folded = 0;
      for (Eigen::Index v = 0; v < b.x.cols(); ++v) {
        Eigen::Matrix3d J;
        differ += (lattice.apply(b.x.col(v), &J).array() != p.col(v).array()).any();
        folded += J.determinant() <= 0;
      }
      EXPECT_EQ(differ, 0u) << "shrink " << shrink << ", level " << level;
      EXPECT_EQ(counts.folded, folded) << "shrink " << shrink << ", level " << level;
    }
    EXPECT_GT(lattice.vertices_located(), 4u * static_cast<std::size_t>(b.x.cols()));
  }
  EXPECT_GT(walked_on, 0) << "no walk reached a cell the moves left unsubdivided";
}

TEST(OctreeLattice, LocalSubdivisionAgreesWithSubdividingTheWholeLevel) {
  // A move re-subdivides N_{S,3} only; the result is the whole level's subdivision (to
  // rounding: the whole level multiplies by merged stencils) for every n (the moves' image
  // lies in N_{S,2}; one more ring holds the rules' neighbours). Checked at the vertices and
  // at points all over the box.
  BunnyLattice b;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  Eigen::Matrix3Xd samples(3, b.x.cols() + 1500);
  samples.leftCols(b.x.cols()) = b.x;
  for (Eigen::Index i = b.x.cols(); i < samples.cols(); ++i)
    samples.col(i) = b.box.to_world(Eigen::Vector3d(u01(rng), u01(rng), u01(rng)));
  for (int n = 1; n <= 3; ++n) {
    OctreeOptions local = options(4, n), whole = options(4, n);
    local.whole_level_cells = 0;
    whole.whole_level_cells = 1u << 30;
    OctreeLattice a(b.box, b.x, local), c(b.box, b.x, whole);
    const GridComplex& g = a.complex(4);
    for (std::size_t p : {std::size_t{0}, g.num_points() / 3, g.num_points() / 2, g.num_points() / 2 + 7}) {
      move_one(a, 4, g.points[p], Eigen::Vector3d(0.01, 0.0, 0.015));
      move_one(c, 4, g.points[p], Eigen::Vector3d(0.01, 0.0, 0.015));
    }
    double worst = 0;
    for (Eigen::Index v = 0; v < samples.cols(); ++v)
      worst = std::max(worst, (a.apply(samples.col(v), nullptr) - c.apply(samples.col(v), nullptr)).norm());
    std::printf("[local vs whole] cc_steps %d: max difference %g\n", n, worst);
    EXPECT_LT(worst, 1e-15) << "cc_steps " << n;
  }
}

TEST(OctreeLattice, ASmallLevelsMovesAreTheWholeStepMatricesProducts) {
  // A small level multiplies again only the rows of its step matrices that read a changed
  // value, building each row the first time a move reaches it. After moves of scattered
  // points, one point twice and several at once, every C^k(delta) is still the whole
  // matrices' product S_k ... S_1 delta (to rounding: the product here is this file's).
  BunnyLattice b;
  OctreeOptions o = options(3, 2);
  o.whole_level_cells = 1u << 30;
  OctreeLattice lattice(b.box, b.x, o);
  const int l = 3;
  const GridComplex& g = lattice.complex(l);
  const std::size_t n = g.num_points();
  move_one(lattice, l, g.points[n / 4], Eigen::Vector3d(0.01, 0.0, 0.015));
  move_one(lattice, l, g.points[3 * n / 4], Eigen::Vector3d(-0.02, 0.01, 0.0));
  move_one(lattice, l, g.points[n / 4], Eigen::Vector3d(0.0, -0.005, 0.01));
  const Eigen::Matrix3Xd shown = lattice.points(l);
  std::vector<std::int32_t> ids;
  std::vector<Eigen::Vector3d> targets;
  for (std::size_t p = n / 2; p < n / 2 + 5; ++p)
    ids.push_back(static_cast<std::int32_t>(p)), targets.push_back(shown.col(static_cast<Eigen::Index>(p)) + Eigen::Vector3d(0.003, 0.004, -0.002));
  lattice.move_level_points(l, ids, targets);
  Eigen::MatrixXd expected = lattice.points(l) - lattice.rest_points(l);  // only this level moved
  for (int k = 1; k <= 2; ++k) {
    const Eigen::SparseMatrix<double, Eigen::RowMajor> S =
        subdivision_matrix(lattice.subdivided(l, k - 1), lattice.subdivided(l, k).points, SubdivisionRule::CatmullClark);
    expected = (S * expected.transpose()).transpose();
    const Eigen::Matrix3Xd moves = lattice.subdivided_moves(l, k);
    ASSERT_EQ(moves.cols(), expected.cols());
    EXPECT_GT(moves.cwiseAbs().maxCoeff(), 0.01) << "C^" << k;
    EXPECT_LE((moves - expected).cwiseAbs().maxCoeff(), 1e-16) << "C^" << k;
  }
}

/// Moves two points of `level` in a lattice that subdivides its rest lattice on demand and
/// in one whose rest lattice is subdivided whole first: both deform the bunny alike, bit
/// for bit. `small`: the level moves by its steps' matrices (whole_level_cells), else by
/// N_{S,3}.
void expect_on_demand_rest_is_whole(int level, int cc_steps, bool small = false) {
  SCOPED_TRACE("level " + std::to_string(level) + ", cc_steps " + std::to_string(cc_steps) + (small ? ", small" : ""));
  BunnyLattice b;
  OctreeOptions o = options(level, cc_steps);
  o.whole_level_cells = small ? std::size_t{1} << 20 : 0;
  OctreeLattice lazy(b.box, b.x, o), whole(b.box, b.x, o);
  for (int k = 1; k <= cc_steps; ++k) whole.subdivided_rest(level, k);  // every cell, in one go
  const GridComplex& g = lazy.complex(level);
  for (std::size_t p : {g.num_points() / 3, g.num_points() / 2}) {
    move_one(lazy, level, g.points[p], Eigen::Vector3d(0.01, 0.0, 0.015));
    move_one(whole, level, g.points[p], Eigen::Vector3d(0.01, 0.0, 0.015));
  }
  EXPECT_LT(lazy.rest_cells_subdivided(level), g.num_cells() / 2);
  EXPECT_EQ(whole.rest_cells_subdivided(level), g.num_cells());
  std::vector<std::uint32_t> ids;
  lazy.changed_points(b.x, ids);
  Eigen::Matrix3Xd nrm = b.mesh.normals(), pa = b.x, pb = b.x, na = nrm, nb = nrm;
  WarpCounts counts;
  lazy.apply(b.x, nrm, ids, pa, na, counts);
  whole.apply(b.x, nrm, ids, pb, nb, counts);
  EXPECT_TRUE((pa.array() == pb.array()).all());
  EXPECT_TRUE((na.array() == nb.array()).all());
  for (Eigen::Index v = 0; v < b.x.cols(); v += 7) {
    Eigen::Matrix3d Ja, Jb;
    EXPECT_TRUE((lazy.apply(b.x.col(v), &Ja).array() == whole.apply(b.x.col(v), &Jb).array()).all());
    EXPECT_TRUE((Ja.array() == Jb.array()).all());
  }
  // Every point the moves subdivided keeps its value when the rest of the level is filled.
  for (int k = 1; k <= cc_steps; ++k)
    EXPECT_TRUE((lazy.subdivided_rest(level, k).array() == whole.subdivided_rest(level, k).array()).all()) << "C^" << k;
}

TEST(OctreeLattice, TheRestLatticeSubdividedOnDemandIsTheWholeLevelsBitForBit) {
  // A level subdivides its rest lattice only in the cells a move marks (and where a
  // location walks to), each Catmull-Clark step over as much of C^k as the next one reads
  // there; the positions there are the whole level's subdivision exactly, so the
  // deformation is too, for a level that moves by its steps' matrices as for one that
  // moves by N_{S,3}. Three steps check the margins' recursion as well as two.
  expect_on_demand_rest_is_whole(4, 2);
  expect_on_demand_rest_is_whole(3, 3);
  expect_on_demand_rest_is_whole(4, 2, true);
}

TEST(OctreeLattice, AFirstMoveAtTheFinestLevelLocatesFewVertices) {
  // Ono et al. section 3.2: a move touches N_{S,3}. The first move of one point at level 5
  // subdivides and locates only there, not the whole level and every vertex.
  BunnyLattice b;
  OctreeLattice lattice(b.box, b.x, options(5, 2));
  const GridComplex& g = lattice.complex(5);
  move_one(lattice, 5, g.points[g.num_points() / 2], Eigen::Vector3d(0.01, 0.02, 0.0));
  std::vector<std::uint32_t> ids;
  lattice.changed_points(b.x, ids);
  Eigen::Matrix3Xd nrm = b.mesh.normals(), pos = b.x, out_nrm = nrm;
  WarpCounts counts;
  lattice.apply(b.x, nrm, ids, pos, out_nrm, counts);
  std::printf("[first move, level 5] %zu of %td vertices located, %zu of %zu cells subdivided\n",
              lattice.vertices_located(), b.x.cols(), lattice.rest_cells_subdivided(5), g.num_cells());
  EXPECT_GT(lattice.vertices_located(), 0u);
  EXPECT_LT(lattice.vertices_located(), static_cast<std::size_t>(b.x.cols()) / 10);
  EXPECT_LT(lattice.rest_cells_subdivided(5), g.num_cells() / 10);
}

TEST(OctreeLattice, JacobianMatchesFiniteDifferences) {
  BunnyLattice b;
  OctreeLattice lattice(b.box, b.x, options(2, 2));
  const GridComplex& g = lattice.complex(2);
  for (std::size_t p = 0; p < g.num_points(); p += 3)
    move_one(lattice, 2, g.points[p], Eigen::Vector3d(0.01 * std::sin(p), 0.01 * std::cos(p), 0.005));
  double worst = 0;
  const double h = 1e-6;
  for (Eigen::Index v = 0; v < b.x.cols(); v += 97) {
    const Eigen::Vector3d x = b.x.col(v);
    Eigen::Matrix3d J;
    lattice.apply(x, &J);
    Eigen::Matrix3d fd;
    for (int a = 0; a < 3; ++a) {
      const Eigen::Vector3d e = Eigen::Vector3d::Unit(a) * h;
      fd.col(a) = (lattice.apply(x + e, nullptr) - lattice.apply(x - e, nullptr)) / (2 * h);
    }
    worst = std::max(worst, (J - fd).norm());
  }
  EXPECT_LT(worst, 1e-5);
}

TEST(OctreeLattice, TheDeformationIsContinuousAcrossCellFaces) {
  BunnyLattice b;
  OctreeLattice lattice(b.box, b.x, options(3, 2));
  const GridComplex& g = lattice.complex(3);
  for (std::size_t p = 0; p < g.num_points(); p += 5)
    move_one(lattice, 3, g.points[p], Eigen::Vector3d(0.02, -0.01, 0.01));
  // Pairs of points 2e-9 apart across the faces between fine cells inside the lattice.
  const GridComplex& fine = lattice.subdivided(3, 2);
  double worst = 0;
  const int res = fine.resolution;
  for (std::size_t c = 0; c < fine.num_cells(); c += 11) {
    const GridIndex& cell = fine.cells[c];
    if (!fine.has_cell(cell[0] + 1, cell[1], cell[2])) continue;
    const Eigen::Vector3d t = (Eigen::Vector3d(cell[0] + 1, cell[1] + 0.37, cell[2] + 0.61)) / res;
    const Eigen::Vector3d x = b.box.to_world(t);
    const Eigen::Vector3d e = b.box.axes().col(0) * 1e-9;
    worst = std::max(worst, (lattice.apply(x + e, nullptr) - lattice.apply(x - e, nullptr)).norm());
  }
  EXPECT_LT(worst, 1e-7);
}

TEST(OctreeLattice, ChangingLevelDoesNotMoveTheModel) {
  BunnyLattice b;
  OctreeLattice lattice(b.box, b.x, options(3, 2));
  const GridComplex& g1 = lattice.complex(1);
  move_one(lattice, 1, g1.points[g1.num_points() / 2], Eigen::Vector3d(0.0, 0.05, 0.02));
  std::vector<Eigen::Vector3d> before;
  for (Eigen::Index v = 0; v < b.x.cols(); ++v) before.push_back(lattice.apply(b.x.col(v), nullptr));
  // Level 2 now shows the octree subdivision of the moved level 1.
  const Eigen::Matrix3Xd shown = lattice.points(2);
  EXPECT_GT((shown - lattice.rest_points(2)).cwiseAbs().maxCoeff(), 1e-3);
  // Taking level 2 up (a zero move of a point) leaves the model where it was.
  move_one(lattice, 2, lattice.complex(2).points[5], Eigen::Vector3d::Zero());
  double worst = 0;
  for (Eigen::Index v = 0; v < b.x.cols(); ++v)
    worst = std::max(worst, (lattice.apply(b.x.col(v), nullptr) - before[static_cast<std::size_t>(v)]).norm());
  EXPECT_LT(worst, 1e-9);
  // Moving level 2 adds its own field: a point of level 2 moves the model near it.
  const std::int32_t id = lattice.point_index(2, lattice.complex(2).points[lattice.complex(2).num_points() / 2]);
  lattice.move_level_points(2, {id}, {Eigen::Vector3d(lattice.points(2).col(id) + Eigen::Vector3d(0.03, 0, 0))});
  EXPECT_NEAR((lattice.points(2).col(id) - shown.col(id)).norm(), 0.03, 1e-12);
}

TEST(OctreeLattice, PointWeightsPredictTheDeformation) {
  BunnyLattice b;
  OctreeLattice lattice(b.box, b.x, options(2, 2));
  std::vector<std::pair<std::int32_t, double>> w;
  const Eigen::Vector3d x = b.x.col(1234);
  lattice.point_weights(2, x, w);
  ASSERT_FALSE(w.empty());
  double sum = 0;
  Eigen::Vector3d predicted = x;
  const Eigen::Vector3d d(0.01, -0.02, 0.03);
  for (const auto& [p, wp] : w) sum += wp;
  EXPECT_NEAR(sum, 1.0, 1e-12);
  // Move every weighted point by d: F(x) moves by d (partition of unity).
  std::vector<std::int32_t> ids;
  std::vector<Eigen::Vector3d> targets;
  const Eigen::Matrix3Xd shown = lattice.points(2);
  for (const auto& [p, wp] : w) ids.push_back(p), targets.push_back(shown.col(p) + d * (p % 3));
  for (const auto& [p, wp] : w) predicted += wp * d * (p % 3);
  lattice.move_level_points(2, ids, targets);
  EXPECT_LT((lattice.apply(x, nullptr) - predicted).norm(), 1e-12);
}

TEST(OctreeLattice, ALargeLevelsPointWeightsAreASmallLevelsBitForBit) {
  // A large level reads its C^k through StepGrid (slots, stencils over the implied
  // topology); a small one through built complexes. Same weights, same order, same bits.
  BunnyLattice b;
  OctreeOptions large = options(4, 2), small = options(4, 2);
  large.whole_level_cells = 0;
  small.whole_level_cells = 1u << 30;
  const OctreeLattice a(b.box, b.x, large), c(b.box, b.x, small);
  std::vector<std::pair<std::int32_t, double>> wa, wc;
  std::size_t weighted = 0;
  for (Eigen::Index v = 0; v < b.x.cols(); v += 97) {
    a.point_weights(4, b.x.col(v), wa);
    c.point_weights(4, b.x.col(v), wc);
    ASSERT_EQ(wa, wc) << "vertex " << v;
    weighted += !wa.empty();
  }
  EXPECT_GT(weighted, static_cast<std::size_t>(b.x.cols() / 97) * 9 / 10);
}

TEST(StepGrid, ImpliesTheRefinedComplexWithOneSlotPerPoint) {
  // C^k of a cut, concave level (the bunny's level 3) as StepGrid reads it, against
  // refine() applied k times: the same cells, every point one slot and back, distinct
  // slots, the same corners, and the same stencils (as nodes and weights).
  BunnyLattice b;
  const OctreeLattice lattice(b.box, b.x, options(3, 2));
  const GridComplex& level = lattice.complex(3);
  GridComplex built = level;
  for (int k = 1; k <= 2; ++k) {
    const GridComplex coarse = built;
    built = refine(built);
    const StepGrid implied{&level, nullptr, k}, coarse_implied{&level, nullptr, k - 1};
    ASSERT_EQ(implied.resolution(), built.resolution);
    std::vector<std::int32_t> slots;
    for (const GridIndex& n : built.points) {
      const std::int32_t p = implied.point(n);
      ASSERT_GE(p, 0);
      ASSERT_LT(static_cast<std::size_t>(p), implied.num_points());
      EXPECT_EQ(implied.node(p), n);
      slots.push_back(p);
    }
    std::sort(slots.begin(), slots.end());
    EXPECT_EQ(std::adjacent_find(slots.begin(), slots.end()), slots.end()) << "two points share a slot";
    const int res = built.resolution;
    std::size_t cells = 0;
    for (int z = -1; z <= res; ++z)
      for (int y = -1; y <= res; ++y)
        for (int x = -1; x <= res; ++x) {
          const std::int32_t cell = implied.cell(x, y, z);
          ASSERT_EQ(cell >= 0, built.has_cell(x, y, z)) << x << " " << y << " " << z;
          if (cell < 0) continue;
          ++cells;
          const auto built_cell = static_cast<std::size_t>(built.cell(x, y, z));
          std::int32_t implied_corners[8], built_corners[8];  // all eight at once, as the apply reads them
          implied.corners(cell, implied_corners);
          built.corners(built_cell, built_corners);
          for (int c = 0; c < 8; ++c) {
            EXPECT_EQ(implied.node(implied.corner(cell, c)), built.points[static_cast<std::size_t>(built.corner(built_cell, c))]);
            EXPECT_EQ(implied_corners[c], implied.corner(cell, c));
            EXPECT_EQ(built_corners[c], built.corner(built_cell, c));
          }
        }
    EXPECT_EQ(cells, built.num_cells());
    Stencil from_built, from_implied;
    const StepGrid coarse_grid = k == 1 ? StepGrid{&level, &level, 0} : coarse_implied;
    for (std::size_t p = 0; p < built.num_points(); p += 7) {
      subdivision_stencil(coarse, built.points[p], SubdivisionRule::CatmullClark, from_built);
      subdivision_stencil(coarse_grid, built.points[p], SubdivisionRule::CatmullClark, from_implied);
      ASSERT_EQ(from_built.size(), from_implied.size());
      for (std::size_t i = 0; i < from_built.size(); ++i) {
        EXPECT_EQ(coarse.points[static_cast<std::size_t>(from_built[i].first)], coarse_grid.node(from_implied[i].first));
        EXPECT_EQ(from_built[i].second, from_implied[i].second);
      }
    }
  }
}

}  // namespace
}  // namespace ffd

namespace ffd {
namespace {

/// The positions of C^k as a sorted list, rounded to 1e-9, to compare point sets.
std::vector<std::array<long long, 3>> rounded(const Eigen::Matrix3Xd& x) {
  std::vector<std::array<long long, 3>> out;
  for (Eigen::Index p = 0; p < x.cols(); ++p)
    out.push_back({std::llround(x(0, p) * 1e9), std::llround(x(1, p) * 1e9), std::llround(x(2, p) * 1e9)});
  std::sort(out.begin(), out.end());
  return out;
}

TEST(CellComplex, TheGeneralRulesAgreeWithTheGridRulesOnACutLattice) {
  // The bunny's level-3 lattice (cut cells, concave and non-manifold boundary), as a
  // general complex with nothing subdivided: two Catmull-Clark steps by the general code
  // give the same points as the grid code.
  BunnyLattice b;
  const OctreeLattice lattice(b.box, b.x, options(3, 2));
  std::vector<GridIndex> nodes;
  CellComplex k = locally_subdivided(lattice.complex(3), std::vector<std::uint8_t>(lattice.complex(3).num_cells(), 0), nodes);
  EXPECT_EQ(k.num_cells(), lattice.complex(3).num_cells());
  EXPECT_EQ(lattice_defect(k), "");
  Eigen::Matrix3Xd x = lattice.rest_points(3);
  for (int step = 1; step <= 2; ++step) {
    Eigen::SparseMatrix<double, Eigen::RowMajor> S;
    k = catmull_clark_step(k, S);
    x = (S * x.transpose()).transpose();
    EXPECT_EQ(lattice_defect(k), "") << "step " << step;
    EXPECT_EQ(k.num_cells(), lattice.subdivided(3, step).num_cells());
  }
  EXPECT_EQ(rounded(x), rounded(lattice.subdivided_rest(3, 2)));
}

TEST(CellComplex, LocalSubdivisionKeepsTheLatticeValid) {
  const OctreeLattice lattice(unit_box(), filling_points(4), options(2, 2));
  const GridComplex& g = lattice.complex(2);
  std::vector<std::uint8_t> flags(g.num_cells(), 0);
  flags[static_cast<std::size_t>(g.cell(1, 1, 1))] = flags[static_cast<std::size_t>(g.cell(2, 1, 1))] = 1;
  flags[static_cast<std::size_t>(g.cell(0, 3, 3))] = 1;  // a corner cell too
  std::vector<GridIndex> nodes;
  CellComplex k = locally_subdivided(g, flags, nodes);
  EXPECT_EQ(k.num_cells(), g.num_cells() - 3 + 24);
  for (int step = 0; step <= 2; ++step) {
    EXPECT_EQ(lattice_defect(k), "") << "step " << step;
    // A solid ball: V - E + F - C = 1.
    const long long euler = k.num_points - static_cast<long long>(k.edges.size()) + static_cast<long long>(k.num_faces()) -
                            static_cast<long long>(k.num_cells());
    EXPECT_EQ(euler, 1) << "step " << step;
    Eigen::SparseMatrix<double, Eigen::RowMajor> S;
    if (step < 2) k = catmull_clark_step(k, S);
  }
  // Extraordinary points: cells that are not hexahedra (other than 6 faces) appear.
  std::size_t other = 0;
  for (std::size_t c = 0; c < k.num_cells(); ++c) other += k.cell_offsets[c + 1] - k.cell_offsets[c] != 6;
  EXPECT_GT(other, 0u);
}

TEST(CellComplex, ALocallySubdividedLevelIsTheIdentityUntilMovedAndContinuousAfter) {
  const OctreeLattice base(unit_box(), filling_points(8), options(2, 2));
  OctreeLattice lattice(unit_box(), filling_points(8), options(2, 2));
  const GridComplex& g = lattice.complex(2);
  const int l = lattice.subdivide(2, {g.cell(1, 1, 1), g.cell(2, 1, 1)});
  EXPECT_EQ(l, 3);
  EXPECT_EQ(lattice.resolution(l), 8);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  // Taking the new level up moves nothing, bit for bit.
  move_one(lattice, l, {4, 4, 4}, Eigen::Vector3d::Zero());
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector3d x(u01(rng), u01(rng), u01(rng));
    EXPECT_TRUE((lattice.apply(x, nullptr).array() == x.array()).all());
  }
  // Move a point on the face between the subdivided cells and their neighbours.
  move_one(lattice, l, {4, 3, 3}, Eigen::Vector3d(0.03, 0.02, -0.01));
  move_one(lattice, l, {3, 3, 4}, Eigen::Vector3d(-0.01, 0.02, 0.02));
  double jump = 0, moved = 0;
  for (int i = 0; i < 400; ++i) {  // across the planes x = 0.25 and x = 0.75, y = 0.25, z = 0.5
    const int axis = i % 3;
    Eigen::Vector3d x(0.2 + 0.6 * u01(rng), 0.15 + 0.4 * u01(rng), 0.2 + 0.6 * u01(rng));
    x[axis] = axis == 0 ? (i % 2 ? 0.25 : 0.75) : axis == 1 ? 0.25 : 0.5;
    const Eigen::Vector3d e = Eigen::Vector3d::Unit(axis) * 1e-10;
    jump = std::max(jump, (lattice.apply(x + e, nullptr) - lattice.apply(x - e, nullptr)).norm());
    moved = std::max(moved, (lattice.apply(x, nullptr) - x).norm());
  }
  EXPECT_GT(moved, 1e-3);
  EXPECT_LT(jump, 1e-8);
  // Jacobian against finite differences.
  for (int i = 0; i < 50; ++i) {
    const Eigen::Vector3d x(0.2 + 0.4 * u01(rng), 0.2 + 0.4 * u01(rng), 0.3 + 0.4 * u01(rng));
    Eigen::Matrix3d J, fd;
    lattice.apply(x, &J);
    for (int a = 0; a < 3; ++a) {
      const Eigen::Vector3d h = Eigen::Vector3d::Unit(a) * 1e-7;
      fd.col(a) = (lattice.apply(x + h, nullptr) - lattice.apply(x - h, nullptr)) / 2e-7;
    }
    EXPECT_LT((J - fd).norm(), 1e-5);
  }
  // The grid levels still deform as they did: level 2 of both lattices agree.
  EXPECT_TRUE((lattice.points(2).array() == base.points(2).array()).all());
}

TEST(CellComplex, ASubdividedLevelsRestTetrahedraTileTheBox) {
  // No self-intersection at rest: the tetrahedra of every cell of C^k fill the box once.
  OctreeLattice lattice(unit_box(), filling_points(4), options(1, 2));
  const int l = lattice.subdivide(1, {lattice.complex(1).cell(0, 0, 0)});
  const CellComplex& k = lattice.local(l).complex();
  const Eigen::Matrix3Xd& x = lattice.local(l).rest();
  double volume = 0;
  for (std::size_t c = 0; c < k.num_cells(); ++c) {
    const auto pts = k.cell_points(c);
    Eigen::Vector3d C = Eigen::Vector3d::Zero();
    for (auto p : pts) C += x.col(p);
    C /= static_cast<double>(pts.size());
    for (std::int32_t s = k.cell_offsets[c]; s < k.cell_offsets[c + 1]; ++s) {
      const std::int32_t f = k.cell_faces[static_cast<std::size_t>(s)];
      const std::int32_t o = k.face_offsets[f], n = k.face_offsets[f + 1] - o;
      Eigen::Vector3d F = Eigen::Vector3d::Zero();
      for (std::int32_t j = o; j < o + n; ++j) F += x.col(k.face_points[static_cast<std::size_t>(j)]);
      F /= n;
      for (std::int32_t j = 0; j < n; ++j) {
        Eigen::Matrix3d M;
        M << F - C, x.col(k.face_points[static_cast<std::size_t>(o + j)]) - C,
            x.col(k.face_points[static_cast<std::size_t>(o + (j + 1) % n)]) - C;
        volume += std::abs(M.determinant()) / 6;
      }
    }
  }
  EXPECT_NEAR(volume, 1.0, 1e-12);
}

}  // namespace
}  // namespace ffd

namespace ffd {
namespace {

TEST(OctreeLattice, TheObbAxesAreTheCovarianceEigenvectors) {
  // The octree's level 0 with fit "obb": independently, the eigenvectors of the bunny's
  // vertex covariance; each box axis is parallel to one of them.
  BunnyLattice b;
  const Eigen::Vector3d mean = b.x.rowwise().mean();
  const Eigen::Matrix3Xd centred = b.x.colwise() - mean;
  const Eigen::Matrix3d covariance = centred * centred.transpose() / static_cast<double>(b.x.cols());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
  ASSERT_GT(eigen.eigenvalues()[1] - eigen.eigenvalues()[0], 1e-6 * eigen.eigenvalues()[2]);  // distinct
  for (int a = 0; a < 3; ++a) {
    const Eigen::Vector3d axis = b.box.axes().col(a).normalized();
    double best = 0;
    for (int e = 0; e < 3; ++e) best = std::max(best, std::abs(axis.dot(eigen.eigenvectors().col(e))));
    EXPECT_NEAR(best, 1.0, 1e-9) << "axis " << a;
  }
}

TEST(OctreeLattice, ComposesInTheWarpStackWithABSplineLattice) {
  // A B-spline lattice, then an octree lattice around its output; the mesh is the octree
  // applied to the B-spline's output, vertex by vertex, and normals follow both Jacobians.
  Mesh mesh = test::bunny();
  const Eigen::Matrix3Xd rest = mesh.positions();
  WarpStack stack;
  auto bspline = std::make_unique<BSplineLattice>(fit_aabb(rest, {}, 0.05), Index3{6, 6, 6}, 3);
  BSplineLattice* first = bspline.get();
  stack.push(mesh, "body", std::move(bspline));
  first->move_point({3, 3, 3}, first->point({3, 3, 3}) + Eigen::Vector3d(0.01, 0.02, 0));
  stack.update(mesh, "body");
  const Eigen::Matrix3Xd between = mesh.positions();
  auto octree = std::make_unique<OctreeLattice>(fit_principal_box(between, {}, 0.05), between, options(3, 2));
  OctreeLattice* second = octree.get();
  stack.push(mesh, "auto", std::move(octree));
  move_one(*second, 2, second->complex(2).points[second->complex(2).num_points() / 2], Eigen::Vector3d(0, 0.02, 0.01));
  stack.update(mesh, "auto");
  std::size_t differ = 0;
  for (Eigen::Index v = 0; v < rest.cols(); ++v) {
    const Eigen::Vector3d expected = second->apply(first->apply(rest.col(v), nullptr), nullptr);
    differ += (mesh.positions().col(v) - expected).norm() > 1e-12;
  }
  EXPECT_EQ(differ, 0u);
  // Moving the B-spline lattice again re-evaluates through the octree above it.
  first->move_point({3, 3, 3}, first->point({3, 3, 3}) + Eigen::Vector3d(0, -0.02, 0));
  stack.update(mesh, "body");
  for (Eigen::Index v = 0; v < rest.cols(); v += 7)
    EXPECT_LT((mesh.positions().col(v) - second->apply(first->apply(rest.col(v), nullptr), nullptr)).norm(), 1e-12);
}

}  // namespace
}  // namespace ffd
