#include "script/output_files.h"

#include <filesystem>

#include "common/errors.h"
#include "render/control_net.h"
#include "render/png_io.h"
#include "render/render.h"

namespace ffd {

std::size_t stage_mesh(Scene& scene, const std::string& relative, const WriteOptions& options) {
  return stage_mesh_at(scene, (std::filesystem::path(scene.output_folder) / relative).string(), options);
}

std::size_t stage_mesh_at(Scene& scene, const std::string& path, const WriteOptions& options) {
  if (const std::string lost = unwritten_data(scene.mesh, mesh_format(path)); !lost.empty())
    scene.warnings.push_back(path + ": " + lost);
  std::size_t bytes = 0;
  for (StagedFile& f : stage_mesh_files(path, scene.mesh, options, &bytes)) scene.staged.push_back(std::move(f));
  return bytes;
}

std::size_t stage_preview(Scene& scene, const std::string& target) {
  if (!has_png_extension(target)) throw InputError(At{target}, "a preview is a PNG picture: give it the extension .png");
  std::vector<Overlay> nets;
  for (const auto& [name, deformer] : scene.deformers) nets.push_back(control_net(*deformer));
  const Image image = render_mesh(scene.mesh, RenderOptions{}, nullptr, nets);
  StagedFile staged{std::filesystem::path(target)};
  const std::size_t bytes = staged.write([&](std::ostream& os) { write_png(os, image); });
  scene.staged.push_back(std::move(staged));
  return bytes;
}

}  // namespace ffd
