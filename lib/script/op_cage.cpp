// The cage op: a named cage deformer (mean value coordinates: warp/cage_deformer.h) on top
// of the warp stack, its cage a mesh file in any format ffdtool reads. Its vertices are
// the control points: move (by number or from a posed cage's file), drag, save's net (the
// posed cage, with its faces) and sensitivities work on it through the Deformer seam.
#include "common/numbers.h"
#include "script/op.h"
#include "script/scattered_steps.h"
#include "warp/cage_deformer.h"

namespace ffd {
namespace {

/// The most memory a cage's binding may take: beyond it, points are evaluated afresh at
/// every pose (the same result, slower).
constexpr std::size_t kMaxBindingBytes = std::size_t{2} << 30;

enum class Coordinates { MeanValue };
const std::vector<std::pair<std::string, Coordinates>> kCoordinates = {{"mean_value", Coordinates::MeanValue}};
const std::vector<std::pair<std::string, CageDeformer::Binding>> kBindings = {
    {"none", CageDeformer::Binding::None},
    {"weights", CageDeformer::Binding::Weights},
    {"weights and gradients", CageDeformer::Binding::WeightsAndGradients}};

struct CageStep final : Step {
  std::string name;
  MeshSource cage;
  Coordinates coordinates = Coordinates::MeanValue;

  void check(ScriptChecks& checks) const override;
  void run(Scene& scene, StepContext& ctx) const override;
};

KeyTable<CageStep> cage_keys() {
  using S = CageStep;
  return {{key<S>("/name", schema_text(), nullptr, "Name used by later steps (move's and drag's lattice key).",
                  [](auto& s) -> auto& { return s.name; })
               .required(),
           key<S>("/cage", schema_text(), nullptr,
                  "The cage at rest: a closed, consistently oriented mesh file in any format ffdtool reads, "
                  "relative to the script. Polygons are split into fans from their first corner. Its vertices "
                  "are the control points, numbered as in the file.",
                  [](auto& s) -> auto& { return s.cage; })
               .required()
               .about("cage"),
           enum_key<S>("/coordinates", kCoordinates, "mean_value",
                       "The generalized barycentric coordinates: mean_value (Ju, Schaefer and Warren 2005), defined "
                       "inside and outside the cage.",
                       [](auto& s) -> auto& { return s.coordinates; })}};
}

void CageStep::check(ScriptChecks& checks) const {
  checks.check_new_lattice(name, pointer + "/name");
  checks.deformers[name] = scattered_shape("cage", cage.points.size(), "cage vertices");
}

void CageStep::run(Scene& scene, StepContext& ctx) const {
  auto made = std::make_unique<CageDeformer>(cage.points, cage.faces);
  CageDeformer* raw = made.get();
  const auto positions = scene.mesh.positions();
  const bool normals = !scene.mesh.normals().isZero(0.0);
  std::size_t outside = 0;
  const CageDeformer::Binding binding = raw->bind(positions, normals, kMaxBindingBytes, outside);
  scene.stack.push(scene.mesh, name, std::move(made));
  scene.deformers[name] = raw;
  ctx.stats["name"] = name;
  ctx.stats["basis"] = "cage";
  ctx.stats["coordinates"] = name_of(kCoordinates, coordinates);
  ctx.stats["cage"] = cage.file;
  ctx.stats["cage_vertices"] = raw->num_points(0);
  ctx.stats["cage_faces"] = raw->faces().size();
  ctx.stats["cage_triangles"] = raw->num_triangles();
  ctx.stats["binding"] = name_of(kBindings, binding);
  ctx.stats["vertices_outside"] = outside;
  if (outside)
    scene.warnings.push_back(ctx.pointer + ": " + format_count(outside) + " vertices lie outside cage '" + name +
                             "': mean value coordinates deform them too, by extrapolation; enlarge the cage to "
                             "enclose them");
  ctx.summary = "cage '" + name + "': " + format_count(raw->num_points(0)) + " vertices, " +
                format_count(raw->num_triangles()) + " triangles, " + format_count(outside) + " mesh vertices outside";
}

}  // namespace

const OpInfo& cage_op() {
  static const OpDecl<CageStep> op{"cage",
                                   "Creates a named cage deformer (mean value coordinates: x + sum w_j(x) (p_j - r_j) "
                                   "over the cage's vertices) on top of the warp stack.",
                                   cage_keys()};
  return op;
}

}  // namespace ffd
