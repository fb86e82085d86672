#include "support/cgal_hausdorff.h"

#include <CGAL/Polygon_mesh_processing/distance.h>

#include <algorithm>
#include <array>

#include "mesh/surface_index.h"

namespace ffd {

SurfaceMesh triangle_soup(const Mesh& m) {
  SurfaceMesh soup;
  const SurfaceIndex index(m);
  for (std::uint32_t t = 0; t < index.num_triangles(); ++t) {
    std::array<VertexIndex, 3> v;
    for (int i = 0; i < 3; ++i) v[i] = soup.add_vertex(to_point(index.point(index.triangle(t)[i])));
    soup.add_face(v[0], v[1], v[2]);
  }
  return soup;
}

double cgal_hausdorff(const Mesh& a, const Mesh& b, double error) {
  namespace PMP = CGAL::Polygon_mesh_processing;
  const SurfaceMesh sa = triangle_soup(a), sb = triangle_soup(b);
  return std::max(PMP::bounded_error_Hausdorff_distance<CGAL::Sequential_tag>(sa, sb, error),
                  PMP::bounded_error_Hausdorff_distance<CGAL::Sequential_tag>(sb, sa, error));
}

}  // namespace ffd
