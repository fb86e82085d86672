// What the surface-edit ops (bcm, transform) share: freezing the warp stack into the mesh
// before an edit, and the words they report with.
#pragma once

#include <string>
#include <vector>

#include "script/scene.h"

namespace ffd {

/// Freezes the warp stack into the mesh (a surface edit acts on the deformed surface);
/// records which step did it. Returns the names of the lattices frozen.
nlohmann::ordered_json bake_stack(Scene& scene, const std::string& pointer);
/// Warns that `baked` lattices can no longer be moved.
void warn_baked(Scene& scene, const nlohmann::ordered_json& baked, const StepContext& ctx);
/// "'a', 'b', 'c'".
std::string quoted_list(const std::vector<std::string>& names);
/// "0.153 ms" below a millisecond, "12.5 ms" above.
std::string ms_text(double ms);

}  // namespace ffd
