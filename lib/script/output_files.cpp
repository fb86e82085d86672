#include "script/output_files.h"

#include <filesystem>

namespace ffd {

std::size_t stage_mesh(Scene& scene, const std::string& relative, const WriteOptions& options) {
  return stage_mesh_at(scene, (std::filesystem::path(scene.output_folder) / relative).string(), options);
}

std::size_t stage_mesh_at(Scene& scene, const std::string& path, const WriteOptions& options) {
  const std::filesystem::path target(path);
  const MeshFormat format = mesh_format(target);
  check_writable(scene.mesh, format, path);
  StagedFile staged(target);
  const std::size_t bytes = staged.write([&](std::ostream& os) { write_mesh(os, format, scene.mesh, options); });
  scene.staged.push_back(std::move(staged));
  return bytes;
}

}  // namespace ffd
