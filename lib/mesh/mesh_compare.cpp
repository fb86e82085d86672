#include "mesh/mesh_compare.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Polygon_mesh_processing/distance.h>

#include <cmath>

#include "mesh/halfedge_view_cgal.h"

namespace ffd {
namespace PMP = CGAL::Polygon_mesh_processing;

namespace {

// True when both meshes have the same elements: kinds, sizes and vertex indices.
bool same_elements(const Mesh& a, const Mesh& b) {
  const MeshElements &ea = a.elements(), &eb = b.elements();
  return ea.kinds == eb.kinds && ea.offsets == eb.offsets && ea.corners == eb.corners;
}

}  // namespace

MeshDifference compare_vertices(const Mesh& a, const Mesh& b) {
  MeshDifference d;
  d.metric = "vertex";
  if (a.num_vertices() != b.num_vertices()) {
    d.comparable = false;
    d.reason = "vertex counts differ (" + std::to_string(a.num_vertices()) + " vs " +
               std::to_string(b.num_vertices()) + "); use --metric hausdorff";
    return d;
  }
  d.distances = vertex_distances(a, b, false);
  double sum = 0, sum2 = 0;
  for (std::size_t i = 0; i < d.distances.size(); ++i) {
    const double e = d.distances[i];
    sum += e;
    sum2 += e * e;
    if (e > d.max) {
      d.max = e;
      d.worst_vertex = i;
    }
  }
  const double n = std::max<double>(1, static_cast<double>(d.distances.size()));
  d.mean = sum / n;
  d.rms = std::sqrt(sum2 / n);
  d.same_connectivity = same_elements(a, b);
  if (!d.same_connectivity)
    d.reason = "face lists differ (" + std::to_string(a.num_faces()) + " vs " + std::to_string(b.num_faces()) +
               " faces)";
  return d;
}

namespace {

// The polygons as a triangle soup (each polygon fanned from its first corner), every
// triangle with vertices of its own: a valid Surface_mesh whatever the mesh's topology,
// and the same surface, which is all a distance needs.
SurfaceMesh triangle_soup(const Mesh& m) {
  SurfaceMesh soup;
  const MeshElements& el = m.elements();
  const ConstVec3Array p = m.positions();
  for (std::size_t e = 0; e < el.size(); ++e) {
    if (el.kinds[e] != ElementKind::Polygon) continue;
    const std::uint32_t* v = el.vertices(e);
    for (std::uint32_t i = 1; i + 1 < el.degree(e); ++i) {
      const VertexIndex a = soup.add_vertex(to_point(p.col(v[0])));
      const VertexIndex b = soup.add_vertex(to_point(p.col(v[i])));
      const VertexIndex c = soup.add_vertex(to_point(p.col(v[i + 1])));
      soup.add_face(a, b, c);
    }
  }
  return soup;
}

// The distance from every vertex of `from` that a polygon uses to the surface `to`;
// NaN for the other vertices.
std::vector<double> distances_to_surface(const Mesh& from, const SurfaceMesh& to) {
  using Primitive = CGAL::AABB_face_graph_triangle_primitive<SurfaceMesh>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
  Tree tree(faces(to).first, faces(to).second, to);
  tree.accelerate_distance_queries();
  std::vector<char> used(from.num_vertices(), 0);
  const MeshElements& el = from.elements();
  for (std::size_t e = 0; e < el.size(); ++e)
    if (el.kinds[e] == ElementKind::Polygon)
      for (std::uint32_t c = el.begin(e); c < el.end(e); ++c) used[el.corners[c]] = 1;
  const ConstVec3Array p = from.positions();
  std::vector<double> out(used.size(), std::nan(""));
  for (std::size_t v = 0; v < used.size(); ++v)
    if (used[v]) out[v] = std::sqrt(tree.squared_distance(to_point(p.col(static_cast<Eigen::Index>(v)))));
  return out;
}

// Adds the distances that are known (not NaN) to the sums and the count.
void add_distances(const std::vector<double>& distances, double& sum, double& sum2, std::size_t& n) {
  for (const double e : distances) {
    if (std::isnan(e)) continue;
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
  const SurfaceMesh ta = triangle_soup(a), tb = triangle_soup(b);
  const double ab = PMP::bounded_error_Hausdorff_distance<CGAL::Sequential_tag>(ta, tb, error_bound);
  const double ba = PMP::bounded_error_Hausdorff_distance<CGAL::Sequential_tag>(tb, ta, error_bound);
  d.max = std::max(ab, ba);
  double sum = 0, sum2 = 0;
  std::size_t n = 0;
  add_distances(distances_to_surface(a, tb), sum, sum2, n);
  d.distances = distances_to_surface(b, ta);
  add_distances(d.distances, sum, sum2, n);
  d.mean = n ? sum / n : 0;
  d.rms = n ? std::sqrt(sum2 / n) : 0;
  d.same_connectivity = same_elements(a, b);
  return d;
}

std::vector<double> vertex_distances(const Mesh& a, const Mesh& b, bool hausdorff) {
  if (hausdorff) return a.num_faces() ? distances_to_surface(b, triangle_soup(a)) : std::vector<double>();
  if (a.num_vertices() != b.num_vertices()) return {};
  std::vector<double> out(b.num_vertices());
  for (std::size_t v = 0; v < out.size(); ++v) {
    const auto i = static_cast<Eigen::Index>(v);
    out[v] = (a.positions().col(i) - b.positions().col(i)).norm();
  }
  return out;
}

}  // namespace ffd
