// The rbf op: a named RBF deformer (PyGeM's RBF: warp/rbf_deformer.h) on top of the warp
// stack, its control points given by a list, a file or a selection of mesh vertices. move
// (by index n or from a file of positions), drag, save's net and sensitivities then work
// on it through the Deformer seam.
#include "common/numbers.h"
#include "script/op.h"
#include "script/scattered_steps.h"
#include "warp/rbf_deformer.h"

namespace ffd {
namespace {

const std::vector<std::pair<std::string, RbfKernel>> kKernels = {
    {"gaussian_spline", RbfKernel::Gaussian},
    {"multi_quadratic_biharmonic_spline", RbfKernel::MultiQuadratic},
    {"inv_multi_quadratic_biharmonic_spline", RbfKernel::InvMultiQuadratic},
    {"thin_plate_spline", RbfKernel::ThinPlate},
    {"beckert_wendland_c2_basis", RbfKernel::Wendland},
    {"polyharmonic_spline", RbfKernel::Polyharmonic}};

struct RbfStep final : Step {
  bool needs_vertex_normals() const override { return false; }
  std::string name;
  RbfOptions options;
  PointSource points;

  void check(ScriptChecks& checks) const override;
  void run(Scene& scene, StepContext& ctx) const override;
};

KeyTable<RbfStep> rbf_keys() {
  using S = RbfStep;
  return {{key<S>("/name", schema_text(), nullptr, "Name used by later steps (move's and drag's lattice key).",
                  [](auto& s) -> auto& { return s.name; })
               .required(),
           enum_key<S>("/kernel", kKernels, "gaussian_spline",
                       "PyGeM's kernels, r the distance, R the radius, s = r / R: gaussian_spline exp(-s^2); "
                       "multi_quadratic_biharmonic_spline sqrt(r^2 + R^2); inv_multi_quadratic_biharmonic_spline "
                       "1 / sqrt(r^2 + R^2); thin_plate_spline s^k log s; beckert_wendland_c2_basis "
                       "(1 - s)^4 (4 s + 1), zero beyond R; polyharmonic_spline s^k (odd k), s^k log s (even k).",
                       [](auto& s) -> auto& { return s.options.kernel; }),
           key<S>("/radius", schema_number(0), 0.5, "R, PyGeM's radius (positive).",
                  [](auto& s) -> auto& { return s.options.radius; }),
           key<S>("/k", schema_integer(1, 10), 2, "The power of thin_plate_spline and polyharmonic_spline.",
                  [](auto& s) -> auto& { return s.options.k; }),
           key<S>("/points", schema_ref("points"), nullptr,
                  "The control points at rest; move gives their targets (the map interpolates them).",
                  [](auto& s) -> auto& { return s.points; })
               .required()
               .about("points")}};
}

void RbfStep::check(ScriptChecks& checks) const {
  checks.check_new_lattice(name, pointer + "/name");
  if (!(options.radius > 0)) checks.fail(pointer + "/radius", "the radius must be positive");
  check_point_source(points);
  checks.deformers[name] = scattered_shape("rbf", points.select ? 0 : points.points.size(), "control points");
}

void RbfStep::run(Scene& scene, StepContext& ctx) const {
  auto made = std::make_unique<RbfDeformer>(rest_points(points, scene), options);
  RbfDeformer* raw = made.get();
  scene.stack.push(scene.mesh, name, std::move(made));
  scene.deformers[name] = raw;
  ctx.stats["name"] = name;
  ctx.stats["basis"] = "rbf";
  ctx.stats["kernel"] = name_of(kKernels, options.kernel);
  ctx.stats["radius"] = options.radius;
  ctx.stats["k"] = options.k;
  ctx.stats["control_points"] = raw->num_points(0);
  ctx.stats["condition_number"] = raw->condition();
  ctx.stats["factorization"] = raw->sparse() ? "sparse" : "dense";
  ctx.stats["matrix_entries"] = raw->matrix_entries();
  char condition[32];
  std::snprintf(condition, sizeof condition, "%.3g", raw->condition());
  ctx.summary = "rbf '" + name + "': " + name_of(kKernels, options.kernel) + ", " + format_count(raw->num_points(0)) +
                " control points, condition number " + condition;
}

}  // namespace

const OpInfo& rbf_op() {
  static const OpDecl<RbfStep> op{"rbf",
                                  "Creates a named RBF deformer (PyGeM's RBF: M(x) = c + Q x + sum gamma_i "
                                  "phi(|x - x_i|), interpolating the control points' targets) on top of the warp stack.",
                                  rbf_keys()};
  return op;
}

}  // namespace ffd
