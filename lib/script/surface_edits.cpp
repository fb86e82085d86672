#include "script/surface_edits.h"

#include <algorithm>
#include <cstdio>

namespace ffd {

void SurfaceEditorDelete::operator()(SurfaceEditor* editor) const { delete editor; }

namespace {

// Sorted and without repeats.
void sort_unique(std::vector<std::uint32_t>& v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

}  // namespace

std::unique_ptr<SurfaceEditor, SurfaceEditorDelete> make_surface_editor(const Mesh& mesh, BcmData bcm) {
  std::unique_ptr<SurfaceEditor, SurfaceEditorDelete> editor(new SurfaceEditor);
  SurfaceEditor& e = *editor;
  e.bcm = std::move(bcm);
  e.topology_version = mesh.topology_version();
  e.moved = e.bcm.regions.free;
  for (const auto& handle : e.bcm.regions.handles) e.moved.insert(e.moved.end(), handle.begin(), handle.end());
  std::sort(e.moved.begin(), e.moved.end());
  std::vector<char> is_moved(mesh.num_vertices(), 0);
  for (std::uint32_t v : e.moved) is_moved[v] = 1;
  std::vector<std::uint32_t> ids;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    mesh.face_vertices(f, ids);
    if (std::any_of(ids.begin(), ids.end(), [&](std::uint32_t v) { return is_moved[v] != 0; }))
      e.normal_vertices.insert(e.normal_vertices.end(), ids.begin(), ids.end());
  }
  e.normal_vertices.insert(e.normal_vertices.end(), e.moved.begin(), e.moved.end());
  sort_unique(e.normal_vertices);
  e.watched = e.bcm.stencil.vertices;
  e.watched.insert(e.watched.end(), e.moved.begin(), e.moved.end());
  sort_unique(e.watched);
  e.remember(mesh.positions());
  return editor;
}

void SurfaceEditor::remember(const Eigen::Ref<const Eigen::Matrix3Xd>& positions) {
  watched_positions.resize(3, static_cast<Eigen::Index>(watched.size()));
  for (std::size_t i = 0; i < watched.size(); ++i) watched_positions.col(static_cast<Eigen::Index>(i)) = positions.col(watched[i]);
}

long SurfaceEditor::changed_vertex(const Eigen::Ref<const Eigen::Matrix3Xd>& positions) const {
  for (std::size_t i = 0; i < watched.size(); ++i)
    if (positions.col(watched[i]) != watched_positions.col(static_cast<Eigen::Index>(i))) return static_cast<long>(watched[i]);
  return -1;
}

std::string quoted_list(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) out += (i ? ", '" : "'") + names[i] + "'";
  return out;
}

nlohmann::ordered_json bake_stack(Scene& scene, const std::string& pointer) {
  nlohmann::ordered_json names = nlohmann::ordered_json::array();
  if (scene.stack.size() == 0) return names;
  for (const std::string& name : scene.stack.bake(scene.mesh)) {
    scene.baked[name] = pointer;
    scene.deformers.erase(name);
    names.push_back(name);
  }
  return names;
}

void warn_baked(Scene& scene, const nlohmann::ordered_json& baked, const StepContext& ctx) {
  if (baked.empty()) return;
  std::vector<std::string> names;
  for (const auto& name : baked) names.push_back(name.get<std::string>());
  scene.warnings.push_back(ctx.pointer + ": " + (names.size() == 1 ? "lattice " : "lattices ") + quoted_list(names) +
                           (names.size() == 1 ? " was" : " were") +
                           " frozen into the mesh for this surface edit; later steps cannot move " +
                           (names.size() == 1 ? "it" : "them"));
}

}  // namespace ffd
