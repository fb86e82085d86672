// The save op: write the current mesh mid-script.
#include <filesystem>
#include <fstream>

#include "common/errors.h"
#include "script/ops.h"

namespace ffd {

std::size_t stage_mesh(Scene& scene, const std::string& relative) {
  const std::filesystem::path target = std::filesystem::path(scene.output_folder) / relative;
  const MeshFormat format = mesh_format(target);
  StagedFile staged(target);
  std::ofstream os(staged.temp_path(), std::ios::binary | std::ios::trunc);
  if (!os) throw RunError(target.string() + ": cannot open for writing");
  write_mesh(os, format, scene.mesh, scene.write_options());
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
  const std::size_t bytes = stage_mesh(scene, path);
  ctx.stats["path"] = path;
  ctx.stats["bytes"] = bytes;
  ctx.summary = "save " + path;
}

}  // namespace ffd
