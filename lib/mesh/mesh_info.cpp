#include "mesh/mesh_info.h"

#include <CGAL/Polygon_mesh_processing/connected_components.h>

#include <cmath>
#include <limits>

#include "mesh/mesh_storage.h"

namespace ffd {

MeshInfo mesh_info(const Mesh& mesh) {
  const SurfaceMesh& sm = mesh.storage().sm;
  MeshInfo info;
  info.vertices = sm.number_of_vertices();
  info.faces = sm.number_of_faces();
  info.edges = sm.number_of_edges();
  info.euler = static_cast<long>(info.vertices) - static_cast<long>(info.edges) + static_cast<long>(info.faces);
  info.has_uvs = mesh.has_uvs();
  info.has_normals = mesh.has_file_normals();
  info.has_colors = mesh.has_colors();
  const ConstVec3Array p = mesh.positions();
  if (p.cols() > 0) {
    info.min = p.rowwise().minCoeff();
    info.max = p.rowwise().maxCoeff();
    info.diagonal = (info.max - info.min).norm();
  }
  for (FaceIndex f : sm.faces()) {
    ++info.faces_by_degree[sm.degree(f)];
    Eigen::Vector3d area = Eigen::Vector3d::Zero();
    HalfedgeIndex h0 = sm.halfedge(f);
    const Eigen::Vector3d o = p.col(sm.target(h0).idx());
    for (HalfedgeIndex h = sm.next(h0); sm.next(h) != h0; h = sm.next(h))
      area += (p.col(sm.target(h).idx()) - o).cross(p.col(sm.target(sm.next(h)).idx()) - o);
    if (!(area.norm() > 0)) ++info.degenerate_faces;
  }
  double sum = 0;
  info.min_edge = std::numeric_limits<double>::infinity();
  for (EdgeIndex e : sm.edges()) {
    const HalfedgeIndex h = sm.halfedge(e);
    const double len = (p.col(sm.target(h).idx()) - p.col(sm.source(h).idx())).norm();
    sum += len;
    info.min_edge = std::min(info.min_edge, len);
    info.max_edge = std::max(info.max_edge, len);
    if (sm.is_border(e)) ++info.boundary_edges;
  }
  if (info.edges == 0) info.min_edge = 0;
  info.mean_edge = info.edges ? sum / static_cast<double>(info.edges) : 0;
  std::vector<bool> seen(sm.number_of_halfedges(), false);
  for (HalfedgeIndex h : sm.halfedges()) {
    if (!sm.is_border(h) || seen[h.idx()]) continue;
    ++info.boundary_loops;
    for (HalfedgeIndex g : CGAL::halfedges_around_face(h, sm)) seen[g.idx()] = true;
  }
  for (VertexIndex v : sm.vertices()) info.isolated_vertices += sm.is_isolated(v);
  if (info.faces) {
    // A scratch property, removed before returning (the mesh is logically unchanged).
    SurfaceMesh& scratch = const_cast<SurfaceMesh&>(sm);
    auto component = scratch.add_property_map<FaceIndex, std::size_t>("f:ffd_component", 0).first;
    info.components = CGAL::Polygon_mesh_processing::connected_components(sm, component);
    scratch.remove_property_map(component);
  }
  return info;
}

}  // namespace ffd
