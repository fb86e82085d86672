#include "warp/warp_stack.h"

#include "mesh/file_normals.h"

namespace ffd {

std::string WarpStack::input_name(std::size_t k, const char* what) {
  return "stack:" + std::to_string(k) + ":" + what;
}

void WarpStack::push(Mesh& mesh, std::string name, std::unique_ptr<Warp> warp) {
  const std::size_t k = warps_.size();
  if (k > 0) {
    mesh.vec3_attribute(input_name(k, "pos")) = mesh.positions();
    mesh.vec3_attribute(input_name(k, "nrm")) = mesh.normals();
  }
  names_.push_back(std::move(name));
  warps_.push_back(std::move(warp));
}

Warp* WarpStack::find(const std::string& name) const {
  for (std::size_t k = 0; k < names_.size(); ++k)
    if (names_[k] == name) return warps_[k].get();
  return nullptr;
}

std::size_t WarpStack::index_of(const std::string& name) const {
  for (std::size_t k = 0; k < names_.size(); ++k)
    if (names_[k] == name) return k;
  return names_.size();
}

Eigen::Vector3d WarpStack::input_position(const Mesh& mesh, std::size_t k, std::uint32_t v) const {
  if (k == 0) return mesh.rest_positions().col(v);
  // The attribute exists for every k >= 1 while the warp does.
  return mesh.vec3_attribute(input_name(k, "pos")).col(v);
}

WarpStack::Update WarpStack::update(Mesh& mesh, const std::string& name) {
  const std::size_t k = index_of(name);
  return k < warps_.size() ? update(mesh, k) : Update{};
}

WarpStack::Update WarpStack::update(Mesh& mesh, std::size_t k) {
  Update result;
  Warp& changed = *warps_[k];
  if (!changed.has_changes()) return result;
  changed.prepare();
  const auto input_pos = [&](std::size_t j) -> Eigen::Map<Eigen::Matrix3Xd> {
    return j == 0 ? mesh.rest_positions() : mesh.vec3_attribute(input_name(j, "pos"));
  };
  const auto input_nrm = [&](std::size_t j) -> Eigen::Map<Eigen::Matrix3Xd> {
    return j == 0 ? mesh.rest_normals() : mesh.vec3_attribute(input_name(j, "nrm"));
  };
  std::vector<std::uint32_t> ids;
  WarpCounts counts;
  // Normals deferred: every normal is zero and stays so (warps keep zero normals zero), so
  // a warp that can evaluate positions alone need not read or write them.
  const bool zero_normals = mesh.normals_deferred();
  // The changed warp finds its changed points as it applies itself, where it can: one pass
  // over its input instead of two.
  std::size_t j = k;
  {
    const bool top = k + 1 == warps_.size();
    const Eigen::Ref<const Eigen::Matrix3Xd> in_nrm = input_nrm(k);
    Eigen::Ref<Eigen::Matrix3Xd> out_nrm = top ? mesh.normals() : input_nrm(k + 1);
    if (changed.apply_changed(input_pos(k), zero_normals ? nullptr : &in_nrm, ids, top ? mesh.positions() : input_pos(k + 1),
                              zero_normals ? nullptr : &out_nrm, counts))
      ++j;
    else
      changed.changed_points(input_pos(k), ids);
  }
  for (; j < warps_.size(); ++j) {
    const bool top = j + 1 == warps_.size();
    warps_[j]->prepare();
    const auto out_pos = top ? mesh.positions() : input_pos(j + 1);
    if (zero_normals && warps_[j]->apply_without_normals(input_pos(j), ids, out_pos, counts)) continue;
    warps_[j]->apply(input_pos(j), input_nrm(j), ids, out_pos, top ? mesh.normals() : input_nrm(j + 1), counts);
  }
  changed.clear_changes();
  result.moved = ids.size();
  result.folded = counts.folded;
  return result;
}

Eigen::Vector3d WarpStack::evaluate(const Eigen::Vector3d& rest, Eigen::Matrix3d* jacobian) const {
  Eigen::Vector3d x = rest;
  if (jacobian) jacobian->setIdentity();
  for (const auto& warp : warps_) {
    Eigen::Matrix3d J;
    x = warp->apply(x, jacobian ? &J : nullptr);
    if (jacobian) *jacobian = J * *jacobian;
  }
  return x;
}

Eigen::Vector3d WarpStack::carry_from(std::size_t k, const Eigen::Vector3d& x) const {
  Eigen::Vector3d y = x;
  for (std::size_t j = k + 1; j < warps_.size(); ++j) y = warps_[j]->apply(y, nullptr);
  return y;
}

void WarpStack::evaluate_point(Eigen::Vector3d& x, Eigen::Vector3d& n, const InputSink& input) const {
  for (std::size_t k = 0; k < warps_.size(); ++k) {
    if (k > 0 && input) input(k, x, n);
    Eigen::Matrix3d J;
    const Eigen::Vector3d u = warps_[k]->apply(x, &J);
    if (u != x || !J.isIdentity(0.0)) {
      const Eigen::Vector3d m = cofactor_times(J, n);
      const double len = m.norm();
      n = len > 0 ? Eigen::Vector3d(m / len) : Eigen::Vector3d::Zero();
    }
    x = u;
  }
}

void WarpStack::evaluate_vertex(Mesh& mesh, std::uint32_t v) const {
  Eigen::Vector3d x = mesh.rest_positions().col(v);
  Eigen::Vector3d n = mesh.rest_normals().col(v);
  evaluate_point(x, n, [&](std::size_t k, const Eigen::Vector3d& xk, const Eigen::Vector3d& nk) {
    mesh.vec3_attribute(input_name(k, "pos")).col(v) = xk;
    mesh.vec3_attribute(input_name(k, "nrm")).col(v) = nk;
  });
  mesh.positions().col(v) = x;
  mesh.normals().col(v) = n;
}

Eigen::Vector3d WarpStack::transform_normal(const Mesh& mesh, std::uint32_t v, const Eigen::Vector3d& n) const {
  if (warps_.empty()) return n;
  Eigen::Matrix3d J;
  evaluate(mesh.rest_positions().col(v), &J);
  if (J.isIdentity(0.0)) return n;
  const Eigen::Vector3d m = cofactor_times(J, n);
  const double len = m.norm();
  return len > 0 ? Eigen::Vector3d(m / len) : n;
}

void WarpStack::bake_copy(Mesh& copy) const {
  bake_file_normals(copy, [&](std::uint32_t v, const Eigen::Vector3d& n) { return transform_normal(copy, v, n); });
  copy.bake();
  for (std::size_t k = 1; k < warps_.size(); ++k) {
    copy.remove_vec3_attribute(input_name(k, "pos"));
    copy.remove_vec3_attribute(input_name(k, "nrm"));
  }
}

std::vector<std::string> WarpStack::bake(Mesh& mesh) {
  bake_copy(mesh);
  std::vector<std::string> dropped = std::move(names_);
  names_.clear();
  warps_.clear();
  return dropped;
}

}  // namespace ffd
