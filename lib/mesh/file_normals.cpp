#include "mesh/file_normals.h"

#include <map>

#include "mesh/mesh_storage.h"

namespace ffd {

CornerNormals transformed_file_normals(const Mesh& mesh, const NormalTransform& transform) {
  const MeshStorage& s = mesh.storage();
  const SurfaceMesh& sm = s.sm;
  CornerNormals result;
  result.corner.assign(sm.number_of_halfedges(), -1);
  if (!s.has_file_normals) return result;

  std::vector<std::vector<Eigen::Vector3d>> values(s.file_normals.size());
  std::vector<std::pair<std::int64_t, std::size_t>> slot_of(sm.number_of_halfedges(), {-1, 0});
  std::map<std::pair<std::int32_t, std::uint32_t>, std::size_t> memo;  // (entry, vertex) -> slot
  for (FaceIndex f : sm.faces())
    for (HalfedgeIndex h : CGAL::halfedges_around_face(sm.halfedge(f), sm)) {
      const std::int32_t k = s.vn[h];
      if (k < 0) continue;
      const std::uint32_t v = sm.target(h).idx();
      auto [it, inserted] = memo.try_emplace({k, v}, 0);
      if (inserted) {
        Eigen::Vector3d n = s.file_normals[k];
        if (transform) n = transform(v, n);
        std::vector<Eigen::Vector3d>& list = values[k];
        std::size_t slot = 0;
        while (slot < list.size() && list[slot] != n) ++slot;
        if (slot == list.size()) list.push_back(n);
        it->second = slot;
      }
      slot_of[h.idx()] = {k, it->second};
    }
  std::vector<std::size_t> first(values.size(), 0);
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (values[k].empty()) values[k].push_back(s.file_normals[k]);
    first[k] = result.table.size();
    result.table.insert(result.table.end(), values[k].begin(), values[k].end());
  }
  for (std::size_t h = 0; h < slot_of.size(); ++h)
    if (slot_of[h].first >= 0)
      result.corner[h] = static_cast<std::int64_t>(first[slot_of[h].first] + slot_of[h].second);
  return result;
}

void bake_file_normals(Mesh& mesh, const NormalTransform& transform) {
  if (!mesh.has_file_normals()) return;
  CornerNormals baked = transformed_file_normals(mesh, transform);
  MeshStorage& s = mesh.storage();
  s.file_normals = std::move(baked.table);
  s.file_normal_count = s.file_normals.size();
  for (HalfedgeIndex h : s.sm.halfedges()) s.vn[h] = static_cast<std::int32_t>(baked.corner[h.idx()]);
}

}  // namespace ffd
