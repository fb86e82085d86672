// The lattice op: a named lattice on top of the warp stack.
#include "common/numbers.h"
#include "script/op.h"
#include "script/selection.h"
#include "warp/bernstein_lattice.h"
#include "warp/box_fit.h"
#include "warp/lattice_spec.h"

namespace ffd {
namespace {

const std::vector<std::pair<std::string, Lattice::Basis>> kBases = {{"bspline", Lattice::Basis::BSpline},
                                                                     {"bernstein", Lattice::Basis::Bernstein}};

struct LatticeStep final : Step {
  std::string name;
  LatticeSpec lattice;
  BoxSpec box;

  void check(ScriptChecks& checks) const override;
  void run(Scene& scene, StepContext& ctx) const override;
};

KeyTable<LatticeStep> lattice_keys() {
  using S = LatticeStep;
  const nlohmann::json cells = {{"type", "array"}, {"items", schema_integer(1, 1000)}, {"minItems", 3}, {"maxItems", 3}};
  return {{
      key<S>("/name", schema_text(), nullptr, "Name used by later steps.", [](auto& s) -> auto& { return s.name; })
          .required(),
      enum_key<S>("/basis", kBases, "bspline",
                  "bspline: uniform B-spline with fixed influenced and phantom zones (identity outside the box, "
                  "C^(degree-1) across it). bernstein: Sederberg & Parry's Bézier volume.",
                  [](auto& s) -> auto& { return s.lattice.basis; }),
      key<S>("/degree", schema_integer(1, 3), 3,
             "B-spline degree (bspline only; a Bernstein lattice's degree per axis is its cell count).",
             [](auto& s) -> auto& { return s.lattice.degree; }),
      key<S>("/box", schema_ref("box"), write_value(BoxSpec{}), "The lattice's box.",
             [](auto& s) -> auto& { return s.box; })
          .about("box"),
      key<S>("/cells", cells, nullptr,
             "Cells per axis [l, m, n]: B-spline knot spans across the box, or Bernstein degrees.",
             [](auto& s) -> auto& { return s.lattice.cells; })
          .required(),
  }};
}

void LatticeStep::check(ScriptChecks& checks) const {
  if (checks.lattices.count(name)) checks.fail(pointer + "/name", "a lattice named '" + name + "' already exists");
  const bool bspline = lattice.basis == Lattice::Basis::BSpline;
  double points = 1;
  for (int a = 0; a < 3; ++a) {
    const std::string cell = pointer + "/cells/" + std::to_string(a);
    if (!bspline && lattice.cells[a] > BernsteinLattice::kMaxDegree)
      checks.fail(cell, "a Bernstein lattice's degree per axis is at most " +
                            std::to_string(BernsteinLattice::kMaxDegree) + "; use basis \"bspline\" for finer lattices");
    if (bspline && lattice.cells[a] < lattice.degree + 1)
      checks.fail(cell, "a degree-" + std::to_string(lattice.degree) + " B-spline lattice needs at least " +
                            std::to_string(lattice.degree + 1) +
                            " cells per axis to have a movable point (its influenced and phantom zones stay fixed)");
    points *= lattice.cells[a] + (bspline ? lattice.degree : 1);
  }
  if (points > 16.0 * 1024 * 1024) checks.fail(pointer + "/cells", "the lattice would have more than 16M control points");
  checks.lattices[name] = lattice;
}

Parallelepiped make_box(const Scene& scene, const BoxSpec& box) {
  if (box.kind == BoxSpec::Kind::MinMax) return Parallelepiped::from_min_max(box.min, box.max);
  if (box.kind == BoxSpec::Kind::OriginAxes) return Parallelepiped(box.origin, box.axes);
  std::vector<std::uint32_t> ids;
  if (box.select) ids = select_vertices(*box.select, scene.mesh.positions());
  const auto positions = scene.mesh.positions();
  switch (box.fit) {
    case BoxSpec::Fit::Obb:
      return fit_principal_box(positions, ids, box.padding);
    case BoxSpec::Fit::MinVolume:
      return fit_min_volume_box(positions, ids, box.padding);
    case BoxSpec::Fit::Aabb:
      break;
  }
  return fit_aabb(positions, ids, box.padding);
}

nlohmann::json vec_json(const Eigen::Vector3d& v) { return write_value(v); }

void LatticeStep::run(Scene& scene, StepContext& ctx) const {
  const Parallelepiped placed = concerning("box", [&] { return make_box(scene, box); });
  std::unique_ptr<Lattice> made = make_lattice(lattice, placed);
  Lattice* raw = made.get();
  scene.stack.push(scene.mesh, name, std::move(made));
  scene.lattices[name] = raw;

  std::size_t movable = 0, inside = 0;
  for (std::size_t f = 0; f < raw->num_points(); ++f) movable += raw->movable(raw->index(f));
  const auto positions = scene.mesh.positions();
  for (Eigen::Index v = 0; v < positions.cols(); ++v) inside += Lattice::inside(placed.to_local(positions.col(v)));
  const Index3 degree = raw->degree();
  const std::string basis = name_of(kBases, lattice.basis);
  const Index3& cells = lattice.cells;
  ctx.stats["name"] = name;
  ctx.stats["basis"] = basis;
  ctx.stats["degree"] = write_value(degree);
  ctx.stats["cells"] = write_value(cells);
  ctx.stats["control_points"] = raw->num_points();
  ctx.stats["movable_points"] = movable;
  ctx.stats["vertices_inside"] = inside;
  ctx.stats["box"] = {{"origin", vec_json(placed.origin())},
                      {"axes", {vec_json(placed.axes().col(0)), vec_json(placed.axes().col(1)),
                                vec_json(placed.axes().col(2))}}};
  ctx.stats["boundary_continuity"] = raw->boundary_continuity();
  ctx.summary = "lattice '" + name + "': " + basis +
                (lattice.basis == Lattice::Basis::BSpline ? " degree " + std::to_string(degree[0]) : std::string()) +
                ", " + std::to_string(cells[0]) + "x" + std::to_string(cells[1]) + "x" + std::to_string(cells[2]) +
                " cells, " + format_count(raw->num_points()) + " points (" + format_count(movable) + " movable), " +
                format_count(inside) + " vertices inside";
  if (inside == 0) scene.warnings.push_back(ctx.pointer + ": lattice '" + name + "' contains no mesh vertex");
}

}  // namespace

const OpInfo& lattice_op() {
  static const OpDecl<LatticeStep> op{"lattice", "Creates a named lattice on top of the warp stack.", lattice_keys()};
  return op;
}

}  // namespace ffd
