// The save op: write the current mesh mid-script.
#include <algorithm>
#include <filesystem>
#include <optional>

#include "remesh/adaptive_remesher.h"
#include "script/op.h"
#include "script/output_files.h"

namespace ffd {
namespace {

const std::vector<std::pair<std::string, bool>> kColors = {{"mesh", false}, {"level", true}};

struct SaveStep final : Step {
  std::string path;
  bool colors_by_level = false;
  std::optional<std::string> preview;

  std::vector<OutputFile> outputs() const override {
    std::vector<OutputFile> out = {{"/path", path}};
    if (preview) out.push_back({"/preview", *preview, true});
    return out;
  }
  void run(Scene& scene, StepContext& ctx) const override;
};

KeyTable<SaveStep> save_keys() {
  using S = SaveStep;
  return {{key<S>("/path", schema_text(), nullptr, "Relative to the output folder (the folder of -o).",
                  [](auto& s) -> auto& { return s.path; })
               .required(),
           enum_key<S>("/colors", kColors, "mesh",
                       "mesh: the mesh's own vertex colours, if any; level: each vertex's refinement level as a "
                       "colour (grey = input, blue to red = deeper).",
                       [](auto& s) -> auto& { return s.colors_by_level; }),
           key<S>("/preview", schema_text(), nullptr,
                  "Also renders the mesh with every lattice's control net over it to this PNG (1280 x 960, iso "
                  "view); relative to the output folder.",
                  [](auto& s) -> auto& { return s.preview; })}};
}

void SaveStep::run(Scene& scene, StepContext& ctx) const {
  WriteOptions options = scene.write_options();
  if (colors_by_level) {
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
  if (preview) {
    ctx.stats["preview"] = *preview;
    ctx.stats["preview_bytes"] = stage_preview(scene, (std::filesystem::path(scene.output_folder) / *preview).string());
    ctx.summary += ", preview " + *preview;
  }
}

}  // namespace

const OpInfo& save_op() {
  static const OpDecl<SaveStep> op{
      "save", "Writes the current mesh; the format follows the extension (.obj .off .ply .stl .gltf .glb).", save_keys()};
  return op;
}

}  // namespace ffd
