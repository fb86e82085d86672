#include "script/surface_edits.h"

#include <cstdio>

#include "bcm/bcm_editor.h"

namespace ffd {

void BcmEditorDelete::operator()(BcmEditor* editor) const { delete editor; }

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
    scene.lattices.erase(name);
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

std::string ms_text(double ms) {
  char buf[32];
  std::snprintf(buf, sizeof buf, ms < 1 ? "%.3f ms" : "%.1f ms", ms);
  return buf;
}

}  // namespace ffd
