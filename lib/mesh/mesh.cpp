#include "mesh/mesh.h"

#include "mesh/mesh_storage.h"
#include "mesh/vertex_colors.h"
#include "mesh/vertex_normals.h"

namespace ffd {

MeshStorage::MeshStorage() {
  rest = sm.add_property_map<VertexIndex, Eigen::Vector3d>("v:rest", Eigen::Vector3d::Zero()).first;
  rest_normal =
      sm.add_property_map<VertexIndex, Eigen::Vector3d>("v:rest_normal", Eigen::Vector3d::Zero()).first;
  normal = sm.add_property_map<VertexIndex, Eigen::Vector3d>("v:normal", Eigen::Vector3d::Zero()).first;
  uv = sm.add_property_map<HalfedgeIndex, std::int32_t>("h:uv", -1).first;
  vn = sm.add_property_map<HalfedgeIndex, std::int32_t>("h:vn", -1).first;
  group = sm.add_property_map<FaceIndex, std::int32_t>("f:group", -1).first;
}

MeshStorage::MeshStorage(const MeshStorage& other)
    : sm(other.sm),
      uvs(other.uvs),
      file_normals(other.file_normals),
      groups(other.groups),
      header(other.header),
      has_uvs(other.has_uvs),
      has_file_normals(other.has_file_normals),
      has_colors(other.has_colors),
      topology_version(other.topology_version),
      file_uv_count(other.file_uv_count),
      file_normal_count(other.file_normal_count) {
  bind();
}

void MeshStorage::bind() {
  rest = sm.property_map<VertexIndex, Eigen::Vector3d>("v:rest").first;
  rest_normal = sm.property_map<VertexIndex, Eigen::Vector3d>("v:rest_normal").first;
  normal = sm.property_map<VertexIndex, Eigen::Vector3d>("v:normal").first;
  uv = sm.property_map<HalfedgeIndex, std::int32_t>("h:uv").first;
  vn = sm.property_map<HalfedgeIndex, std::int32_t>("h:vn").first;
  group = sm.property_map<FaceIndex, std::int32_t>("f:group").first;
  if (has_colors) color = sm.property_map<VertexIndex, Eigen::Vector3f>("v:color").first;
}

void MeshStorage::enable_colors() {
  color = sm.add_property_map<VertexIndex, Eigen::Vector3f>("v:color", Eigen::Vector3f(0.8f, 0.8f, 0.8f))
              .first;
  has_colors = true;
}

namespace {

// The Surface_mesh property name behind Mesh::vec3_attribute(name).
std::string attribute_name(const std::string& name) { return "v:attr:" + name; }

}  // namespace

Vec3Property MeshStorage::vec3_attribute(const std::string& name) {
  return sm.add_property_map<VertexIndex, Eigen::Vector3d>(attribute_name(name), Eigen::Vector3d::Zero()).first;
}

namespace {

// (An empty mesh maps no memory: CGAL's data() indexes its first element, undefined when
// there is none.)
Vec3Array vec3_map(SurfaceMesh::Property_map<VertexIndex, Eigen::Vector3d>& map, std::size_t n) {
  return {n ? const_cast<double*>(reinterpret_cast<const double*>(map.data())) : nullptr, 3,
          static_cast<Eigen::Index>(n)};
}

ConstVec3Array const_vec3_map(const SurfaceMesh::Property_map<VertexIndex, Eigen::Vector3d>& map,
                              std::size_t n) {
  return {n ? reinterpret_cast<const double*>(map.data()) : nullptr, 3, static_cast<Eigen::Index>(n)};
}

}  // namespace

Mesh::Mesh() : storage_(std::make_unique<MeshStorage>()) {}
Mesh::~Mesh() = default;
Mesh::Mesh(Mesh&&) noexcept = default;
Mesh& Mesh::operator=(Mesh&&) noexcept = default;

Mesh Mesh::clone() const {
  Mesh copy;
  copy.storage_ = std::make_unique<MeshStorage>(*storage_);
  return copy;
}

std::size_t Mesh::num_vertices() const { return storage_->sm.number_of_vertices(); }
std::size_t Mesh::num_faces() const { return storage_->sm.number_of_faces(); }
std::size_t Mesh::num_edges() const { return storage_->sm.number_of_edges(); }

bool Mesh::is_triangle_mesh() const {
  const SurfaceMesh& sm = storage_->sm;
  for (FaceIndex f : sm.faces())
    if (sm.degree(f) != 3) return false;
  return true;
}

Vec3Array Mesh::rest_positions() { return vec3_map(storage_->rest, num_vertices()); }
ConstVec3Array Mesh::rest_positions() const { return const_vec3_map(storage_->rest, num_vertices()); }
Vec3Array Mesh::positions() { return point_array(storage_->sm); }
ConstVec3Array Mesh::positions() const {
  return {reinterpret_cast<const double*>(storage_->sm.points().data()), 3,
          static_cast<Eigen::Index>(num_vertices())};
}
Vec3Array Mesh::rest_normals() { return vec3_map(storage_->rest_normal, num_vertices()); }
ConstVec3Array Mesh::rest_normals() const {
  return const_vec3_map(storage_->rest_normal, num_vertices());
}
Vec3Array Mesh::normals() { return vec3_map(storage_->normal, num_vertices()); }
ConstVec3Array Mesh::normals() const { return const_vec3_map(storage_->normal, num_vertices()); }

Vec3Array Mesh::vec3_attribute(const std::string& name) {
  Vec3Property map = storage_->vec3_attribute(name);
  return vec3_map(map, num_vertices());
}

bool Mesh::has_vec3_attribute(const std::string& name) const {
  return storage_->sm.property_map<VertexIndex, Eigen::Vector3d>(attribute_name(name)).second;
}

void Mesh::remove_vec3_attribute(const std::string& name) {
  auto map = storage_->sm.property_map<VertexIndex, Eigen::Vector3d>(attribute_name(name));
  if (map.second) storage_->sm.remove_property_map(map.first);
}

void Mesh::face_vertices(std::size_t f, std::vector<std::uint32_t>& out) const {
  const SurfaceMesh& sm = storage_->sm;
  out.clear();
  for (VertexIndex v : CGAL::vertices_around_face(sm.halfedge(FaceIndex(static_cast<std::uint32_t>(f))), sm))
    out.push_back(static_cast<std::uint32_t>(v.idx()));
}

std::vector<std::vector<std::uint32_t>> Mesh::faces() const {
  std::vector<std::vector<std::uint32_t>> result(num_faces());
  for (std::size_t f = 0; f < result.size(); ++f) face_vertices(f, result[f]);
  return result;
}

bool Mesh::has_uvs() const { return storage_->has_uvs; }
bool Mesh::has_file_normals() const { return storage_->has_file_normals; }
bool Mesh::has_colors() const { return storage_->has_colors; }

std::uint64_t Mesh::topology_version() const { return storage_->topology_version; }
void Mesh::mark_topology_changed() { ++storage_->topology_version; }

void Mesh::bake() {
  rest_positions() = positions();
  rest_normals() = normals();
}

void Mesh::recompute_rest_normals(bool also_current) {
  compute_vertex_normals(*this, rest_positions(), rest_normals());
  if (also_current) normals() = rest_normals();
}

std::vector<Eigen::Vector3f> color_array(const Mesh& mesh) {
  const MeshStorage& s = mesh.storage();
  std::vector<Eigen::Vector3f> colors;
  if (!s.has_colors) return colors;
  colors.resize(s.sm.number_of_vertices());
  for (VertexIndex v : s.sm.vertices()) colors[v.idx()] = s.color[v];
  return colors;
}

}  // namespace ffd
