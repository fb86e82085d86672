// The declared per-vertex arrays (FFD_MESH_VERTEX_ARRAYS): clone copies each, resizing
// gives new vertices each array's default, and a halfedge view built from a mesh and
// written back unchanged leaves every array as it was, bit for bit.
#include <gtest/gtest.h>

#include <random>

#include "mesh/halfedge_view_cgal.h"
#include "test_meshes.h"

namespace ffd {
namespace {

bool same(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b) {
  return a.cols() == b.cols() && (a.cols() == 0 || (a.array() == b.array()).all());
}
template <class T>
bool same(const std::vector<T>& a, const std::vector<T>& b) {
  return a == b;
}

/// The bunny with every declared array holding something other than its default.
Mesh decorated_bunny() {
  Mesh mesh = test::bunny();
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0, 1);
  mesh.colors().resize(mesh.num_vertices());
  for (Eigen::Vector3f& c : mesh.colors()) c = Eigen::Vector3f(u(rng), u(rng), u(rng));
  mesh.vertex_levels().assign(mesh.num_vertices(), 0);
  for (std::size_t v = 0; v < mesh.num_vertices(); v += 7) mesh.vertex_levels()[v] = 2;
  mesh.positions().col(5) += Eigen::Vector3d(0.25, 0, 0);  // current differs from rest
  mesh.normals().col(5) = Eigen::Vector3d(0, 1, 0);
  mesh.vec3_attribute("extra").setConstant(1.5);
  return mesh;
}

TEST(MeshAttributes, CloneCopiesEveryDeclaredArray) {
  const Mesh mesh = decorated_bunny();
  const Mesh copy = mesh.clone();
  int arrays = 0;
  Mesh::for_each_vertex_array([&](const auto& a) {
    ++arrays;
    EXPECT_TRUE(same(mesh.*a.member, copy.*a.member)) << a.name;
    EXPECT_GT((mesh.*a.member).size(), 0) << a.name;
  });
  EXPECT_EQ(arrays, 6);
  EXPECT_TRUE(same(Eigen::Matrix3Xd(mesh.vec3_attribute("extra")), Eigen::Matrix3Xd(copy.vec3_attribute("extra"))));
  EXPECT_EQ(mesh.attribute_names(), copy.attribute_names());
}

TEST(MeshAttributes, NewVerticesGetEachArraysDefault) {
  Mesh mesh = decorated_bunny();
  Mesh plain = test::bunny();  // its optional arrays (colours, levels) are absent
  const std::size_t n = mesh.num_vertices();
  mesh.resize_vertices(n + 3);
  plain.resize_vertices(n + 3);
  Mesh::for_each_vertex_array([&](const auto& a) {
    const auto& array = mesh.*a.member;
    if constexpr (std::is_same_v<std::decay_t<decltype(array)>, Eigen::Matrix3Xd>) {
      EXPECT_EQ(static_cast<std::size_t>(array.cols()), n + 3) << a.name;
      for (Eigen::Index v = static_cast<Eigen::Index>(n); v < array.cols(); ++v)
        EXPECT_EQ(Eigen::Vector3d(array.col(v)), a.fallback) << a.name;
    } else {
      EXPECT_EQ(array.size(), n + 3) << a.name;
      for (std::size_t v = n; v < array.size(); ++v) EXPECT_EQ(array[v], a.fallback) << a.name;
      EXPECT_EQ((plain.*a.member).size(), a.optional ? 0u : n + 3) << a.name << ": an absent array stays absent";
    }
  });
}

TEST(MeshAttributes, AHalfedgeViewWrittenBackUnchangedKeepsEveryArray) {
  Mesh mesh = decorated_bunny();
  const Mesh before = mesh.clone();
  HalfedgeCache cache;
  HalfedgeView& view = halfedge_view(mesh, cache);
  EXPECT_TRUE(view.has_colors);
  write_back(view, mesh, false, cache);
  EXPECT_TRUE(cache.valid_for(mesh));
  Mesh::for_each_vertex_array(
      [&](const auto& a) { EXPECT_TRUE(same(before.*a.member, mesh.*a.member)) << a.name << " changed"; });
  EXPECT_TRUE(same(Eigen::Matrix3Xd(before.vec3_attribute("extra")), Eigen::Matrix3Xd(mesh.vec3_attribute("extra"))));
  EXPECT_EQ(before.faces(), mesh.faces());
  // A clone of the cache is a separate view of the same mesh.
  const HalfedgeCache copy = cache.clone();
  ASSERT_NE(copy.view(), nullptr);
  EXPECT_NE(copy.view(), cache.view());
  EXPECT_EQ(copy.view()->sm.number_of_faces(), cache.view()->sm.number_of_faces());
  EXPECT_TRUE(copy.valid_for(mesh));
}

}  // namespace
}  // namespace ffd
