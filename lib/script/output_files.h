// The files a run writes: staged in their targets' folders (common/atomic_file.h) and put
// in place only when the whole run succeeded (docs/architecture.md, "Staged output").
#pragma once

#include <string>

#include "mesh/mesh_io.h"
#include "script/scene.h"

namespace ffd {

/// Writes the scene's current mesh to `relative` (inside the output folder) as a staged
/// file committed at the end of the run, with `options` (Scene::write_options() and any
/// replacement colours); returns the bytes written. \throw IoError on a failed write.
std::size_t stage_mesh(Scene& scene, const std::string& relative, const WriteOptions& options);
/// The same at `target` itself (a path, not relative to the output folder).
std::size_t stage_mesh_at(Scene& scene, const std::string& target, const WriteOptions& options);
/// Renders the scene's current mesh with every lattice's control net over it
/// (render/render.h, 1280 × 960, iso view) and stages it as a PNG at `target` (a path);
/// returns the bytes. \throw InputError unless `target` ends in .png.
std::size_t stage_preview(Scene& scene, const std::string& target);
/// The same with the scene's own write options.
inline std::size_t stage_mesh(Scene& scene, const std::string& relative) {
  return stage_mesh(scene, relative, scene.write_options());
}

}  // namespace ffd
