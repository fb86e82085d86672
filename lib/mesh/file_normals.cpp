#include "mesh/file_normals.h"

#include <map>

namespace ffd {

CornerNormals transformed_file_normals(const Mesh& mesh, const NormalTransform& transform) {
  const MeshElements& el = mesh.elements();
  const std::vector<Eigen::Vector3d>& file_normals = mesh.file_normals();
  CornerNormals result;
  if (!mesh.has_file_normals() || el.corner_normals.empty()) {
    result.table = file_normals;  // no corner has one: `corner` stays empty
    return result;
  }
  result.corner.assign(el.corners.size(), -1);
  std::vector<std::vector<Eigen::Vector3d>> values(file_normals.size());
  std::vector<std::pair<std::int64_t, std::size_t>> slot_of(el.corners.size(), {-1, 0});
  std::map<std::pair<std::int32_t, std::uint32_t>, std::size_t> memo;  // (entry, vertex) -> slot
  for (std::size_t c = 0; c < el.corners.size(); ++c) {
    const std::int32_t k = el.corner_normals[c];
    if (k < 0) continue;
    const std::uint32_t v = el.corners[c];
    auto [it, inserted] = memo.try_emplace({k, v}, 0);
    if (inserted) {
      Eigen::Vector3d n = file_normals[k];
      if (transform) n = transform(v, n);
      std::vector<Eigen::Vector3d>& list = values[k];
      std::size_t slot = 0;
      while (slot < list.size() && list[slot] != n) ++slot;
      if (slot == list.size()) list.push_back(n);
      it->second = slot;
    }
    slot_of[c] = {k, it->second};
  }
  std::vector<std::size_t> first(values.size(), 0);
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (values[k].empty()) values[k].push_back(file_normals[k]);
    first[k] = result.table.size();
    result.table.insert(result.table.end(), values[k].begin(), values[k].end());
  }
  for (std::size_t c = 0; c < slot_of.size(); ++c)
    if (slot_of[c].first >= 0)
      result.corner[c] = static_cast<std::int64_t>(first[slot_of[c].first] + slot_of[c].second);
  return result;
}

void bake_file_normals(Mesh& mesh, const NormalTransform& transform) {
  if (!mesh.has_file_normals()) return;
  CornerNormals baked = transformed_file_normals(mesh, transform);
  mesh.file_normals() = std::move(baked.table);
  mesh.file_normal_count = mesh.file_normals().size();
  std::vector<std::int32_t>& corner = mesh.corner_data().corner_normals;
  if (corner.empty()) return;
  for (std::size_t c = 0; c < corner.size(); ++c) corner[c] = static_cast<std::int32_t>(baked.corner[c]);
}

VertexFileNormals vertex_file_normals(const Mesh& mesh, const NormalTransform& transform) {
  const MeshElements& el = mesh.elements();
  VertexFileNormals out;
  out.value.assign(mesh.num_vertices(), Eigen::Vector3d::Zero());
  out.has.assign(mesh.num_vertices(), 0);
  out.moved.assign(mesh.num_vertices(), 0);
  const auto take = [&](std::uint32_t v, const Eigen::Vector3d& n) {
    out.value[v] = transform ? transform(v, n) : n;
    out.moved[v] = out.value[v] != n;
    out.has[v] = 1;
  };
  for (std::size_t c = 0; c < el.corners.size() && !el.corner_normals.empty(); ++c) {
    const std::uint32_t v = el.corners[c];
    if (!out.has[v] && el.corner_normals[c] >= 0) take(v, mesh.file_normals()[el.corner_normals[c]]);
  }
  // A PLY's or NOFF's normals are one per vertex (their readers make the table so): a
  // vertex in no element, a point of a cloud, has its own too.
  if ((mesh.file_normals_per_vertex || mesh.ply_source_as_read()) && mesh.file_normals().size() == mesh.num_vertices())
    for (std::uint32_t v = 0; v < out.has.size(); ++v)
      if (!out.has[v]) take(v, mesh.file_normals()[v]);
  return out;
}

}  // namespace ffd
