// Multiresolution detail (Botsch & Kobbelt section 4, normal_detail.h) against a plain
// per-vertex implementation written here from the header's definition: frames from the
// base's area-weighted normals and a fixed reference neighbour, detail stored in them and
// added back on a moved base. The fast path (slots, blocks, all cores) must agree to
// 1e-12, give the surface back on an unmoved base, and not depend on the thread count.
#include <gtest/gtest.h>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "bcm/detail_rows.h"
#include "bcm/normal_detail.h"
#include "bcm/triangle_normals.h"
#include "bcm_test_util.h"
#include "test_meshes.h"

namespace ffd {
namespace {

// The frame of vertex i of `base` over `triangles`, with `reference` its tangent
// neighbour; false where it is degenerate.
bool frame_at(const Eigen::Matrix3Xd& base, const std::vector<Triangle>& triangles, std::uint32_t i,
              std::uint32_t reference, Eigen::Matrix3d& frame) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Triangle& t : triangles)
    if (t[0] == i || t[1] == i || t[2] == i) sum += (base.col(t[1]) - base.col(t[0])).cross(base.col(t[2]) - base.col(t[0]));
  const Eigen::Vector3d d = base.col(reference) - base.col(i);
  if (!(sum.norm() > 0)) return false;
  const Eigen::Vector3d n = sum.normalized();
  const Eigen::Vector3d tangent = d - d.dot(n) * n;
  if (!(tangent.squaredNorm() > 1e-24 * d.squaredNorm())) return false;
  frame.col(0) = n;
  frame.col(1) = tangent.normalized();
  frame.col(2) = n.cross(frame.col(1));
  return true;
}

// The neighbour with the longest part in the tangent plane at setup (ties: lowest index).
std::uint32_t reference_of(const Eigen::Matrix3Xd& base, const std::vector<Triangle>& triangles, std::uint32_t i) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Triangle& t : triangles)
    if (t[0] == i || t[1] == i || t[2] == i) sum += (base.col(t[1]) - base.col(t[0])).cross(base.col(t[2]) - base.col(t[0]));
  const Eigen::Vector3d n = sum.normalized();
  double best = -1;
  std::uint32_t pick = 0;
  for (const Triangle& t : triangles) {
    if (t[0] != i && t[1] != i && t[2] != i) continue;
    for (std::uint32_t j : t) {
      if (j == i) continue;
      const Eigen::Vector3d d = base.col(j) - base.col(i);
      const double along = (d - d.dot(n) * n).norm();
      if (along > best || (along == best && j < pick)) {
        best = along;
        pick = j;
      }
    }
  }
  return pick;
}

// The plain transfer: encode `detailed − base` at vertices 0..count−1, then rebuild on `moved`.
Eigen::Matrix3Xd plain_transfer(const Eigen::Matrix3Xd& base, const Eigen::Matrix3Xd& detailed,
                                const Eigen::Matrix3Xd& moved, std::size_t count, const std::vector<Triangle>& triangles) {
  Eigen::Matrix3Xd out = moved;
  for (std::uint32_t i = 0; i < count; ++i) {
    const std::uint32_t reference = reference_of(base, triangles, i);
    Eigen::Matrix3d at_setup, now;
    const Eigen::Vector3d d = detailed.col(i) - base.col(i);
    const bool flat = !frame_at(base, triangles, i, reference, at_setup);
    const Eigen::Vector3d c = flat ? d : Eigen::Vector3d(at_setup.transpose() * d);
    if (flat || !frame_at(moved, triangles, i, reference, now))
      out.col(i) = moved.col(i) + c;
    else
      out.col(i) = moved.col(i) + now * c;
  }
  return out;
}

struct Case {
  Eigen::Matrix3Xd base, detailed, moved;
  std::vector<Triangle> triangles;
  std::size_t count = 0;
  std::vector<std::uint32_t> columns;
};

// A bumpy sphere over a smooth one, its vertices shuffled so that neighbours lie far apart
// in memory (as in a scanned mesh's file), and the smooth one bent for the moved base. The
// icosphere is jittered: on its exact symmetry the reference neighbour's "longest" is a
// tie that rounding decides, and the two implementations may break it differently.
Case bumpy_sphere() {
  const Mesh mesh = test::sphere_mesh(3);
  const std::vector<Triangle> all = test::all_triangles(mesh);
  const Eigen::Index n = static_cast<Eigen::Index>(mesh.num_vertices());
  std::vector<std::uint32_t> shuffle(static_cast<std::size_t>(n));
  for (std::size_t i = 0; i < shuffle.size(); ++i) shuffle[i] = static_cast<std::uint32_t>(i);
  std::mt19937 rng(11);
  std::shuffle(shuffle.begin(), shuffle.end(), rng);
  Case c;
  c.base.resize(3, n);
  std::uniform_real_distribution<double> jitter(-0.01, 0.01);
  for (Eigen::Index v = 0; v < n; ++v)
    c.base.col(shuffle[static_cast<std::size_t>(v)]) =
        mesh.positions().col(v) + Eigen::Vector3d(jitter(rng), jitter(rng), jitter(rng));
  for (const Triangle& t : all) c.triangles.push_back({shuffle[t[0]], shuffle[t[1]], shuffle[t[2]]});
  c.detailed = c.base;
  c.moved = c.base;
  for (Eigen::Index v = 0; v < n; ++v) {
    const Eigen::Vector3d p = c.base.col(v);
    c.detailed.col(v) = p * (1 + 0.03 * std::sin(9 * p.x()) * std::cos(7 * p.y()));
    c.moved.col(v) = Eigen::Vector3d(p.x() + 0.4 * p.z() * p.z(), p.y(), 1.3 * p.z());
  }
  c.count = static_cast<std::size_t>(n) * 3 / 4;  // the rest: a fixed ring, as in an editor's stencil
  for (std::size_t i = 0; i < c.count; ++i) c.columns.push_back(static_cast<std::uint32_t>(i));
  return c;
}

TEST(NormalDetail, AgreesWithThePlainTransferOnAShuffledMesh) {
  const Case c = bumpy_sphere();
  const NormalDetail detail(c.base, c.detailed, c.count, c.triangles);
  Eigen::Matrix3Xd fast = c.moved;
  detail.reconstruct(c.moved, fast, c.columns);
  const Eigen::Matrix3Xd plain = plain_transfer(c.base, c.detailed, c.moved, c.count, c.triangles);
  double worst = 0;
  for (std::size_t i = 0; i < c.count; ++i)
    worst = std::max(worst, (fast.col(static_cast<Eigen::Index>(i)) - plain.col(static_cast<Eigen::Index>(i))).norm());
  EXPECT_LT(worst, 1e-12);
  // The detail moved with the base: far from a plain translation of it.
  EXPECT_GT((fast - (c.moved + c.detailed - c.base)).leftCols(static_cast<Eigen::Index>(c.count)).cwiseAbs().maxCoeff(), 1e-3);
}

TEST(NormalDetail, AnUnmovedBaseGivesTheSurfaceBack) {
  const Case c = bumpy_sphere();
  const NormalDetail detail(c.base, c.detailed, c.count, c.triangles);
  Eigen::Matrix3Xd out = c.base;
  detail.reconstruct(c.base, out, c.columns);
  EXPECT_LT((out - c.detailed).leftCols(static_cast<Eigen::Index>(c.count)).cwiseAbs().maxCoeff(), 1e-14);
}

TEST(NormalDetail, TheResultDoesNotDependOnTheThreadCount) {
  const Case c = bumpy_sphere();
  const NormalDetail detail(c.base, c.detailed, c.count, c.triangles);
  const int threads = omp_get_max_threads();
  Eigen::Matrix3Xd one = c.moved, many = c.moved;
  omp_set_num_threads(1);
  detail.reconstruct(c.moved, one, c.columns);
  omp_set_num_threads(3);
  detail.reconstruct(c.moved, many, c.columns);
  omp_set_num_threads(threads);
  EXPECT_EQ(one, many);
}

// The rows' arithmetic is the one detail_rows.h writes out, bit for bit: β t fused into
// α n, then γ b added (rows x, y) or fused (row z); a flagged slot's coefficient as it is.
// The products kept apart go through volatile, so that no compiler fuses them here. The
// plain form (no fusion at all) differs from it on these numbers, so the test can fail.
TEST(DetailRows, FuseWhereWrittenOutAndNowhereElse) {
  constexpr int kLength = kDetailRowLength;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> value(-1, 1);
  std::vector<double> data(12 * kLength);
  for (double& x : data) x = value(rng);
  std::vector<unsigned char> flat(kLength);
  for (int j = 0; j < kLength; ++j) flat[static_cast<std::size_t>(j)] = j % 9 == 4;
  const auto row = [&](int k) { return data.data() + k * kLength; };
  const double* c[3] = {row(0), row(1), row(2)};
  const double* n[3] = {row(3), row(4), row(5)};
  const double* t[3] = {row(6), row(7), row(8)};
  const double* b[3] = {row(9), row(10), row(11)};
  std::vector<double> result(3 * kLength);
  double* const detail[3] = {result.data(), result.data() + kLength, result.data() + 2 * kLength};
  detail_rows(c, n, t, b, flat.data(), detail);
  int plain_differs = 0;
  for (int r = 0; r < 3; ++r)
    for (int j = 0; j < kLength; ++j) {
      if (flat[static_cast<std::size_t>(j)]) {
        EXPECT_EQ(detail[r][j], c[r][j]) << r << " " << j;
        continue;
      }
      volatile double alpha_n = c[0][j] * n[r][j], beta_t = c[1][j] * t[r][j], gamma_b = c[2][j] * b[r][j];
      const double inner = std::fma(c[1][j], t[r][j], alpha_n);
      const double expected = r < 2 ? inner + gamma_b : std::fma(c[2][j], b[r][j], inner);
      EXPECT_EQ(detail[r][j], expected) << "row " << r << " slot " << j;
      volatile double plain = alpha_n + beta_t;
      plain_differs += detail[r][j] != plain + gamma_b;
    }
  EXPECT_GT(plain_differs, 0);
}

// triangle_normals() is the cross product (p1 − p0) × (p2 − p0), rounded as its header
// writes out, whether it ran as vectors or not; the fourth coordinate is zero, and nothing
// outside the range is written.
TEST(TriangleNormals, AreTheCrossProductWithTheFusionsWrittenOut) {
  constexpr long kPoints = 40, kTriangles = 300, kBegin = 7, kEnd = 290;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> value(-1, 1);
  std::uniform_int_distribution<std::uint32_t> corner(0, kPoints - 1);
  std::vector<double> points(4 * kPoints, 0.0);
  for (long i = 0; i < kPoints; ++i)
    for (int r = 0; r < 3; ++r) points[static_cast<std::size_t>(4 * i + r)] = value(rng);
  std::vector<std::uint32_t> corners(3 * kTriangles);
  for (std::uint32_t& c : corners) c = corner(rng);
  const double kUnwritten = -7.0;
  std::vector<double> normals(4 * kTriangles, kUnwritten);
  triangle_normals(points.data(), corners.data(), kBegin, kEnd, normals.data());
  int plain_differs = 0;
  for (long f = 0; f < kTriangles; ++f) {
    const double* n = normals.data() + 4 * f;
    if (f < kBegin || f >= kEnd) {
      for (int r = 0; r < 4; ++r) EXPECT_EQ(n[r], kUnwritten) << "triangle " << f;
      continue;
    }
    const auto at = [&](int k) {
      return Eigen::Map<const Eigen::Vector3d>(points.data() + 4 * corners[static_cast<std::size_t>(3 * f + k)]);
    };
    const Eigen::Vector3d e1 = at(1) - at(0), e2 = at(2) - at(0);
    // The products that stay apart go through volatile, so that this file's compiler
    // cannot fuse them.
    volatile double yz = e1.y() * e2.z(), zy = e1.z() * e2.y(), zx = e1.z() * e2.x(), xz = e1.x() * e2.z(),
                    xy = e1.x() * e2.y(), yx = e1.y() * e2.x();
    EXPECT_EQ(n[0], std::fma(-e1.z(), e2.y(), yz)) << "triangle " << f;
    EXPECT_EQ(n[1], std::fma(-e1.x(), e2.z(), zx)) << "triangle " << f;
    EXPECT_EQ(n[2], std::fma(e1.x(), e2.y(), -yx)) << "triangle " << f;
    EXPECT_EQ(n[3], 0.0) << "triangle " << f;
    const Eigen::Vector3d cross = e1.cross(e2);
    for (int r = 0; r < 3; ++r) EXPECT_NEAR(n[r], cross[r], 1e-15) << "triangle " << f;
    plain_differs += n[0] != yz - zy || n[1] != zx - xz || n[2] != xy - yx;
  }
  EXPECT_GT(plain_differs, 0);
}

}  // namespace
}  // namespace ffd
