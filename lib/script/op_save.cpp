// The save op: write the current mesh mid-script.
#include <algorithm>
#include <filesystem>
#include <optional>

#include "common/numbers.h"
#include "multires/octree_lattice.h"
#include "remesh/adaptive_remesher.h"
#include "render/control_net.h"
#include "script/op.h"
#include "script/output_files.h"

namespace ffd {
namespace {

const std::vector<std::pair<std::string, bool>> kColors = {{"mesh", false}, {"level", true}};

struct SaveStep final : Step {
  std::string path;
  bool colors_by_level = false;
  std::optional<std::string> preview;
  std::optional<std::string> lattice;
  std::optional<int> level;

  std::vector<OutputFile> outputs() const override {
    std::vector<OutputFile> out = {{"/path", path}};
    if (preview) out.push_back({"/preview", *preview, true});
    return out;
  }
  void check(ScriptChecks& checks) const override;
  void run(Scene& scene, StepContext& ctx) const override;
  void save_net(Scene& scene, StepContext& ctx) const;
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
                  [](auto& s) -> auto& { return s.preview; }),
           key<S>("/lattice", schema_text(), nullptr,
                  "Write this lattice's control net instead of the mesh (OBJ: its points as v, its edges as l), "
                  "where the lattices created after it carry it.",
                  [](auto& s) -> auto& { return s.lattice; }),
           key<S>("/level", schema_integer(0), nullptr, "With an octree lattice: the level (default: the finest).",
                  [](auto& s) -> auto& { return s.level; })}};
}

void SaveStep::check(ScriptChecks& checks) const {
  if (!lattice) {
    if (level) checks.fail(pointer + "/level", "level goes with lattice");
    return;
  }
  checks.check_lattice_level(*lattice, level, pointer);
  if (mesh_format(path) != MeshFormat::Obj)
    checks.fail(pointer + "/path", "a control net is written as OBJ (points and l lines): give the extension .obj");
  if (colors_by_level) checks.fail(pointer + "/colors", "colors are for meshes, not control nets");
}

/// OBJ text of a net: "v x y z" per point, "l a b" per edge (1-based).
void write_net_obj(std::ostream& os, const Overlay& net, const std::string& title) {
  os << "# " << title << ": " << net.points.size() << " points, " << net.edges.size() << " edges\n";
  char line[128];
  for (const Eigen::Vector3d& p : net.points) {
    char* end = line;
    *end++ = 'v';
    for (int a = 0; a < 3; ++a) *end++ = ' ', end = format_number_to(end, p[a]);
    *end++ = '\n';
    os.write(line, end - line);
  }
  for (const auto& e : net.edges) os << "l " << e[0] + 1 << ' ' << e[1] + 1 << '\n';
}

void SaveStep::save_net(Scene& scene, StepContext& ctx) const {
  Overlay net;
  std::string title = "control net of lattice '" + *lattice + "'";
  if (OctreeLattice* octree = scene.octree(*lattice)) {
    const int l = level.value_or(octree->num_levels() - 1);
    net = control_net(*octree, l);
    title += ", level " + std::to_string(l);
    ctx.stats["level"] = l;
  } else {
    net = control_net(scene.lattice(*lattice));
  }
  const std::size_t k = scene.stack.index_of(*lattice);
  for (Eigen::Vector3d& p : net.points) p = scene.stack.carry_from(k, p);
  StagedFile staged{std::filesystem::path(scene.output_folder) / path};
  const std::size_t bytes = staged.write([&](std::ostream& os) { write_net_obj(os, net, title); });
  scene.staged.push_back(std::move(staged));
  ctx.stats["path"] = path;
  ctx.stats["lattice"] = *lattice;
  ctx.stats["points"] = net.points.size();
  ctx.stats["edges"] = net.edges.size();
  ctx.stats["bytes"] = bytes;
  ctx.summary = "save " + path + ": " + title + ", " + format_count(net.points.size()) + " points, " +
                format_count(net.edges.size()) + " edges";
}

void SaveStep::run(Scene& scene, StepContext& ctx) const {
  if (lattice) return save_net(scene, ctx);
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
