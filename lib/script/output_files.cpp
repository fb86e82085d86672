#include "script/output_files.h"

#include <filesystem>
#include <fstream>

#include "common/errors.h"

namespace ffd {

std::size_t stage_mesh(Scene& scene, const std::string& relative, const WriteOptions& options) {
  return stage_mesh_at(scene, (std::filesystem::path(scene.output_folder) / relative).string(), options);
}

std::size_t stage_mesh_at(Scene& scene, const std::string& path, const WriteOptions& options) {
  const std::filesystem::path target(path);
  const MeshFormat format = mesh_format(target);
  StagedFile staged(target);
  std::ofstream os(staged.temp_path(), std::ios::binary | std::ios::trunc);
  if (!os) throw IoError(At{target.string()}, "cannot open for writing");
  write_mesh(os, format, scene.mesh, options);
  os.flush();
  if (!os) throw IoError(At{target.string()}, "write failed (disk full?)");
  const std::size_t bytes = static_cast<std::size_t>(os.tellp());
  scene.staged.push_back(std::move(staged));
  return bytes;
}

}  // namespace ffd
