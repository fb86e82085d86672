#include "script/output_files.h"

#include <filesystem>

namespace ffd {

std::size_t stage_mesh(Scene& scene, const std::string& relative, const WriteOptions& options) {
  return stage_mesh_at(scene, (std::filesystem::path(scene.output_folder) / relative).string(), options);
}

std::size_t stage_mesh_at(Scene& scene, const std::string& path, const WriteOptions& options) {
  std::size_t bytes = 0;
  for (StagedFile& f : stage_mesh_files(path, scene.mesh, options, &bytes)) scene.staged.push_back(std::move(f));
  return bytes;
}

}  // namespace ffd
