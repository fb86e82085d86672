// What a Mesh is made of: a CGAL::Surface_mesh and its property maps. Include this only
// in .cpp files that need connectivity (I/O, remeshing, BCM); it costs seconds of compile.
//
// Conventions:
// - sm.points() holds the current (deformed) positions;
// - a corner of a face is the halfedge h with face(h) == f, at vertex target(h);
// - "h:uv" / "h:vn" hold per-corner indices into `uvs` / `file_normals`, -1 for none;
// - "f:group" indexes `groups` (OBJ statements in force for the face), -1 for none;
// - the declared attributes of mesh.h (mesh_attribute::*) are properties of those names.
// The mesh never keeps garbage between steps: an op that removes elements calls
// sm.collect_garbage() before it returns, so indices are dense 0..n-1.
#pragma once

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>

#include <Eigen/Dense>

#include "mesh/soup.h"
#include <string>
#include <vector>

namespace ffd {

using Kernel = CGAL::Simple_cartesian<double>;
using Point3 = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point3>;
using VertexIndex = SurfaceMesh::Vertex_index;
using HalfedgeIndex = SurfaceMesh::Halfedge_index;
using EdgeIndex = SurfaceMesh::Edge_index;
using FaceIndex = SurfaceMesh::Face_index;

/// A per-vertex 3-vector property; unlike Mesh's 3 × n views it stays valid through
/// connectivity changes (Euler operations), so code that adds vertices holds these.
using Vec3Property = SurfaceMesh::Property_map<VertexIndex, Eigen::Vector3d>;

static_assert(sizeof(Point3) == 3 * sizeof(double), "Point_3 must be three packed doubles");
static_assert(sizeof(Eigen::Vector3d) == 3 * sizeof(double), "Vector3d must be packed");

struct MeshStorage {
  MeshStorage();
  /// Copies everything, re-binding the property maps to the copy.
  MeshStorage(const MeshStorage& other);
  MeshStorage& operator=(const MeshStorage&) = delete;

  SurfaceMesh sm;
  SurfaceMesh::Property_map<VertexIndex, Eigen::Vector3d> rest;
  SurfaceMesh::Property_map<VertexIndex, Eigen::Vector3d> rest_normal;
  SurfaceMesh::Property_map<VertexIndex, Eigen::Vector3d> normal;
  SurfaceMesh::Property_map<VertexIndex, Eigen::Vector3f> color;  // valid if has_colors
  SurfaceMesh::Property_map<HalfedgeIndex, std::int32_t> uv;
  SurfaceMesh::Property_map<HalfedgeIndex, std::int32_t> vn;
  SurfaceMesh::Property_map<FaceIndex, std::int32_t> group;

  std::vector<Eigen::Vector2d> uvs;
  std::vector<Eigen::Vector3d> file_normals;  // rest space; transformed on save
  std::vector<ObjState> groups;
  std::vector<std::string> header;
  bool has_uvs = false;
  bool has_file_normals = false;
  bool has_colors = false;
  std::uint64_t topology_version = 0;
  // Table sizes as read from the file: entries past these were made by refinement and are
  // dropped again when no corner uses them.
  std::size_t file_uv_count = 0;
  std::size_t file_normal_count = 0;

  /// Binds the property maps by name (after construction or a copy).
  void bind();
  /// Adds the colour map if missing and sets has_colors.
  void enable_colors();
  /// The property behind Mesh::vec3_attribute(name), created (zero) if missing.
  Vec3Property vec3_attribute(const std::string& name);
};

/// The current positions as a 3 × n array over sm.points().
inline Eigen::Map<Eigen::Matrix3Xd> point_array(SurfaceMesh& sm) {
  return {const_cast<double*>(reinterpret_cast<const double*>(sm.points().data())), 3,
          static_cast<Eigen::Index>(sm.number_of_vertices())};
}

inline Eigen::Vector3d to_eigen(const Point3& p) { return {p.x(), p.y(), p.z()}; }
inline Point3 to_point(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace ffd
