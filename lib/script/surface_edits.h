// What the surface-edit ops (bcm, transform) share: the editor a bcm step sets up with
// the script's bookkeeping around it, freezing the warp stack into the mesh before an
// edit, and the words they report with.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "bcm/bcm_editor.h"
#include "script/scene.h"

namespace ffd {

/// A bcm step's editor, and what the script keeps to tell whether later steps may still
/// pose it: the mesh's connectivity at setup, the vertices it reads and writes, where they
/// were when it last wrote them, and whose normals its moves change.
struct SurfaceEditor {
  BcmData bcm;
  std::uint64_t topology_version = 0;
  /// What bcm_pose() writes: free and handle vertices, ascending.
  std::vector<std::uint32_t> moved;
  /// The moved vertices and every vertex sharing a face with one, ascending.
  std::vector<std::uint32_t> normal_vertices;
  /// The stencil and the moved vertices, ascending, and where they are.
  std::vector<std::uint32_t> watched;
  Eigen::Matrix3Xd watched_positions;

  /// Remembers where the watched vertices are now.
  void remember(const Eigen::Ref<const Eigen::Matrix3Xd>& positions);
  /// The first watched vertex that is no longer where remember() saw it, or -1.
  long changed_vertex(const Eigen::Ref<const Eigen::Matrix3Xd>& positions) const;
};

/// The editor around `bcm`, set up on `mesh` as it is now.
std::unique_ptr<SurfaceEditor, SurfaceEditorDelete> make_surface_editor(const Mesh& mesh, BcmData bcm);

/// Freezes the warp stack into the mesh (a surface edit acts on the deformed surface);
/// records which step did it. Returns the names of the lattices frozen.
nlohmann::ordered_json bake_stack(Scene& scene, const std::string& pointer);
/// Warns that `baked` lattices can no longer be moved.
void warn_baked(Scene& scene, const nlohmann::ordered_json& baked, const StepContext& ctx);
/// "'a', 'b', 'c'".
std::string quoted_list(const std::vector<std::string>& names);

}  // namespace ffd
