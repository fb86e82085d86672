#include "mesh/surface_index.h"

namespace ffd {

SurfaceIndex::SurfaceIndex(const Mesh& mesh) : mesh_(mesh), vertex_triangle_(mesh.num_vertices(), kNone) {
  const MeshElements& el = mesh.elements();
  for (std::size_t e = 0; e < el.size(); ++e) {
    if (el.kinds[e] != ElementKind::Polygon) continue;
    const std::uint32_t* v = el.vertices(e);
    for (std::uint32_t i = 1; i + 1 < el.degree(e); ++i) {
      const auto t = static_cast<std::uint32_t>(triangles_.size());
      triangles_.push_back({v[0], v[i], v[i + 1]});
      for (const std::uint32_t corner : triangles_.back())
        if (vertex_triangle_[corner] == kNone) vertex_triangle_[corner] = t;
    }
  }
  tree_ = TriangleBvh(mesh.positions().data(), &triangles_);
}

}  // namespace ffd
