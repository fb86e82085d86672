// The save op: write the current mesh mid-script.
#include <filesystem>
#include <algorithm>
#include <fstream>

#include "common/errors.h"
#include "remesh/adaptive_remesher.h"
#include "script/ops.h"

namespace ffd {

std::size_t stage_mesh(Scene& scene, const std::string& relative, const WriteOptions& options) {
  const std::filesystem::path target = std::filesystem::path(scene.output_folder) / relative;
  const MeshFormat format = mesh_format(target);
  StagedFile staged(target);
  std::ofstream os(staged.temp_path(), std::ios::binary | std::ios::trunc);
  if (!os) throw RunError(target.string() + ": cannot open for writing");
  write_mesh(os, format, scene.mesh, options);
  os.flush();
  if (!os) throw RunError(target.string() + ": write failed (disk full?)");
  const std::size_t bytes = static_cast<std::size_t>(os.tellp());
  scene.staged.push_back(std::move(staged));
  return bytes;
}

void check_save(ScriptChecks& checks, const nlohmann::json& step, const std::string& p) {
  checks.check_output_path(step["path"], p + "/path");
}

void run_save(Scene& scene, const nlohmann::json& step, StepContext& ctx) {
  const std::string path = step["path"];
  WriteOptions options = scene.write_options();
  if (step["colors"] == "level") {
    int top = 1;
    for (int level : vertex_levels(scene.mesh)) top = std::max(top, level);
    options.colors = level_colors(scene.mesh, top);
    if (mesh_format(path) == MeshFormat::Stl)
      scene.warnings.push_back(ctx.pointer + ": STL holds no colours; the levels are not written");
  }
  const std::size_t bytes = stage_mesh(scene, path, options);
  ctx.stats["path"] = path;
  ctx.stats["bytes"] = bytes;
  ctx.summary = "save " + path;
}

}  // namespace ffd
