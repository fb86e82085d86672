#include "mesh/mesh.h"

#include <algorithm>

#include "common/errors.h"
#include "common/zeroed_array.h"
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

Eigen::Matrix3Xd copy_in_team(const Eigen::Ref<const Eigen::Matrix3Xd>& from) {
  const Eigen::Index n = from.cols();
  Eigen::Matrix3Xd to(3, n);
  advise_huge_pages(to.data(), static_cast<std::size_t>(to.size()) * sizeof(double));
#pragma omp parallel for schedule(static) if (n >= 65536)
  for (Eigen::Index i = 0; i < n; ++i) to.col(i) = from.col(i);
  return to;
}

Mesh::Mesh() = default;
Mesh::~Mesh() = default;
Mesh::Mesh(Mesh&&) noexcept = default;
Mesh& Mesh::operator=(Mesh&&) noexcept = default;

bool Mesh::is_triangle_mesh() const {
  for (std::size_t e = 0; e < elements_.size(); ++e)
    if (elements_.kinds[e] == ElementKind::Polygon && elements_.degree(e) != 3) return false;
  return true;
}

namespace {

// m with n columns: the first min(n, old) kept, `fallback` past them.
void resize_array(Eigen::Matrix3Xd& m, std::size_t count, const Eigen::Vector3d& fallback) {
  const Eigen::Index old = m.cols(), n = static_cast<Eigen::Index>(count);
  m.conservativeResize(3, n);
  if (n > old) m.rightCols(n - old).colwise() = fallback;
}

// Zeros m without writing its pages where it is large (zero_bits).
void set_zero(Eigen::Matrix3Xd& m) { zero_bits(m.data(), static_cast<std::size_t>(m.size()) * sizeof(double)); }

template <class T>
void resize_array(std::vector<T>& v, std::size_t count, const T& fallback) {
  v.resize(count, fallback);
}

}  // namespace

void Mesh::resize_vertices(std::size_t count) {
  for_each_vertex_array([&](const auto& a) {
    if (!a.optional || (this->*a.member).size() != 0) resize_array(this->*a.member, count, a.fallback);
  });
  for (auto& [name, m] : attributes_) resize_array(m, count, Eigen::Vector3d::Zero());
}

void Mesh::set_vertices(Eigen::Matrix3Xd positions, bool normals) {
  rest_ = copy_in_team(positions);
  pos_ = std::move(positions);
  if (!normals) {
    rest_normal_.resize(3, pos_.cols());
    normal_.resize(3, pos_.cols());
    set_zero(rest_normal_);
    set_zero(normal_);
    resize_vertices(num_vertices());
    normals_deferred_ = true;
    return;
  }
  rest_normal_.resize(3, pos_.cols());  // compute_vertex_normals writes every column
  resize_vertices(num_vertices());      // recompute_rest_normals then sets the normals
  recompute_rest_normals(true);
}

Vec3Array Mesh::vec3_attribute(const std::string& name) {
  auto [it, created] = attributes_.try_emplace(name);
  if (created) {
    it->second.resize(3, pos_.cols());
    set_zero(it->second);
  }
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
  normals_deferred_ = false;
  compute_vertex_normals(*this, rest_positions(), rest_normals());
  if (also_current) normal_ = rest_normal_;
}

std::vector<Eigen::Vector3f> color_array(const Mesh& mesh) { return mesh.colors(); }

}  // namespace ffd
