// Boundary-constraint modeling on plane grids, where the cotangent Laplacian is the
// 5-point stencil and the answers are known: the membrane is harmonic, every k reproduces
// a linear height field, C^(k−1) clamps and C^0 hinges the boundary with intermediate c
// in between, anisotropic bending evens out the boundary slope of an elongated support,
// detail survives an edit, and an unmoved handle holds like fixed surface (Figure 4).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "bcm/bcm_editor.h"
#include "bcm_test_util.h"
#include "mesh/vertex_normals.h"
#include "test_meshes.h"

namespace ffd {
namespace {

constexpr int kN = 40;  // grid cells per side; vertex (i, j) is j·(kN+1) + i
std::uint32_t id(int i, int j) { return static_cast<std::uint32_t>(j * (kN + 1) + i); }

bool in_disk(const Eigen::Vector3d& p, double x, double y, double r) { return std::hypot(p.x() - x, p.y() - y) <= r; }

Eigen::Matrix3Xd edit(const Mesh& mesh, const std::vector<std::uint32_t>& support, const std::vector<BcmHandle>& handles,
                      const BcmOptions& options, const test::Pose& pose) {
  BcmData editor = bcm_precompute(mesh, support, handles, options);
  bcm_set_pose(editor, 0, pose.linear, pose.translation);
  Eigen::Matrix3Xd positions = mesh.positions();
  bcm_pose(editor, positions);
  EXPECT_TRUE(positions.allFinite());
  return positions;
}

test::Pose lift(double dz) {
  test::Pose pose;
  pose.translation = Eigen::Vector3d(0, 0, dz);
  return pose;
}

BcmOptions options(int k, double outer = -1, double inner = -1, LaplacianKind laplacian = LaplacianKind::Cotan) {
  BcmOptions o;
  o.k = k;
  o.outer_continuity = outer;
  o.inner_continuity = inner;
  o.laplacian = laplacian;
  o.detail = false;
  return o;
}

TEST(BcmPlane, MembraneIsHarmonic) {
  const Mesh grid = test::grid_mesh(kN);
  const auto support = test::pick(grid, [](const Eigen::Vector3d& p) { return in_disk(p, 0.5, 0.5, 0.4); });
  const std::vector<BcmHandle> handles = {{"h", test::pick(grid, [](const Eigen::Vector3d& p) { return in_disk(p, 0.55, 0.5, 0.08); })}};
  test::Pose pose = lift(0.2);
  pose.linear = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  pose.translation += Eigen::Vector3d(0.55, 0.5, 0) - pose.linear * Eigen::Vector3d(0.55, 0.5, 0);
  BcmData editor = bcm_precompute(grid, support, handles, options(1));
  bcm_set_pose(editor, 0, pose.linear, pose.translation);
  Eigen::Matrix3Xd p = grid.positions();
  bcm_pose(editor, p);
  double moved = 0;
  for (std::uint32_t v : editor.regions.free) {
    const int i = static_cast<int>(v % (kN + 1)), j = static_cast<int>(v / (kN + 1));
    // The 5-point mean value property (this grid's cotangent Laplacian), in x, y and z.
    const Eigen::Vector3d mean = (p.col(id(i - 1, j)) + p.col(id(i + 1, j)) + p.col(id(i, j - 1)) + p.col(id(i, j + 1))) / 4;
    EXPECT_LT((p.col(v) - mean).norm(), 1e-12) << "vertex " << v;
    moved = std::max(moved, (p.col(v) - grid.positions().col(v)).norm());
  }
  EXPECT_GT(moved, 0.05);
}

// Handles all around (4 rings wide): an affine pose of the frame is an affine map of the
// plane, which Δ^k keeps exactly for every k.
TEST(BcmPlane, EveryOrderReproducesALinearHeightField) {
  const Mesh grid = test::grid_mesh(kN);
  std::vector<std::uint32_t> support(grid.num_vertices());
  for (std::uint32_t v = 0; v < support.size(); ++v) support[v] = v;
  const std::vector<BcmHandle> handles = {{"band", test::pick(grid, [](const Eigen::Vector3d& p) {
                                             return std::min({p.x(), p.y(), 1 - p.x(), 1 - p.y()}) < 4.5 / kN;
                                           })}};
  test::Pose pose;
  pose.linear = Eigen::AngleAxisd(M_PI / 6, Eigen::Vector3d::UnitX()).toRotationMatrix() *
                Eigen::Vector3d(1.1, 0.9, 1.0).asDiagonal();
  pose.translation = Eigen::Vector3d(0.1, 0.2, 0.3);
  for (int k = 1; k <= 3; ++k) {
    SCOPED_TRACE("k = " + std::to_string(k));
    const Eigen::Matrix3Xd p = edit(grid, support, handles, options(k), pose);
    double worst = 0, height = 0;
    for (Eigen::Index v = 0; v < p.cols(); ++v) {
      worst = std::max(worst, (p.col(v) - pose(grid.positions().col(v))).norm());
      height = std::max(height, std::abs(p(2, v)));
    }
    EXPECT_LT(worst, 1e-10);
    EXPECT_GT(height, 0.5);  // a real tilt: z = 0.3 + y·sin 30°·0.9
  }
}

struct Profile {
  double outer_slope = 0;  // mean z / h over free vertices next to fixed ones
  double inner_drop = 0;   // mean (z_handle − z) / h over free vertices next to the handle
  Eigen::VectorXd z;       // at the free vertices
};

Profile profile(int k, double outer, double inner) {
  const Mesh grid = test::grid_mesh(kN);
  const auto support = test::pick(grid, [](const Eigen::Vector3d& p) { return in_disk(p, 0.5, 0.5, 0.4); });
  const std::vector<BcmHandle> handles = {{"h", test::pick(grid, [](const Eigen::Vector3d& p) { return in_disk(p, 0.5, 0.5, 0.1); })}};
  BcmData editor = bcm_precompute(grid, support, handles, options(k, outer, inner));
  bcm_set_pose(editor, 0, Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, 0.2));
  Eigen::Matrix3Xd p = grid.positions();
  bcm_pose(editor, p);
  std::vector<char> kind(grid.num_vertices(), 'f');  // f fixed, p free, h handle
  for (std::uint32_t v : editor.regions.free) kind[v] = 'p';
  for (std::uint32_t v : handles[0].vertices) kind[v] = 'h';
  Profile out;
  out.z.resize(static_cast<Eigen::Index>(editor.regions.free.size()));
  int n_outer = 0, n_inner = 0;
  for (std::size_t f = 0; f < editor.regions.free.size(); ++f) {
    const std::uint32_t v = editor.regions.free[f];
    out.z[static_cast<Eigen::Index>(f)] = p(2, v);
    const int i = static_cast<int>(v % (kN + 1)), j = static_cast<int>(v / (kN + 1));
    bool by_fixed = false, by_handle = false;
    for (std::uint32_t u : {id(i - 1, j), id(i + 1, j), id(i, j - 1), id(i, j + 1)}) {
      by_fixed = by_fixed || kind[u] == 'f';
      by_handle = by_handle || kind[u] == 'h';
    }
    if (by_fixed) {
      out.outer_slope += p(2, v) * kN;
      ++n_outer;
    }
    if (by_handle) {
      out.inner_drop += (0.2 - p(2, v)) * kN;
      ++n_inner;
    }
  }
  out.outer_slope /= n_outer;
  out.inner_drop /= n_inner;
  return out;
}

// Figure 1's configurations: C^(k−1) leaves the fixed surface (or the handle) flat, C^0
// with a kink, and intermediate c lies between, monotonically.
TEST(BcmPlane, ClampedHingedAndBlendedBoundaries) {
  for (int k = 2; k <= 3; ++k) {
    SCOPED_TRACE("k = " + std::to_string(k));
    const double top = k - 1;
    const Profile clamped = profile(k, top, top);
    const Profile hinged_outer = profile(k, 0, top);
    const Profile hinged_inner = profile(k, top, 0);
    // Outer boundary: clamped starts far flatter than hinged.
    EXPECT_LT(clamped.outer_slope, 0.5 * hinged_outer.outer_slope);
    // Inner boundary: a clamped handle carries its plane into the surface, a hinged one
    // drops off at once.
    EXPECT_LT(clamped.inner_drop, 0.5 * hinged_inner.inner_drop);
    // The other boundary barely notices.
    EXPECT_NEAR(hinged_inner.outer_slope, clamped.outer_slope, 0.5 * clamped.outer_slope + 0.05);
    // Intermediate c: between the two, monotone in c.
    double previous = hinged_outer.outer_slope;
    const double gap = (hinged_outer.z - clamped.z).norm();
    for (double t : {0.25, 0.5, 0.75}) {
      const Profile mid = profile(k, t * top, top);
      EXPECT_LT(mid.outer_slope, previous) << "c = " << t * top;
      EXPECT_GT(mid.outer_slope, clamped.outer_slope) << "c = " << t * top;
      EXPECT_LT((mid.z - clamped.z).norm(), gap);
      EXPECT_LT((mid.z - hinged_outer.z).norm(), gap);
      previous = mid.outer_slope;
    }
  }
}

// An elongated (4:1) support with a round handle: the isotropic basis function dies off
// along the long axis, so its slope along the outer boundary varies much more than the
// anisotropic one's (Figure 3).
TEST(BcmPlane, AnisotropicBendingEvensTheBoundarySlope) {
  constexpr int n = 96;
  const Mesh grid = test::grid_mesh(n);
  const auto inside = [](const Eigen::Vector3d& p) { return std::abs(p.x() - 0.5) <= 0.4 && std::abs(p.y() - 0.5) <= 0.1; };
  const auto support = test::pick(grid, inside);
  const std::vector<BcmHandle> handles = {{"h", test::pick(grid, [](const Eigen::Vector3d& p) { return in_disk(p, 0.5, 0.5, 0.04); })}};
  const auto variation = [&](LaplacianKind kind) {
    BcmData editor = bcm_precompute(grid, support, handles, options(1, -1, -1, kind));
    bcm_set_pose(editor, 0, Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, 0.1));
    Eigen::Matrix3Xd p = grid.positions();
    bcm_pose(editor, p);
    // Slope at each free vertex next to the fixed surface (the outer boundary), corners
    // left out: z over the grid step to its fixed neighbour (where z = 0).
    std::vector<char> fixed(grid.num_vertices(), 1);
    for (std::uint32_t v : support) fixed[v] = 0;
    std::vector<double> slopes;
    for (std::uint32_t v : editor.regions.free) {
      const int i = static_cast<int>(v % (n + 1)), j = static_cast<int>(v / (n + 1));
      const auto at = [&](int a, int b) { return fixed[static_cast<std::size_t>(b * (n + 1) + a)] != 0; };
      const bool side_x = at(i - 1, j) || at(i + 1, j), side_y = at(i, j - 1) || at(i, j + 1);
      const bool near_x = at(i - 3, j) || at(i + 3, j), near_y = at(i, j - 3) || at(i, j + 3);
      if (!(side_x || side_y) || (near_x && near_y)) continue;
      slopes.push_back(p(2, v) * n);
    }
    double mean = 0, square = 0;
    for (double s : slopes) mean += s / static_cast<double>(slopes.size());
    for (double s : slopes) square += (s - mean) * (s - mean) / static_cast<double>(slopes.size());
    const auto [low, high] = std::minmax_element(slopes.begin(), slopes.end());
    return std::make_pair(std::sqrt(square) / mean, *high / *low);  // coefficient of variation, max/min
  };
  const auto isotropic = variation(LaplacianKind::Cotan), anisotropic = variation(LaplacianKind::Anisotropic);
  RecordProperty("isotropic_slope_variation", std::to_string(isotropic.first));
  RecordProperty("anisotropic_slope_variation", std::to_string(anisotropic.first));
  // Measured: isotropic slopes span a factor of about 190 along the boundary, anisotropic
  // ones about 8.
  EXPECT_LT(anisotropic.first, 0.7 * isotropic.first) << "isotropic " << isotropic.first << ", anisotropic " << anisotropic.first;
  EXPECT_LT(anisotropic.second, 0.1 * isotropic.second) << "isotropic " << isotropic.second << ", anisotropic " << anisotropic.second;
}

// A bumpy plane lifted by its handle: with detail the bumps ride on the bent base, their
// normal displacements within 5% of the originals; without, they are flattened.
TEST(BcmPlane, DetailKeepsTheBumpsAndPlainBcmFlattensThem) {
  constexpr int n = 64;
  const auto bump = [](double x, double y) {
    const double r = std::hypot(x - 0.5, y - 0.5);
    // Zero at the handle (r < 0.1) and outside r = 0.36: the rings Δ^k reaches stay flat.
    const double window = r < 0.12 || r > 0.34 ? 0.0 : std::pow(std::sin(M_PI * (r - 0.12) / 0.22), 2);
    return 0.004 * window * std::sin(2 * M_PI * 10 * x) * std::sin(2 * M_PI * 10 * y);
  };
  const Mesh bumpy = test::grid_mesh(n, bump);
  const Mesh flat = test::grid_mesh(n);
  const auto disk = [](double r) { return [r](const Eigen::Vector3d& p) { return in_disk(p, 0.5, 0.5, r); }; };
  const auto support = test::pick(flat, disk(0.42));
  const std::vector<BcmHandle> handles = {{"h", test::pick(flat, disk(0.08))}};
  test::Pose pose;
  pose.linear = Eigen::AngleAxisd(0.35, Eigen::Vector3d::UnitY()).toRotationMatrix();
  pose.translation = Eigen::Vector3d(0, 0, 0.15) + Eigen::Vector3d(0.5, 0.5, 0) - pose.linear * Eigen::Vector3d(0.5, 0.5, 0);

  BcmOptions with = options(2), without = options(2);
  with.detail = true;
  const Eigen::Matrix3Xd detailed = edit(bumpy, support, handles, with, pose);
  const Eigen::Matrix3Xd plain = edit(bumpy, support, handles, without, pose);
  const Eigen::Matrix3Xd smooth = edit(flat, support, handles, without, pose);
  // The bent base: the plain BCM surface of the same setup (free vertices), and its normals.
  const Eigen::Matrix3Xd base_normals = vertex_normals(bumpy, plain);
  const Eigen::Matrix3Xd smooth_normals = vertex_normals(flat, smooth);
  BcmData editor = bcm_precompute(bumpy, support, handles, without);
  double worst = 0, amplitude = 0, flattened = 0, tilt = 0;
  for (std::uint32_t v : editor.regions.free) {
    const double original = bumpy.positions()(2, v);
    amplitude = std::max(amplitude, std::abs(original));
    const double kept = (detailed.col(v) - plain.col(v)).dot(base_normals.col(v));
    worst = std::max(worst, std::abs(kept - original));
    flattened = std::max(flattened, std::abs((plain.col(v) - smooth.col(v)).dot(smooth_normals.col(v))));
    tilt = std::max(tilt, 1 - base_normals(2, v));
  }
  EXPECT_GT(tilt, 0.05);  // the base really turned
  EXPECT_LT(worst, 0.05 * amplitude) << "amplitude " << amplitude;
  EXPECT_LT(flattened, 0.05 * amplitude);
  // With the identity pose, detail gives back the input surface.
  BcmData identity = bcm_precompute(bumpy, support, handles, with);
  Eigen::Matrix3Xd same = bumpy.positions();
  bcm_pose(identity, same);
  EXPECT_LT((same - bumpy.positions()).cwiseAbs().maxCoeff(), 1e-12);
}

// Figure 4: a handle never moved holds its part like fixed surface. With the same
// continuity at both boundaries it is exactly the editor with those vertices fixed.
TEST(BcmPlane, AnUnmovedHandleIsAFixedIsland) {
  const Mesh grid = test::grid_mesh(kN);
  const auto support = test::pick(grid, [](const Eigen::Vector3d& p) { return in_disk(p, 0.5, 0.5, 0.45); });
  const auto island = test::pick(grid, [](const Eigen::Vector3d& p) { return in_disk(p, 0.3, 0.5, 0.08); });
  const auto pulled = test::pick(grid, [](const Eigen::Vector3d& p) { return in_disk(p, 0.7, 0.5, 0.06); });
  std::vector<std::uint32_t> support_without_island;
  std::set_difference(support.begin(), support.end(), island.begin(), island.end(), std::back_inserter(support_without_island));
  const test::Pose pose = lift(0.25);
  for (int k = 1; k <= 3; ++k) {
    SCOPED_TRACE("k = " + std::to_string(k));
    const Eigen::Matrix3Xd two = edit(grid, support, {{"pulled", pulled}, {"island", island}}, options(k), pose);
    const Eigen::Matrix3Xd one = edit(grid, support_without_island, {{"pulled", pulled}}, options(k), pose);
    EXPECT_LT((two - one).cwiseAbs().maxCoeff(), 1e-10);
    for (std::uint32_t v : island) EXPECT_EQ(two.col(v), grid.positions().col(v));
    EXPECT_GT(two.row(2).maxCoeff(), 0.2);
  }
}

}  // namespace
}  // namespace ffd
