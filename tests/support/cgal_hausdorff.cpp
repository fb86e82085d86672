#include "support/cgal_hausdorff.h"

#include "mesh/halfedge_view_cgal.h"  // CGAL's kernel before its distance functions

#include <CGAL/Polygon_mesh_processing/distance.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "mesh/mesh.h"

namespace ffd {
namespace {

using Triangle = std::array<Point3, 3>;

// The polygons of `m` fanned from their first corners.
std::vector<Triangle> fanned_triangles(const Mesh& m) {
  std::vector<Triangle> out;
  const MeshElements& el = m.elements();
  const ConstVec3Array p = m.positions();
  for (std::size_t e = 0; e < el.size(); ++e) {
    if (el.kinds[e] != ElementKind::Polygon) continue;
    const std::uint32_t* v = el.vertices(e);
    for (std::uint32_t i = 1; i + 1 < el.degree(e); ++i)
      out.push_back({to_point(p.col(v[0])), to_point(p.col(v[i])), to_point(p.col(v[i + 1]))});
  }
  return out;
}

// The triangles as a soup: each with corners of its own.
SurfaceMesh soup_of(const std::vector<Triangle>& triangles) {
  SurfaceMesh soup;
  for (const Triangle& t : triangles)
    soup.add_face(soup.add_vertex(t[0]), soup.add_vertex(t[1]), soup.add_vertex(t[2]));
  return soup;
}

double nearest_squared(const Point3& q, const std::vector<Triangle>& to, const std::vector<CGAL::Bbox_3>& boxes) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t b = 0; b < to.size(); ++b) {
    double box = 0;  // the squared distance from q to triangle b's box
    for (int i = 0; i < 3; ++i) {
      const double d = std::max({boxes[b].min(i) - q[i], q[i] - boxes[b].max(i), 0.0});
      box += d * d;
    }
    if (box < best) best = std::min(best, CGAL::squared_distance(q, Kernel::Triangle_3(to[b][0], to[b][1], to[b][2])));
  }
  return best;
}

}  // namespace

double cgal_hausdorff(const Mesh& a, const Mesh& b, double error) {
  namespace PMP = CGAL::Polygon_mesh_processing;
  const SurfaceMesh sa = soup_of(fanned_triangles(a)), sb = soup_of(fanned_triangles(b));
  return std::max(PMP::bounded_error_Hausdorff_distance<CGAL::Sequential_tag>(sa, sb, error),
                  PMP::bounded_error_Hausdorff_distance<CGAL::Sequential_tag>(sb, sa, error));
}

double brute_force_directed_hausdorff(const Mesh& from, const Mesh& to, int samples) {
  const std::vector<Triangle> f = fanned_triangles(from), t = fanned_triangles(to);
  std::vector<CGAL::Bbox_3> boxes;
  for (const Triangle& tri : t) boxes.push_back(tri[0].bbox() + tri[1].bbox() + tri[2].bbox());
  double worst = 0;
  for (const Triangle& tri : f)
    for (int i = 0; i <= samples; ++i)
      for (int j = 0; i + j <= samples; ++j) {
        const int k = samples - i - j;
        const Point3 q((i * tri[0].x() + j * tri[1].x() + k * tri[2].x()) / samples,
                       (i * tri[0].y() + j * tri[1].y() + k * tri[2].y()) / samples,
                       (i * tri[0].z() + j * tri[1].z() + k * tri[2].z()) / samples);
        worst = std::max(worst, std::sqrt(nearest_squared(q, t, boxes)));
      }
  return worst;
}

}  // namespace ffd
