// The move op: lattice control points moved by index (`by` / `to`), or a selection of
// movable points moved by a 9-dof transform about its centroid.
#include "common/numbers.h"
#include "script/lattice_reports.h"
#include "script/op.h"
#include "script/selection.h"

namespace ffd {
namespace {

struct MovePoint {
  Index3 index{0, 0, 0};
  std::optional<Eigen::Vector3d> by, to;
};

struct MoveStep final : Step {
  std::string lattice;
  std::vector<MovePoint> points;
  std::optional<Selection> select;
  std::optional<Transform> transform;

  void check(ScriptChecks& checks) const override;
  void run(Scene& scene, StepContext& ctx) const override;
  std::size_t move_selection(Lattice& target) const;
};

KeyTable<MovePoint> point_keys() {
  using P = MovePoint;
  return {{key<P>("/index", schema_ref("index3"), nullptr, "The control point [i, j, k].",
                  [](auto& p) -> auto& { return p.index; })
               .required(),
           key<P>("/by", schema_ref("vec3"), nullptr, "Displacement added to the point's current position.",
                  [](auto& p) -> auto& { return p.by; }),
           key<P>("/to", schema_ref("vec3"), nullptr, "The point's new position.",
                  [](auto& p) -> auto& { return p.to; })},
          {{"by"}, {"to"}}};
}

KeyTable<MoveStep> move_keys() {
  using S = MoveStep;
  return {{key<S>("/lattice", schema_text(), nullptr, "Name of a lattice created earlier.",
                  [](auto& s) -> auto& { return s.lattice; })
               .required()
               .about("lattice"),
           list_key<S>("/points", point_keys(), "Points moved one by one.", [](auto& s) -> auto& { return s.points; }),
           key<S>("/select", schema_ref("selection"), nullptr,
                  "Movable points picked by index or by their current positions.",
                  [](auto& s) -> auto& { return s.select; }),
           key<S>("/transform", schema_ref("transform"), nullptr,
                  "The map applied to the selected points; center: their centroid.",
                  [](auto& s) -> auto& { return s.transform; })},
          {{"points"}, {"select", "transform"}}};
}

void MoveStep::check(ScriptChecks& checks) const {
  const LatticeSpec& shape = checks.lattice_of(lattice, pointer + "/lattice");
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int a = 0; a < 3; ++a) {
      int lo, hi;
      movable_span(shape, a, lo, hi);
      const int v = points[i].index[a];
      if (v < lo || v > hi)
        checks.fail(pointer + "/points/" + std::to_string(i) + "/index", "point " +
                                                                             write_value(points[i].index).dump() +
                                                                             " is not movable (movable: " +
                                                                             movable_text(shape) + ")");
    }
}

std::size_t MoveStep::move_selection(Lattice& target) const {
  const std::vector<std::size_t> picked = select_lattice_points(*select, target);
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> current;
  for (std::size_t f : picked) {
    current.push_back(target.point(target.index(f)));
    centroid += current.back();
  }
  centroid /= static_cast<double>(picked.size());
  for (std::size_t i = 0; i < picked.size(); ++i)
    target.move_point(target.index(picked[i]), transform->apply(current[i], centroid));
  return picked.size();
}

void MoveStep::run(Scene& scene, StepContext& ctx) const {
  Lattice& target = scene.lattice(lattice);
  std::size_t moved_points = 0;
  if (select) {
    moved_points = move_selection(target);
  } else {
    for (const MovePoint& point : points) {
      target.move_point(point.index, point.by ? Eigen::Vector3d(target.point(point.index) + *point.by) : *point.to);
      ++moved_points;
    }
  }
  const WarpStack::Update update = scene.stack.update(scene.mesh, lattice);
  ctx.stats["lattice"] = lattice;
  ctx.stats["points_moved"] = moved_points;
  report_update(scene, update, ctx);
  warn_if_tearing(scene, target, lattice, ctx);
  ctx.summary = "move '" + lattice + "': " + format_count(moved_points) + " points, " + format_count(update.moved) +
                " vertices moved";
}

}  // namespace

const OpInfo& move_op() {
  static const OpDecl<MoveStep> op{
      "move", "Moves lattice control points: listed points by `by`/`to`, or a selection by a transform.",
      move_keys()};
  return op;
}

}  // namespace ffd
