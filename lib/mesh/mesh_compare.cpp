#include "mesh/mesh_compare.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Polygon_mesh_processing/distance.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>

#include <cmath>

#include "mesh/mesh_storage.h"

namespace ffd {
namespace PMP = CGAL::Polygon_mesh_processing;

MeshDifference compare_vertices(const Mesh& a, const Mesh& b) {
  MeshDifference d;
  d.metric = "vertex";
  if (a.num_vertices() != b.num_vertices()) {
    d.comparable = false;
    d.reason = "vertex counts differ (" + std::to_string(a.num_vertices()) + " vs " +
               std::to_string(b.num_vertices()) + "); use --metric hausdorff";
    return d;
  }
  const ConstVec3Array pa = a.positions(), pb = b.positions();
  double sum = 0, sum2 = 0;
  for (Eigen::Index i = 0; i < pa.cols(); ++i) {
    const double e = (pa.col(i) - pb.col(i)).norm();
    sum += e;
    sum2 += e * e;
    if (e > d.max) {
      d.max = e;
      d.worst_vertex = static_cast<std::size_t>(i);
    }
  }
  const double n = std::max<double>(1, static_cast<double>(pa.cols()));
  d.mean = sum / n;
  d.rms = std::sqrt(sum2 / n);
  d.same_connectivity = a.faces() == b.faces();
  if (!d.same_connectivity)
    d.reason = "face lists differ (" + std::to_string(a.num_faces()) + " vs " + std::to_string(b.num_faces()) +
               " faces)";
  return d;
}

namespace {

SurfaceMesh triangulated(const Mesh& m) {
  SurfaceMesh copy = m.storage().sm;
  PMP::triangulate_faces(copy);
  return copy;
}

// Distances from every vertex of `from` to the surface `to`.
void vertex_to_surface(const SurfaceMesh& from, const SurfaceMesh& to, double& sum, double& sum2, std::size_t& n) {
  using Primitive = CGAL::AABB_face_graph_triangle_primitive<SurfaceMesh>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
  Tree tree(faces(to).first, faces(to).second, to);
  tree.accelerate_distance_queries();
  for (VertexIndex v : from.vertices()) {
    if (from.is_isolated(v)) continue;
    const double e = std::sqrt(tree.squared_distance(from.point(v)));
    sum += e;
    sum2 += e * e;
    ++n;
  }
}

}  // namespace

MeshDifference compare_hausdorff(const Mesh& a, const Mesh& b, double error_bound) {
  MeshDifference d;
  d.metric = "hausdorff";
  if (a.num_faces() == 0 || b.num_faces() == 0) {
    d.comparable = false;
    d.reason = "the Hausdorff metric needs faces on both meshes";
    return d;
  }
  const SurfaceMesh ta = triangulated(a), tb = triangulated(b);
  const double ab = PMP::bounded_error_Hausdorff_distance<CGAL::Sequential_tag>(ta, tb, error_bound);
  const double ba = PMP::bounded_error_Hausdorff_distance<CGAL::Sequential_tag>(tb, ta, error_bound);
  d.max = std::max(ab, ba);
  double sum = 0, sum2 = 0;
  std::size_t n = 0;
  vertex_to_surface(ta, tb, sum, sum2, n);
  vertex_to_surface(tb, ta, sum, sum2, n);
  d.mean = n ? sum / n : 0;
  d.rms = n ? std::sqrt(sum2 / n) : 0;
  d.same_connectivity = a.faces() == b.faces();
  return d;
}

}  // namespace ffd
