// The Hausdorff compare (mesh/hausdorff.h) against independent answers: CGAL's point-to-
// triangle distance and AABB tree, CGAL's bounded-error Hausdorff distance, and a brute
// force over every triangle; its decision on pairs made just under and just over the
// tolerance; and results that do not depend on the thread count.
#include <gtest/gtest.h>

#include "mesh/halfedge_view_cgal.h"  // CGAL's kernel before its distance functions

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>

#include <random>

#include "mesh/build_mesh.h"
#include "mesh/hausdorff.h"
#include "mesh/mesh_compare.h"
#include "mesh/mesh_io.h"
#include "mesh/point_triangle.h"
#include "mesh/surface_index.h"
#include "support/cgal_hausdorff.h"
#include "test_meshes.h"
#include "warp/bernstein_lattice.h"

namespace ffd {
namespace {

using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, CGAL::AABB_face_graph_triangle_primitive<SurfaceMesh>>>;

double diagonal(const Mesh& m) {
  const ConstVec3Array p = m.positions();
  return (p.rowwise().maxCoeff() - p.rowwise().minCoeff()).norm();
}

// `mesh` deformed by a 4 x 4 x 4 Bernstein lattice around it whose point [2, 1, 2] moved
// by `by` times the diagonal along (1, 2, -1)/|...|.
Mesh deformed(const Mesh& mesh, double by) {
  const ConstVec3Array p = mesh.positions();
  const Eigen::Vector3d lo = p.rowwise().minCoeff(), hi = p.rowwise().maxCoeff();
  const Eigen::Vector3d pad = 0.05 * (hi - lo);
  BernsteinLattice lattice(Parallelepiped(lo - pad, (hi - lo + 2 * pad).asDiagonal()), {3, 3, 3});
  const std::size_t id = *lattice.find_point(0, PointIndex{true, {2, 1, 2}, 0});
  const Eigen::Vector3d target = lattice.points(0, {id}).col(0) + by * diagonal(mesh) * Eigen::Vector3d(1, 2, -1).normalized();
  lattice.move_points(0, {id}, {target});
  Mesh out = mesh.clone();
  for (Eigen::Index v = 0; v < p.cols(); ++v) out.positions().col(v) = lattice.apply(p.col(v), nullptr);
  return out;
}

std::vector<Mesh> real_meshes(const std::vector<const char*>& names = {"elephant.off", "pig.off", "couplingdown.off"}) {
  std::vector<Mesh> out;
  out.push_back(test::bunny());
  for (const char* name : names)
    if (const std::string path = test::cgal_mesh(name); !path.empty()) out.push_back(read_mesh(path));
  EXPECT_EQ(out.size(), names.size() + 1) << "CGAL's data set is missing: scripts/setup.sh installs libcgal-demo";
  return out;
}

// The project's shared meshes (26k to 53k vertices), which CGAL's data set holds too.
const std::vector<const char*> kSharedMeshes = {"armadillo.off", "bunny00.off", "refined_elephant.off"};

// The squared distance from p to segment [s, e], for the degenerate cases.
double segment_squared_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& s, const Eigen::Vector3d& e) {
  const double len2 = (e - s).squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - s).dot(e - s) / len2, 0.0, 1.0) : 0.0;
  return (p - s - t * (e - s)).squaredNorm();
}

TEST(PointTriangle, EqualsCgalsDistanceAndASegmentsForDegenerateTriangles) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  const auto random = [&] { return Eigen::Vector3d(u(rng), u(rng), u(rng)); };
  for (int i = 0; i < 20000; ++i) {
    const Eigen::Vector3d a = random(), b = random(), c = random(), p = 2 * random();
    const double cgal = CGAL::to_double(CGAL::squared_distance(to_point(p), Kernel::Triangle_3(to_point(a), to_point(b), to_point(c))));
    ASSERT_NEAR(point_triangle_squared_distance(p, a, b, c), cgal, 1e-12 * (1 + cgal)) << i;
    // Degenerate: a corner on the opposite edge, two corners at one place, a point.
    const double ab = segment_squared_distance(p, a, b);
    ASSERT_NEAR(point_triangle_squared_distance(p, a, b, a + 0.3 * (b - a)), ab, 1e-12 * (1 + ab)) << i;
    ASSERT_NEAR(point_triangle_squared_distance(p, a, a, b), ab, 1e-12 * (1 + ab)) << i;
    ASSERT_NEAR(point_triangle_squared_distance(p, b, a, a), ab, 1e-12 * (1 + ab)) << i;
    // To 4 ulps: the library's copy is compiled at -O3, where GCC fuses other products
    // into FMAs than in the tests' -O1 (tests/CMakeLists.txt links the library's copy).
    ASSERT_DOUBLE_EQ(point_triangle_squared_distance(p, a, a, a), (p - a).squaredNorm()) << i;
  }
}

// The index's triangles as a CGAL soup (corners not shared), for CGAL's own AABB tree.
SurfaceMesh triangle_soup(const SurfaceIndex& index) {
  SurfaceMesh soup;
  for (std::uint32_t t = 0; t < index.num_triangles(); ++t) {
    std::array<VertexIndex, 3> v;
    for (int i = 0; i < 3; ++i) v[i] = soup.add_vertex(to_point(index.point(index.triangle(t)[i])));
    soup.add_face(v[0], v[1], v[2]);
  }
  return soup;
}

TEST(SurfaceIndex, ClosestDistanceEqualsCgalsAabbTreeWhateverTheHint) {
  for (const Mesh& mesh : real_meshes()) {
    const SurfaceIndex index(mesh);
    const SurfaceMesh soup = triangle_soup(index);
    Tree tree(faces(soup).first, faces(soup).second, soup);
    const ConstVec3Array p = mesh.positions();
    const Eigen::Vector3d lo = p.rowwise().minCoeff(), hi = p.rowwise().maxCoeff();
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-0.2, 1.2);
    std::uniform_int_distribution<std::uint32_t> any(0, static_cast<std::uint32_t>(index.num_triangles() - 1));
    for (int i = 0; i < 3000; ++i) {
      // Points all around the mesh, and near its surface (vertices pushed off it).
      const Eigen::Vector3d q = i % 2 ? Eigen::Vector3d(lo + Eigen::Vector3d(u(rng), u(rng), u(rng)).cwiseProduct(hi - lo))
                                      : Eigen::Vector3d(p.col(any(rng) % p.cols()) + 1e-3 * (hi - lo).norm() * Eigen::Vector3d(u(rng), u(rng), u(rng)));
      const double cgal = tree.squared_distance(to_point(q));
      const SurfaceIndex::Closest c = index.closest(q, i % 3 ? any(rng) : SurfaceIndex::kNone);
      ASSERT_NEAR(c.squared, cgal, 1e-12 * (hi - lo).squaredNorm()) << mesh.source() << " point " << i;
      ASSERT_EQ(index.squared_distance(q, c.triangle), c.squared);
    }
  }
}

// Each triangle of `mesh` split in two at its first edge's midpoint (a soup: corners not
// shared), then deformed: the same surface, bent, with other connectivity.
Mesh split_and_deformed(const Mesh& mesh) {
  const SurfaceIndex index(mesh);
  PolygonSoup soup;
  for (std::uint32_t t = 0; t < index.num_triangles(); ++t) {
    std::array<Eigen::Vector3d, 3> c;
    for (int i = 0; i < 3; ++i) c[i] = index.point(index.triangle(t)[i]);
    const auto base = static_cast<std::uint32_t>(soup.positions.size());
    for (const Eigen::Vector3d& q : {c[0], c[1], c[2], Eigen::Vector3d((c[0] + c[1]) / 2)}) soup.positions.push_back(q);
    soup.elements.add_polygon({base, base + 3, base + 2});
    soup.elements.add_polygon({base + 3, base + 1, base + 2});
  }
  return deformed(build_mesh(std::move(soup), "split"), 0.02);
}

TEST(Hausdorff, ReportedMaxIsWithinItsBoundOfABruteForce) {
  // The bunny (3,674 faces) against a bent copy of it with twice the triangles: the
  // farthest points lie inside faces, not at vertices.
  const Mesh a = test::bunny();
  const Mesh b = split_and_deformed(a);
  const double reference = std::max(brute_force_directed_hausdorff(a, b, 5), brute_force_directed_hausdorff(b, a, 4));
  const double error = 0.02 * reference;
  const MeshDifference d = compare_hausdorff(a, b, {reference, error, 0});
  EXPECT_LE(d.max, d.max_upper);
  EXPECT_LE(d.max_upper - d.max, error);
  EXPECT_LE(reference, d.max_upper * (1 + 1e-12));  // the brute force's points are points too
  EXPECT_LE(d.max, reference + error) << "sampled densely, the brute force comes within the bound";
  EXPECT_GT(reference, 0.001 * diagonal(a));
}

TEST(Hausdorff, AgreesWithCgalsBoundedErrorDistanceOnRealMeshes) {
  for (const Mesh& mesh : real_meshes()) {
    const Mesh moved = deformed(mesh, 0.01);
    const double error = 1e-4 * diagonal(mesh);
    const double cgal = cgal_hausdorff(mesh, moved, error);
    const MeshDifference d = compare_hausdorff(mesh, moved, {cgal, error, 0});
    EXPECT_NEAR(d.max, cgal, 2 * error) << mesh.source();
    EXPECT_LE(d.max_upper - d.max, error) << mesh.source();
  }
}

// `mesh` and its FFD with the lattice point moved by `by` times the diagonal, compared at
// tolerances that put the distance at 0.9 and at 1.1 of them.
void expect_decisions(const Mesh& mesh, double by) {
  const Mesh moved = deformed(mesh, by);
  // The distance to within 1e-3 of the lattice point's move, by CGAL's bounded-error
  // algorithm: far inside the 10% either side of the tolerance.
  const double error = 1e-3 * by * diagonal(mesh);
  const double h = cgal_hausdorff(mesh, moved, error);
  ASSERT_GT(h, 50 * error) << mesh.source();
  CompareOptions options;
  options.metric = "hausdorff";
  options.tolerance = h / 0.9;  // the distance at 0.9 of the tolerance
  EXPECT_TRUE(within_tolerance(compare_meshes(mesh, moved, options), options.tolerance)) << mesh.source() << " " << by;
  options.tolerance = h / 1.1;  // at 1.1 of it
  EXPECT_FALSE(within_tolerance(compare_meshes(mesh, moved, options), options.tolerance)) << mesh.source() << " " << by;
}

TEST(Hausdorff, DecidesPairsJustUnderAndJustOverTheTolerance) {
  for (const Mesh& mesh : real_meshes())
    for (const double by : {0.003, 0.03}) expect_decisions(mesh, by);
}

TEST(Hausdorff, DecidesPairsJustUnderAndJustOverTheToleranceOnTheSharedMeshes) {
  for (const Mesh& mesh : real_meshes(kSharedMeshes)) expect_decisions(mesh, 0.03);
}

TEST(Hausdorff, AMeshAgainstItselfIsZeroAndThreadsChangeNoBit) {
  for (const Mesh& mesh : real_meshes()) {
    const MeshDifference same = compare_hausdorff(mesh, mesh, {0, 1e-9, 0});
    EXPECT_EQ(same.max, 0) << mesh.source();
    EXPECT_EQ(same.max_upper, 0) << mesh.source();
    EXPECT_FALSE(same.larger);
    const Mesh moved = deformed(mesh, 0.02);
    const MeshDifference one = compare_hausdorff(mesh, moved, {1e-3, 1e-5 * diagonal(mesh), 1});
    const MeshDifference two = compare_hausdorff(mesh, moved, {1e-3, 1e-5 * diagonal(mesh), 2});
    EXPECT_EQ(one.max, two.max);
    EXPECT_EQ(one.max_upper, two.max_upper);
    EXPECT_EQ(one.mean, two.mean);
    EXPECT_EQ(one.points, two.points);
    ASSERT_EQ(one.distances.size(), two.distances.size());
    for (std::size_t v = 0; v < one.distances.size(); ++v)
      ASSERT_TRUE(one.distances[v] == two.distances[v] || (std::isnan(one.distances[v]) && std::isnan(two.distances[v])));
  }
}

}  // namespace
}  // namespace ffd
