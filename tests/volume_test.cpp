// The volume mesh core: the cell quality guard against independent formulas, and the SU2
// reader and its patching writer.
#include <gtest/gtest.h>
#include <omp.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

#include "common/errors.h"
#include "mesh/cell_quality.h"
#include "mesh/su2_io.h"
#include "mesh/volume_patch.h"

namespace ffd {
namespace {

// One cell of `type` over nodes 0..n-1 at `points`.
VolumeCells one_cell(std::uint8_t type, int n) {
  VolumeCells cells;
  std::vector<std::uint32_t> ids(n);
  for (int k = 0; k < n; ++k) ids[k] = static_cast<std::uint32_t>(k);
  cells.add(type, ids.data(), ids.size());
  return cells;
}

Eigen::Matrix3Xd columns(std::initializer_list<Eigen::Vector3d> points) {
  Eigen::Matrix3Xd m(3, static_cast<Eigen::Index>(points.size()));
  Eigen::Index i = 0;
  for (const Eigen::Vector3d& p : points) m.col(i++) = p;
  return m;
}

Eigen::Matrix3Xd unit_cube() {
  return columns({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}});
}

TEST(CellQuality, IdealCellsScoreOneAndHaveTheirVolume) {
  const double h = std::sqrt(3.0) / 2;
  const Eigen::Matrix3Xd tet = columns({{0, 0, 0}, {1, 0, 0}, {0.5, h, 0}, {0.5, std::sqrt(3.0) / 6, std::sqrt(2.0 / 3)}});
  const CellMeasure t = measure_cell(one_cell(cell_type::kTetra, 4), 0, tet);
  EXPECT_NEAR(t.scaled_jacobian, 1, 1e-12);
  EXPECT_NEAR(t.volume, std::sqrt(2.0) / 12, 1e-12);  // a regular tetrahedron of edge 1
  const CellMeasure c = measure_cell(one_cell(cell_type::kHexahedron, 8), 0, unit_cube());
  EXPECT_NEAR(c.scaled_jacobian, 1, 1e-12);
  EXPECT_NEAR(c.volume, 1, 1e-12);
  // VTK's wedge: (0, 1, 2) winds clockwise seen from (3, 4, 5).
  const Eigen::Matrix3Xd wedge = columns({{0, 0, 0}, {0.5, h, 0}, {1, 0, 0}, {0, 0, 1}, {0.5, h, 1}, {1, 0, 1}});
  const CellMeasure w = measure_cell(one_cell(cell_type::kWedge, 6), 0, wedge);
  EXPECT_NEAR(w.scaled_jacobian, 1, 1e-12);
  EXPECT_NEAR(w.volume, h / 2, 1e-12);
  const Eigen::Matrix3Xd pyramid = columns({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, std::sqrt(0.5)}});
  const CellMeasure p = measure_cell(one_cell(cell_type::kPyramid, 5), 0, pyramid);
  EXPECT_NEAR(p.scaled_jacobian, 1, 1e-12);
  EXPECT_NEAR(p.volume, std::sqrt(0.5) / 3, 1e-12);
}

// An affine map x -> A x + b scales every volume by det A; for a hexahedron the face fans
// are exact (its faces stay planar parallelograms), and a reflection inverts every cell.
TEST(CellQuality, AffineMapsScaleVolumesByTheDeterminant) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::Matrix3d A;
    for (int i = 0; i < 9; ++i) A(i / 3, i % 3) = u(rng) + (i % 4 == 0 ? 2.0 : 0.0);
    const Eigen::Vector3d b(u(rng), u(rng), u(rng));
    const Eigen::Matrix3Xd cube = (A * unit_cube()).colwise() + b;
    const CellMeasure m = measure_cell(one_cell(cell_type::kHexahedron, 8), 0, cube);
    EXPECT_NEAR(m.volume, A.determinant(), 1e-12);
    EXPECT_EQ(inverted(m), A.determinant() <= 0) << "trial " << trial;
  }
}

// The tetrahedron's own path (one determinant, the extreme edge product) against the
// general corner loop of its quadratic kind, which reads the same four corners, on
// random and inverted tetrahedra.
TEST(CellQuality, TetrahedraMatchTheCornerLoop) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 200; ++trial) {
    Eigen::Matrix3Xd p(3, 10);
    for (int k = 0; k < 10; ++k) p.col(k) = Eigen::Vector3d(u(rng), u(rng), u(rng));
    const CellMeasure fast = measure_cell(one_cell(cell_type::kTetra, 4), 0, p);
    const CellMeasure loop = measure_cell(one_cell(cell_type::kQuadraticTetra, 10), 0, p);
    EXPECT_NEAR(fast.scaled_jacobian, loop.scaled_jacobian, 1e-12) << "trial " << trial;
    EXPECT_NEAR(fast.volume, loop.volume, 1e-12);
  }
}

// The same cube as a polyhedron (VTK 42, faces wound outward) measures as the hexahedron.
TEST(CellQuality, PolyhedronCubeMatchesTheHexahedron) {
  VolumeCells cells;
  const std::vector<std::uint32_t> nodes = {0, 1, 2, 3, 4, 5, 6, 7};
  const std::vector<std::uint32_t> faces = {6, 4, 0, 3, 2, 1, 4, 4, 5, 6, 7, 4, 0, 1, 5, 4,
                                            4, 1, 2, 6, 5, 4, 2, 3, 7, 6, 4, 3, 0, 4, 7};
  cells.add_polyhedron(nodes, faces);
  const CellMeasure m = measure_cell(cells, 0, unit_cube());
  EXPECT_NEAR(m.volume, 1, 1e-12);
  EXPECT_GT(m.scaled_jacobian, 0);
  Eigen::Matrix3Xd squashed = unit_cube();
  squashed(2, 6) = -0.5;  // node 6 pushed through the bottom: a face pyramid turns over
  EXPECT_TRUE(inverted(measure_cell(cells, 0, squashed)));
}

// A mesh of many cells: the counts, the first inverted cell and the worst list, the same
// for any thread count, against a loop over measure_cell.
TEST(CellQuality, CountsAgreeWithALoopOverTheCells) {
  VolumeCells cells;
  Eigen::Matrix3Xd points(3, 4 * 40000);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  for (std::uint32_t c = 0; c < 40000; ++c) {
    const std::uint32_t ids[4] = {4 * c, 4 * c + 1, 4 * c + 2, 4 * c + 3};
    for (std::uint32_t k = 0; k < 4; ++k) points.col(ids[k]) = Eigen::Vector3d(u(rng), u(rng), u(rng));
    cells.add(cell_type::kTetra, ids, 4);
  }
  std::size_t inverted_count = 0, first = 0;
  double lowest = 1;
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const CellMeasure m = measure_cell(cells, c, points);
    if (inverted(m) && !inverted_count++) first = c;
    lowest = std::min(lowest, m.scaled_jacobian);
  }
  const CellQuality q = cell_quality(cells, points, 7);
  EXPECT_EQ(q.checked, cells.size());
  EXPECT_EQ(q.inverted, inverted_count);
  EXPECT_EQ(q.first_inverted, first);
  EXPECT_EQ(q.min_scaled_jacobian, lowest);
  ASSERT_EQ(q.worst.size(), 7u);
  EXPECT_EQ(q.worst.front().scaled_jacobian, lowest);
  for (std::size_t i = 1; i < q.worst.size(); ++i) EXPECT_LE(q.worst[i - 1].scaled_jacobian, q.worst[i].scaled_jacobian);
}

// A valid mesh (a jittered grid of Kuhn tetrahedra, a hexahedron among them): most cells
// are decided without their score, and the verdict is the loop's: the minimum, and the
// worst cells with their scores, in order, for any thread count and with no worst list.
TEST(CellQuality, OnAValidMeshTheWorstCellsAreTheLoops) {
  const int n = 30;
  Eigen::Matrix3Xd points(3, n * n * n);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> jitter(-0.2, 0.2);
  for (int i = 0; i < n * n * n; ++i)
    points.col(i) = Eigen::Vector3d(i % n + jitter(rng), i / n % n + jitter(rng), i / (n * n) + jitter(rng));
  VolumeCells cells;
  const int kuhn[6][4] = {{0, 1, 3, 7}, {0, 1, 7, 5}, {0, 4, 5, 7}, {0, 2, 6, 7}, {0, 3, 2, 7}, {0, 6, 4, 7}};
  for (int z = 0; z + 1 < n; ++z)
    for (int y = 0; y + 1 < n; ++y)
      for (int x = 0; x + 1 < n; ++x) {
        std::uint32_t corner[8];
        for (int k = 0; k < 8; ++k) corner[k] = static_cast<std::uint32_t>((x + (k & 1)) + n * ((y + (k >> 1 & 1)) + n * (z + (k >> 2))));
        for (const auto& t : kuhn) {
          std::uint32_t ids[4] = {corner[t[0]], corner[t[1]], corner[t[2]], corner[t[3]]};
          const Eigen::Vector3d a = points.col(ids[0]);
          if ((points.col(ids[1]) - a).dot((points.col(ids[2]) - a).cross(points.col(ids[3]) - a)) < 0) std::swap(ids[2], ids[3]);
          cells.add(cell_type::kTetra, ids, 4);
        }
        if (x == 7 && y == 7 && z == 7) {
          const std::uint32_t hex[8] = {corner[0], corner[1], corner[3], corner[2], corner[4], corner[5], corner[7], corner[6]};
          cells.add(cell_type::kHexahedron, hex, 8);
        }
      }
  std::vector<CellMeasure> loop;
  for (std::size_t c = 0; c < cells.size(); ++c) loop.push_back(measure_cell(cells, c, points));
  std::sort(loop.begin(), loop.end(), [](const CellMeasure& a, const CellMeasure& b) {
    return a.scaled_jacobian != b.scaled_jacobian ? a.scaled_jacobian < b.scaled_jacobian : a.cell < b.cell;
  });
  ASSERT_GT(loop.front().scaled_jacobian, 0);
  const int team = omp_get_max_threads();
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    const CellQuality q = cell_quality(cells, points, 9);
    EXPECT_EQ(q.checked, cells.size());
    EXPECT_EQ(q.inverted, 0u);
    EXPECT_EQ(q.min_scaled_jacobian, loop.front().scaled_jacobian);
    ASSERT_EQ(q.worst.size(), 9u);
    for (std::size_t i = 0; i < 9; ++i) {
      EXPECT_EQ(q.worst[i].cell, loop[i].cell);
      EXPECT_EQ(q.worst[i].scaled_jacobian, loop[i].scaled_jacobian);
      EXPECT_EQ(q.worst[i].volume, loop[i].volume);
    }
    EXPECT_EQ(cell_quality(cells, points, 0).min_scaled_jacobian, loop.front().scaled_jacobian);
  }
  omp_set_num_threads(team);
}

// The guard of a run's steps: after a move, only blocks of cells with a moved node are
// measured again, and the verdict is a fresh one's, field for field.
TEST(CellQuality, AVerdictUpdatedAfterAMoveIsAFreshOnes) {
  VolumeCells cells;
  const std::uint32_t n = 60000;  // tetrahedra, 4 blocks
  Eigen::Matrix3Xd points(3, 4 * n);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(0, 1);
  for (std::uint32_t c = 0; c < n; ++c) {
    const std::uint32_t ids[4] = {4 * c, 4 * c + 1, 4 * c + 2, 4 * c + 3};
    points.col(ids[0]) = Eigen::Vector3d(u(rng), u(rng), u(rng));
    points.col(ids[1]) = points.col(ids[0]) + Eigen::Vector3d(1, 0, 0);
    points.col(ids[2]) = points.col(ids[0]) + Eigen::Vector3d(0, 1, 0);
    points.col(ids[3]) = points.col(ids[0]) + Eigen::Vector3d(u(rng), u(rng), 0.5 + u(rng));
    cells.add(cell_type::kTetra, ids, 4);
  }
  CellQualityCache cache;
  const auto expect_same = [&](const CellQuality& a, const CellQuality& b) {
    EXPECT_EQ(a.checked, b.checked);
    EXPECT_EQ(a.inverted, b.inverted);
    EXPECT_EQ(a.first_inverted, b.first_inverted);
    EXPECT_EQ(a.min_scaled_jacobian, b.min_scaled_jacobian);
    ASSERT_EQ(a.worst.size(), b.worst.size());
    for (std::size_t i = 0; i < a.worst.size(); ++i) {
      EXPECT_EQ(a.worst[i].cell, b.worst[i].cell);
      EXPECT_EQ(a.worst[i].scaled_jacobian, b.worst[i].scaled_jacobian);
    }
  };
  expect_same(cell_quality(cells, points, cache), cell_quality(cells, points));
  points(2, 4 * 50000 + 3) = -5;  // cell 50,000 turned over: one block changes
  const CellQuality after = cell_quality(cells, points, cache);
  EXPECT_EQ(after.inverted, 1u);
  EXPECT_EQ(after.first_inverted, 50000u);
  expect_same(after, cell_quality(cells, points));
  points(2, 4 * 50000 + 3) = points(2, 4 * 50000) + 1;  // turned back, and a cell of the first block squashed
  points(2, 4 * 10 + 3) = points(2, 4 * 10) + 1e-3;
  expect_same(cell_quality(cells, points, cache), cell_quality(cells, points));
  EXPECT_EQ(cell_quality(cells, points, cache).worst.front().cell, 10u);
}

const char kSu2[] =
    "% a cube split in a hexahedron and a wedge-free tet corner\n"
    "NDIME= 3\n"
    "NELEM= 2\n"
    "12 0 1 2 3 4 5 6 7 0\n"
    "10 1 8 2 5 1\n"
    "NPOIN= 9\n"
    "0 0 0 0\n1 0 0 1\n1 1 0 2\n0 1 0 3\n0 0 1 4\n1 0 1 5\n1 1 1 6\n0 1 1 7\n2.5 0.5 0.25 8\n"
    "NMARK= 2\n"
    "MARKER_TAG= bottom\n"
    "MARKER_ELEMS= 1\n"
    "9 0 3 2 1\n"
    "MARKER_TAG= tip\n"
    "MARKER_ELEMS= 1\n"
    "5 1 8 2\n"
    "FFD_NBOX= 0\n";

VolumeRead su2(const std::string& text) { return read_su2(std::make_shared<const FileBytes>(std::string(text)), "m.su2"); }

std::string written(const VolumeRead& read, const Eigen::Matrix3Xd& positions) {
  std::ostringstream os;
  read.source.file->write(os, positions);
  return os.str();
}

TEST(Su2Reader, ReadsElementsNodesAndMarkers) {
  const VolumeRead read = su2(kSu2);
  EXPECT_EQ(read.points.cols(), 9);
  EXPECT_EQ(read.points.col(8), Eigen::Vector3d(2.5, 0.5, 0.25));
  ASSERT_EQ(read.source.cells.size(), 4u);  // two volume elements, then the markers' two
  EXPECT_EQ(read.source.cells.type[0], cell_type::kHexahedron);
  EXPECT_EQ(read.source.cells.type[1], cell_type::kTetra);
  EXPECT_EQ(read.source.cells.nodes(1)[1], 8u);
  ASSERT_EQ(read.source.markers.size(), 2u);
  EXPECT_EQ(read.source.markers[1].name, "tip");
  EXPECT_EQ(read.source.markers[1].cells, std::vector<std::uint64_t>{3});
  EXPECT_EQ(read.source.markers[0].dimension, 2);
  EXPECT_EQ(cell_quality(read.source.cells, read.points).inverted, 0u);
}

TEST(Su2Reader, WritesItselfBackAndOnlyTheMovedNodes) {
  const VolumeRead read = su2(kSu2);
  EXPECT_EQ(written(read, read.points), kSu2);
  Eigen::Matrix3Xd moved = read.points;
  moved.col(8) = Eigen::Vector3d(3.25, 0.1, -1e-20);
  const std::string out = written(read, moved);
  std::string expected = kSu2;
  expected.replace(expected.find("2.5 0.5 0.25 8"), 14, "3.25 0.1 -1e-20 8");
  EXPECT_EQ(out, expected);
  EXPECT_EQ(su2(out).points, moved);
}

TEST(Su2Reader, RefusesWithTheLine) {
  auto message = [](std::string text) {
    try {
      su2(text);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  std::string bad = kSu2;
  bad.replace(bad.find("10 1 8 2 5"), 10, "10 1 9 2 5");
  EXPECT_EQ(message(bad), "m.su2:5: node index 9 out of range (the file has 9 nodes)");
  bad = kSu2;
  bad.replace(bad.find("10 1 8"), 2, "11");
  EXPECT_EQ(message(bad), "m.su2:5: element type 11 is not an SU2 element (3, 5, 9, 10, 12, 13, 14)");
  bad = kSu2;
  bad.replace(bad.find("5 1 8 2"), 7, "5 1 18 2");
  EXPECT_EQ(message(bad), "m.su2:22: node index 18 out of range (the file has 9 nodes)");
  const std::string cut = std::string(kSu2).substr(0, std::string(kSu2).find("1 1 0 2"));
  EXPECT_EQ(message(cut), "m.su2:8: the file ends before every node of NPOIN is read");
  // An empty marker before the one at fault (a fuzzing finding: the line was looked up
  // through the markers' first cells).
  bad = kSu2;
  bad.replace(bad.find("MARKER_ELEMS= 1\n9 0 3 2 1\n"), 26, "MARKER_ELEMS= 0\n");
  bad.replace(bad.find("5 1 8 2"), 7, "5 1 18 2");
  EXPECT_EQ(message(bad), "m.su2:21: node index 18 out of range (the file has 9 nodes)");
  EXPECT_EQ(message("NDIME= 3\nNZONE= 2\n"), "m.su2:2: multi-zone SU2 files (NZONE) are not supported; split the zones into files of their own");
  EXPECT_EQ(message("NDIME= 3\nNELEM= 1\n10 0 1 2\n"), "m.su2:3: tetra needs 4 node indices");
  EXPECT_EQ(message("NDIME= 3\nNELEM= 99999999\n"), "m.su2:2: NELEM= 99999999 is more than the rest of the file can hold");
}

}  // namespace
}  // namespace ffd
