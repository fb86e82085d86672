// What the lattice ops (move, drag) report after the warp stack re-evaluated the mesh.
#pragma once

#include <string>

#include "script/scene.h"

namespace ffd {

/// Records the update's counts in the step's stats and warns about folded vertices.
void report_update(Scene& scene, const WarpStack::Update& update, StepContext& ctx);

/// Warns when a deformer that tears as moved (Bernstein with face points moved) meets mesh
/// vertices outside its support: the surface opens where it leaves the box.
void warn_if_tearing(Scene& scene, const Deformer& deformer, const std::string& name, const StepContext& ctx);

}  // namespace ffd
