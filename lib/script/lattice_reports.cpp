#include "script/lattice_reports.h"

#include "common/numbers.h"

namespace ffd {

void report_update(Scene& scene, const WarpStack::Update& update, StepContext& ctx) {
  ctx.stats["vertices_moved"] = update.moved;
  ctx.stats["inverted_jacobians"] = update.folded;
  if (update.folded)
    scene.warnings.push_back(ctx.pointer + ": " + format_count(update.folded) +
                             " vertices where the warp folds space over (Jacobian determinant <= 0); "
                             "the surface self-intersects there");
}

void warn_if_tearing(Scene& scene, const Deformer& deformer, const std::string& name, const StepContext& ctx) {
  if (!deformer.tears()) return;
  const std::size_t k = scene.stack.index_of(name);
  std::size_t outside = 0;
  for (std::uint32_t v = 0; v < scene.mesh.num_vertices(); ++v)
    if (!deformer.in_support(scene.stack.input_position(scene.mesh, k, v))) ++outside;
  if (outside == 0) return;
  scene.warnings.push_back(ctx.pointer + ": " + deformer.tearing_warning(name, outside));
}

}  // namespace ffd
