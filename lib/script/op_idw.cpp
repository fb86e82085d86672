// The idw op: a named inverse-distance-weighting deformer (Shepard: warp/idw_deformer.h)
// on top of the warp stack, its control points given as the rbf op's are.
#include "common/numbers.h"
#include "script/op.h"
#include "script/scattered_steps.h"
#include "warp/idw_deformer.h"

namespace ffd {
namespace {

struct IdwStep final : Step {
  bool needs_vertex_normals() const override { return false; }
  std::string name;
  double power = 2;
  PointSource points;

  void check(ScriptChecks& checks) const override;
  void run(Scene& scene, StepContext& ctx) const override;
};

KeyTable<IdwStep> idw_keys() {
  using S = IdwStep;
  return {{key<S>("/name", schema_text(), nullptr, "Name used by later steps (move's and drag's lattice key).",
                  [](auto& s) -> auto& { return s.name; })
               .required(),
           key<S>("/power", schema_number(0), 2,
                  "p, Shepard's exponent: weights |x - x_i|^-p (positive). PyGeM's IDW takes its power as the "
                  "order of a Minkowski norm and weighs by 1 / distance instead.",
                  [](auto& s) -> auto& { return s.power; })
               .about("power"),
           key<S>("/points", schema_ref("points"), nullptr,
                  "The control points at rest; move gives their targets (the map interpolates them).",
                  [](auto& s) -> auto& { return s.points; })
               .required()
               .about("points")}};
}

void IdwStep::check(ScriptChecks& checks) const {
  checks.check_new_lattice(name, pointer + "/name");
  if (!(power > 0)) checks.fail(pointer + "/power", "the power must be positive");
  check_point_source(points);
  checks.deformers[name] = scattered_shape("idw", points.select ? 0 : points.points.size(), "control points");
}

void IdwStep::run(Scene& scene, StepContext& ctx) const {
  auto made = std::make_unique<IdwDeformer>(rest_points(points, scene), power);
  IdwDeformer* raw = made.get();
  scene.stack.push(scene.mesh, name, std::move(made));
  scene.deformers[name] = raw;
  ctx.stats["name"] = name;
  ctx.stats["basis"] = "idw";
  ctx.stats["power"] = power;
  ctx.stats["control_points"] = raw->num_points(0);
  ctx.summary = "idw '" + name + "': power " + format_number(power) + ", " + format_count(raw->num_points(0)) +
                " control points";
}

}  // namespace

const OpInfo& idw_op() {
  static const OpDecl<IdwStep> op{"idw",
                                  "Creates a named inverse-distance-weighting deformer (Shepard: x + sum w_i d_i / "
                                  "sum w_i, w_i = |x - x_i|^-p, d_i the control points' moves) on top of the warp "
                                  "stack.",
                                  idw_keys()};
  return op;
}

}  // namespace ffd
