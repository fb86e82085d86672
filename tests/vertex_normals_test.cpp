// Angle-weighted vertex normals (lib/mesh/vertex_normals.cpp, SLEEF's vector atan2 in
// batches of triangles) against the textbook formula written out here with std::atan2 at
// every corner, on the bunny, a bumpy quad grid and a mesh of mixed polygon sizes.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>

#include "mesh/build_mesh.h"
#include "mesh/mesh_io.h"
#include "mesh/vertex_normals.h"
#include "test_meshes.h"

namespace ffd {
namespace {

// Σ over a vertex's polygons of (angle at the vertex) × (unit Newell normal), normalized.
Eigen::Matrix3Xd reference_normals(const Mesh& mesh) {
  const ConstVec3Array p = mesh.positions();
  Eigen::Matrix3Xd out = Eigen::Matrix3Xd::Zero(3, p.cols());
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    std::vector<std::uint32_t> ids;
    mesh.face_vertices(f, ids);
    const std::size_t n = ids.size();
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < n; ++i) normal += Eigen::Vector3d(p.col(ids[i])).cross(p.col(ids[(i + 1) % n]));
    if (normal.norm() == 0) continue;
    normal.normalize();
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d a = p.col(ids[(i + n - 1) % n]) - p.col(ids[i]);
      const Eigen::Vector3d b = p.col(ids[(i + 1) % n]) - p.col(ids[i]);
      out.col(ids[i]) += std::atan2(a.cross(b).norm(), a.dot(b)) * normal;
    }
  }
  for (Eigen::Index v = 0; v < out.cols(); ++v)
    if (out.col(v).norm() > 0) out.col(v).normalize();
  return out;
}

double max_difference(const Mesh& mesh) {
  return (vertex_normals(mesh, mesh.positions()) - reference_normals(mesh)).cwiseAbs().maxCoeff();
}

TEST(VertexNormals, AgreeWithTheTextbookFormulaOnTheBunny) {
  EXPECT_LT(max_difference(test::bunny()), 1e-13);
}

TEST(VertexNormals, AgreeWithTheTextbookFormulaOnQuadsAndMixedPolygons) {
  const Mesh quads = test::grid_mesh(12, [](double x, double y) { return 0.1 * std::sin(5 * x) * std::cos(3 * y); }, true);
  EXPECT_LT(max_difference(quads), 1e-13);
  // Triangles, a quad and a pentagon around a shared apex, and a degenerate triangle.
  PolygonSoup soup;
  soup.positions = {{0, 0, 0.2}, {1, 0, 0}, {0.8, 0.9, 0.1}, {-0.2, 1, 0}, {-1, 0.1, 0.05}, {-0.5, -0.9, 0},
                    {0.6, -1, 0.1}, {2, 0, 0}, {1.5, 1.5, 0.3}, {1.5, 0, 0}};
  soup.elements.add_polygon({0, 1, 2});
  soup.elements.add_polygon({0, 2, 3});
  soup.elements.add_polygon({0, 3, 4, 5});
  soup.elements.add_polygon({1, 9, 7});  // collinear: no area, no contribution
  soup.elements.add_polygon({0, 5, 6, 7, 8});
  EXPECT_LT(max_difference(build_mesh(soup, "mixed")), 1e-13);
}

TEST(VertexNormals, AFoldBisectsWhereTheAnglesAreEqual) {
  // Two triangles folded along the edge 0-1 by 90 degrees: the shared vertices' normal
  // bisects the two face normals (equal angles there), the others keep their face's.
  PolygonSoup soup;
  soup.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  soup.elements.add_polygon({0, 1, 2});  // normal +z
  soup.elements.add_polygon({1, 0, 3});  // normal +y
  const Mesh mesh = build_mesh(soup, "fold");
  const Eigen::Matrix3Xd n = vertex_normals(mesh, mesh.positions());
  EXPECT_LT((n.col(2) - Eigen::Vector3d(0, 0, 1)).norm(), 1e-15);
  EXPECT_LT((n.col(3) - Eigen::Vector3d(0, 1, 0)).norm(), 1e-15);
  for (int v : {0, 1}) EXPECT_LT((n.col(v) - Eigen::Vector3d(0, 1, 1).normalized()).norm(), 1e-15) << v;
}

}  // namespace
}  // namespace ffd

namespace ffd {
namespace {

// A run whose steps and outputs need no vertex normals reads the mesh without them
// (Mesh::normals_deferred); computed later, before any warp, they are the ones a plain
// read computes, bit for bit. A file with normals of its own is deferred too: the runner
// computes them when its normals miss a vertex, which a writer fills in from the computed
// ones (file_normals_test.cpp).
TEST(VertexNormals, DeferredNormalsAreTheOnesComputedAtRead) {
  const std::string bunny = test::data("bunny.obj");
  const Mesh eager = read_mesh(bunny);
  Mesh deferred = read_mesh(bunny, /*defer_normals=*/true);
  EXPECT_FALSE(eager.normals_deferred());
  ASSERT_TRUE(deferred.normals_deferred());
  EXPECT_TRUE(deferred.normals().isZero(0.0));
  deferred.compute_deferred_normals();
  EXPECT_FALSE(deferred.normals_deferred());
  EXPECT_TRUE((deferred.normals().array() == eager.normals().array()).all());
  EXPECT_TRUE((deferred.rest_normals().array() == eager.rest_normals().array()).all());
  EXPECT_TRUE(read_mesh(test::data("gltf/scene_world.obj"), true).normals_deferred());
}

}  // namespace
}  // namespace ffd
