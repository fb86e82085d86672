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

void warn_if_tearing(Scene& scene, const Lattice& lattice, const std::string& name, const StepContext& ctx) {
  if (lattice.boundary_continuity() >= 0) return;
  const std::size_t k = scene.stack.index_of(name);
  std::size_t outside = 0;
  for (std::uint32_t v = 0; v < scene.mesh.num_vertices(); ++v)
    if (!Lattice::inside(lattice.box().to_local(scene.stack.input_position(scene.mesh, k, v)))) ++outside;
  if (outside == 0) return;
  scene.warnings.push_back(ctx.pointer + ": lattice '" + name + "' moved points on its box's faces while " +
                           format_count(outside) +
                           " vertices lie outside the box: a Bernstein lattice tears the mesh there "
                           "(use basis \"bspline\", or move only interior points)");
}

}  // namespace ffd
