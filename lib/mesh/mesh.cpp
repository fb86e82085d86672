#include "mesh/mesh.h"

#include <algorithm>

#include "common/errors.h"
#include "mesh/halfedge_view.h"
#include "mesh/vertex_colors.h"
#include "mesh/vertex_normals.h"

namespace ffd {

void throw_too_many_corners() {
  throw InputError("more than 4,294,967,295 element corners: ffdtool indexes corners with 32 bits");
}

std::string element_place(const std::string& file, const MeshElements& elements, std::size_t e) {
  if (elements.line(e) > 0) return file + ":" + std::to_string(elements.line(e));
  const bool all_polygons = std::all_of(elements.kinds.begin(), elements.kinds.end(),
                                        [](ElementKind k) { return k == ElementKind::Polygon; });
  return file + (all_polygons ? ": face " : ": element ") + std::to_string(e);
}

Mesh::Mesh() = default;
Mesh::~Mesh() = default;
Mesh::Mesh(Mesh&&) noexcept = default;
Mesh& Mesh::operator=(Mesh&&) noexcept = default;

Mesh Mesh::clone() const {
  Mesh copy;
  copy.rest_ = rest_;
  copy.pos_ = pos_;
  copy.rest_normal_ = rest_normal_;
  copy.normal_ = normal_;
  copy.attributes_ = attributes_;
  copy.colors_ = colors_;
  copy.elements_ = elements_;
  copy.num_polygons_ = num_polygons_;
  copy.polygon_element_ = polygon_element_;
  copy.uvs_ = uvs_;
  copy.file_normals_ = file_normals_;
  copy.groups_ = groups_;
  copy.header_ = header_;
  copy.file_uv_count = file_uv_count;
  copy.file_normal_count = file_normal_count;
  copy.source_ = source_;
  copy.source_binary_ = source_binary_;
  copy.gltf_ = gltf_;
  copy.gltf_version_ = gltf_version_;
  copy.vertex_levels_ = vertex_levels_;
  copy.edge_levels_ = edge_levels_;
  copy.topology_version_ = topology_version_;
  if (view_) copy.view_ = copy_view(*view_);
  copy.view_version_ = view_version_;
  return copy;
}

bool Mesh::is_triangle_mesh() const {
  for (std::size_t e = 0; e < elements_.size(); ++e)
    if (elements_.kinds[e] == ElementKind::Polygon && elements_.degree(e) != 3) return false;
  return true;
}

namespace {

// m with n columns: the first min(n, old) kept, the rest zero.
void resize_columns(Eigen::Matrix3Xd& m, Eigen::Index n) {
  const Eigen::Index old = m.cols();
  m.conservativeResize(3, n);
  if (n > old) m.rightCols(n - old).setZero();
}

}  // namespace

void Mesh::resize_vertices(std::size_t count) {
  const auto n = static_cast<Eigen::Index>(count);
  for (Eigen::Matrix3Xd* m : {&rest_, &pos_, &rest_normal_, &normal_}) resize_columns(*m, n);
  resize_other_vertex_data(count);
}

void Mesh::set_vertices(Eigen::Matrix3Xd positions) {
  rest_ = positions;
  pos_ = std::move(positions);
  rest_normal_.resize(3, pos_.cols());  // compute_vertex_normals writes every column
  resize_other_vertex_data(num_vertices());
  recompute_rest_normals(true);
}

void Mesh::resize_other_vertex_data(std::size_t count) {
  for (auto& [name, m] : attributes_) resize_columns(m, static_cast<Eigen::Index>(count));
  if (!colors_.empty()) colors_.resize(count, Eigen::Vector3f(0.8f, 0.8f, 0.8f));
  if (!vertex_levels_.empty()) vertex_levels_.resize(count, 0);
}

Vec3Array Mesh::vec3_attribute(const std::string& name) {
  auto [it, created] = attributes_.try_emplace(name);
  if (created) it->second = Eigen::Matrix3Xd::Zero(3, pos_.cols());
  return map(it->second);
}

bool Mesh::has_vec3_attribute(const std::string& name) const { return attributes_.count(name) > 0; }
void Mesh::remove_vec3_attribute(const std::string& name) { attributes_.erase(name); }

std::vector<std::string> Mesh::vec3_attribute_names() const {
  std::vector<std::string> names;
  for (const auto& [name, m] : attributes_) names.push_back(name);
  return names;
}

std::vector<std::string> Mesh::attribute_names() const {
  std::vector<std::string> names;
  for (const auto& [name, m] : attributes_) names.push_back("v:attr:" + name);
  if (!vertex_levels_.empty()) names.push_back(mesh_attribute::kVertexLevel);
  if (!edge_levels_.empty()) names.push_back(mesh_attribute::kEdgeLevel);
  if (view_)
    for (std::string& n : view_property_names(*view_)) names.push_back("view " + n);
  std::sort(names.begin(), names.end());
  return names;
}

void Mesh::set_elements(MeshElements elements) {
  elements_ = std::move(elements);
  num_polygons_ = elements_.count(ElementKind::Polygon);
  polygon_element_.clear();
  if (num_polygons_ != elements_.size())
    for (std::size_t e = 0; e < elements_.size(); ++e)
      if (elements_.kinds[e] == ElementKind::Polygon) polygon_element_.push_back(static_cast<std::uint32_t>(e));
}

std::vector<std::vector<std::uint32_t>> Mesh::faces() const {
  std::vector<std::vector<std::uint32_t>> result;
  result.reserve(num_polygons_);
  for (std::size_t e = 0; e < elements_.size(); ++e)
    if (elements_.kinds[e] == ElementKind::Polygon)
      result.emplace_back(elements_.vertices(e), elements_.vertices(e) + elements_.degree(e));
  return result;
}

void Mesh::bake() {
  rest_ = pos_;
  rest_normal_ = normal_;
}

void Mesh::recompute_rest_normals(bool also_current) {
  compute_vertex_normals(*this, rest_positions(), rest_normals());
  if (also_current) normal_ = rest_normal_;
}

std::vector<Eigen::Vector3f> color_array(const Mesh& mesh) { return mesh.colors(); }

}  // namespace ffd
