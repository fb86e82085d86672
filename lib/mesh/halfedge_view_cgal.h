// The halfedge view of a Mesh's polygons: a CGAL::Surface_mesh and its property maps,
// built (checked) by halfedge_view(), written back by write_back(). Include this only in
// .cpp files that need connectivity (remeshing, BCM's parameterization, compare); it
// costs seconds of compile.
//
// Conventions:
// - vertex i is the mesh's vertex i; face f is the mesh's polygon element face_element[f];
// - sm.points() holds the current (deformed) positions;
// - a corner of a face is the halfedge h with face(h) == f, at vertex target(h);
//   sm.halfedge(f) is the corner at start[f], the vertex the element's corners start at;
// - "h:uv" / "h:vn" hold per-corner indices into `uvs` / `file_normals`, -1 for none;
// - "f:group" indexes the mesh's groups, -1 for none;
// - the declared attributes of mesh.h (mesh_attribute::*) are properties of those names,
//   vec3 attributes are "v:attr:NAME".
// An op that removes elements calls sm.collect_garbage() before write_back.
#pragma once

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>

#include <Eigen/Dense>

#include <string>
#include <vector>

#include "mesh/halfedge_view.h"

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

struct HalfedgeView {
  HalfedgeView();
  /// Copies everything, re-binding the property maps to the copy.
  HalfedgeView(const HalfedgeView& other);
  HalfedgeView& operator=(const HalfedgeView&) = delete;

  SurfaceMesh sm;
  SurfaceMesh::Property_map<VertexIndex, Eigen::Vector3d> rest;
  SurfaceMesh::Property_map<VertexIndex, Eigen::Vector3d> rest_normal;
  SurfaceMesh::Property_map<VertexIndex, Eigen::Vector3d> normal;
  SurfaceMesh::Property_map<VertexIndex, Eigen::Vector3f> color;  // valid if has_colors
  SurfaceMesh::Property_map<HalfedgeIndex, std::int32_t> uv;
  SurfaceMesh::Property_map<HalfedgeIndex, std::int32_t> vn;
  SurfaceMesh::Property_map<FaceIndex, std::int32_t> group;
  SurfaceMesh::Property_map<VertexIndex, RefinementLevel> vertex_level;
  SurfaceMesh::Property_map<EdgeIndex, RefinementLevel> edge_level;
  SurfaceMesh::Property_map<FaceIndex, std::uint32_t> start;

  std::vector<Eigen::Vector2d> uvs;
  std::vector<Eigen::Vector3d> file_normals;  // rest space
  std::size_t file_uv_count = 0;
  std::size_t file_normal_count = 0;
  bool has_colors = false;
  std::vector<std::uint32_t> face_element;  // the mesh element of each face

  /// Binds the property maps by name (after construction, a copy or a sync); has_colors
  /// says whether the colour map exists.
  void bind();
  /// Adds the colour map if missing and sets has_colors.
  void enable_colors();
  /// The property holding Mesh::vec3_attribute(name), created (zero) if missing.
  Vec3Property vec3_attribute(const std::string& name);
};

/// The checked halfedge view of `mesh`'s polygons (check_two_manifold), up to date with
/// its arrays (every array of FFD_MESH_VERTEX_ARRAYS, the vec3 attributes, corner data,
/// edge levels): `cache`'s view when the connectivity is as it left it, else built anew
/// and kept in `cache`. Lines and points are not in it.
/// \throw TopologyError as check_two_manifold says.
HalfedgeView& halfedge_view(Mesh& mesh, HalfedgeCache& cache);

/// Writes the view's vertices (every array of FFD_MESH_VERTEX_ARRAYS the view has, vec3
/// attributes), tables and, when `connectivity_changed`, its faces back into `mesh`'s
/// arrays: faces take the polygon elements' places in order (lines and points stay where
/// they were; faces beyond the old count follow them); `cache` keeps `view` as up to date.
/// \pre the view has no garbage.
void write_back(HalfedgeView& view, Mesh& mesh, bool connectivity_changed, HalfedgeCache& cache);

/// A plain Surface_mesh of `mesh`'s polygons at their current positions (checked as
/// halfedge_view does), for tools that hand a mesh to CGAL (benchmarks, oracles).
SurfaceMesh surface_mesh(const Mesh& mesh);

/// A Mesh of `sm`'s vertices and faces, in index order (sm has no garbage).
Mesh mesh_from_surface(const SurfaceMesh& sm, const std::string& source);

inline Eigen::Vector3d to_eigen(const Point3& p) { return {p.x(), p.y(), p.z()}; }
inline Point3 to_point(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace ffd
