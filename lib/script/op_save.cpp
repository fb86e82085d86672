// The save op: write the current mesh mid-script, a deformer's control net, or the
// sensitivities of the mesh to a deformer's points (dx/dp, Matrix Market).
#include <algorithm>
#include <filesystem>
#include <optional>

#include "common/numbers.h"
#include "remesh/adaptive_remesher.h"
#include "render/control_net.h"
#include "script/op.h"
#include "script/output_files.h"
#include "warp/sensitivity.h"

namespace ffd {
namespace {

const std::vector<std::pair<std::string, bool>> kColors = {{"mesh", false}, {"level", true}};

struct SaveStep final : Step {
  std::string path;
  bool colors_by_level = false;
  std::optional<std::string> preview;
  std::optional<std::string> lattice;
  std::optional<int> level;
  std::optional<std::string> sensitivity;  // the deformer
  std::optional<int> sensitivity_level;

  std::vector<OutputFile> outputs() const override {
    std::vector<OutputFile> out = {{"/path", path, false, sensitivity.has_value()}};
    if (preview) out.push_back({"/preview", *preview, true});
    return out;
  }
  /// A picture shades by them; glTF holds them whatever the input.
  bool needs_vertex_normals() const override {
    if (preview) return true;
    if (lattice || sensitivity) return false;
    const MeshFormat format = mesh_format(path);
    return format == MeshFormat::Gltf || format == MeshFormat::Glb;
  }
  void check(ScriptChecks& checks) const override;
  void run(Scene& scene, StepContext& ctx) const override;
  void save_net(Scene& scene, StepContext& ctx) const;
  void save_sensitivity(Scene& scene, StepContext& ctx) const;
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
                  "Write this lattice's control net instead of the mesh (OBJ: its points as v, its edges as l; a cage's as faces), "
                  "where the lattices created after it carry it.",
                  [](auto& s) -> auto& { return s.lattice; })
               .about("lattice"),
           key<S>("/level", schema_integer(0), nullptr, "With an octree lattice: the level (default: the finest).",
                  [](auto& s) -> auto& { return s.level; }),
           group_key<S>("/sensitivity",
                        "Write dx/dp instead of the mesh: the derivative of every vertex's current position with "
                        "respect to every movable point of a lattice's level, through the lattices created after it "
                        "(chain rule), as a Matrix Market coordinate matrix (.mtx): row 3v + axis, column 3m + axis "
                        "(m: the movable points in the order of the lattice's saved net; 1-based in the file), 17 "
                        "significant digits, a header comment '% point m index i j k' per point."),
           key<S>("/sensitivity/lattice", schema_text(), nullptr,
                  "The lattice (one that a surface edit froze into the mesh has no sensitivity).",
                  [](auto& s) -> auto& { return s.sensitivity; })
               .required()
               .about("sensitivity_lattice"),
           key<S>("/sensitivity/level", schema_integer(0), nullptr,
                  "With an octree lattice: the level whose points p are (default: the finest); the other levels' "
                  "own moves are held, as a move of this level holds them.",
                  [](auto& s) -> auto& { return s.sensitivity_level; })}};
}

void SaveStep::check(ScriptChecks& checks) const {
  if (sensitivity) {
    checks.check_lattice_level(*sensitivity, sensitivity_level, pointer + "/sensitivity");
    if (lattice) checks.fail(pointer + "/lattice", "a control net and sensitivities are separate saves");
    if (level) checks.fail(pointer + "/level", "the level of sensitivities is sensitivity/level");
    if (preview) checks.fail(pointer + "/preview", "a preview goes with a mesh, not with sensitivities");
    if (colors_by_level) checks.fail(pointer + "/colors", "colors are for meshes, not sensitivities");
    return;
  }
  if (!lattice) {
    if (level) checks.fail(pointer + "/level", "level goes with lattice");
    return;
  }
  checks.check_lattice_level(*lattice, level, pointer);
  if (mesh_format(path) != MeshFormat::Obj)
    checks.fail(pointer + "/path", "a control net is written as OBJ (points and l lines): give the extension .obj");
  if (colors_by_level) checks.fail(pointer + "/colors", "colors are for meshes, not control nets");
}

/// OBJ text of a net: "v x y z" per point, then "f a b c ..." per face when the net is a
/// surface (a cage), else "l a b" per edge (1-based).
void write_net_obj(std::ostream& os, const Overlay& net, const std::vector<std::vector<std::uint32_t>>& faces,
                   const std::string& title) {
  os << "# " << title << ": " << net.points.size() << " points, "
     << (faces.empty() ? std::to_string(net.edges.size()) + " edges\n" : std::to_string(faces.size()) + " faces\n");
  char line[128];
  for (const Eigen::Vector3d& p : net.points) {
    char* end = line;
    *end++ = 'v';
    for (int a = 0; a < 3; ++a) *end++ = ' ', end = format_number_to(end, p[a]);
    *end++ = '\n';
    os.write(line, end - line);
  }
  for (const auto& face : faces) {
    os << 'f';
    for (std::uint32_t v : face) os << ' ' << v + 1;
    os << '\n';
  }
  if (faces.empty())
    for (const auto& e : net.edges) os << "l " << e[0] + 1 << ' ' << e[1] + 1 << '\n';
}

void SaveStep::save_net(Scene& scene, StepContext& ctx) const {
  const Deformer& deformer = scene.deformer(*lattice);
  const int l = level.value_or(deformer.default_level());
  Overlay net = control_net(deformer, l);
  std::string title = "control net of lattice '" + *lattice + "'";
  if (deformer.has_levels()) {
    title += ", level " + std::to_string(l);
    ctx.stats["level"] = l;
  }
  const std::size_t k = scene.stack.index_of(*lattice);
  for (Eigen::Vector3d& p : net.points) p = scene.stack.carry_from(k, p);
  StagedFile staged{std::filesystem::path(scene.output_folder) / path};
  const std::vector<std::vector<std::uint32_t>> faces = deformer.net_faces(l);
  const std::size_t bytes = staged.write([&](std::ostream& os) { write_net_obj(os, net, faces, title); });
  scene.staged.push_back(std::move(staged));
  ctx.stats["path"] = path;
  ctx.stats["lattice"] = *lattice;
  ctx.stats["points"] = net.points.size();
  ctx.stats["edges"] = net.edges.size();
  if (!faces.empty()) ctx.stats["faces"] = faces.size();
  ctx.stats["bytes"] = bytes;
  ctx.summary = "save " + path + ": " + title + ", " + format_count(net.points.size()) + " points, " +
                (faces.empty() ? format_count(net.edges.size()) + " edges" : format_count(faces.size()) + " faces");
}

void SaveStep::save_sensitivity(Scene& scene, StepContext& ctx) const {
  const Deformer& deformer = [&]() -> const Deformer& {
    try {
      return scene.deformer(*sensitivity);
    } catch (InputError& e) {  // frozen by a surface edit: placed at this key, not at save's lattice
      e.set_subject({"sensitivity_lattice"});
      throw;
    }
  }();
  const int l = sensitivity_level.value_or(deformer.default_level());
  const std::size_t k = scene.stack.index_of(*sensitivity);
  SensitivityCounts counts;
  StagedFile staged{std::filesystem::path(scene.output_folder) / path};
  const std::size_t bytes =
      staged.write([&](std::ostream& os) { counts = write_sensitivity(os, scene.stack, k, deformer, l, scene.mesh); });
  scene.staged.push_back(std::move(staged));
  ctx.stats["path"] = path;
  ctx.stats["sensitivity"] = *sensitivity;
  if (deformer.has_levels()) ctx.stats["level"] = l;
  ctx.stats["rows"] = counts.rows;
  ctx.stats["columns"] = counts.columns;
  ctx.stats["movable_points"] = counts.points;
  ctx.stats["entries"] = counts.entries;
  ctx.stats["bytes"] = bytes;
  ctx.summary = "save " + path + ": dx/dp of " + format_count(scene.mesh.num_vertices()) + " vertices by " +
                format_count(counts.points) + " points of lattice '" + *sensitivity + "'" +
                (deformer.has_levels() ? " level " + std::to_string(l) : "") + ", " + format_count(counts.entries) +
                " entries";
}

void SaveStep::run(Scene& scene, StepContext& ctx) const {
  if (sensitivity) return save_sensitivity(scene, ctx);
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
