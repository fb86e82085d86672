// The move op: lattice control points moved by index (`by` / `to`), or a selection of
// movable points moved by a 9-dof transform about its centroid.
#include "common/numbers.h"
#include "multires/octree_lattice.h"
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
  std::optional<int> level;

  void check(ScriptChecks& checks) const override;
  void check_octree(ScriptChecks& checks, int levels) const;
  void run(Scene& scene, StepContext& ctx) const override;
  std::size_t move_selection(Lattice& target) const;
  void run_octree(Scene& scene, OctreeLattice& target, StepContext& ctx) const;
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
           list_key<S>("/points", point_keys(), "Points moved one by one.", [](auto& s) -> auto& { return s.points; })
               .about("points", "/index"),
           key<S>("/select", schema_ref("selection"), nullptr,
                  "Movable points picked by index or by their current positions.",
                  [](auto& s) -> auto& { return s.select; }),
           key<S>("/transform", schema_ref("transform"), nullptr,
                  "The map applied to the selected points; center: their centroid.",
                  [](auto& s) -> auto& { return s.transform; }),
           key<S>("/level", schema_integer(0), nullptr,
                  "Octree lattices: the level whose points move (default: the finest); index [i, j, k] is a grid "
                  "node of that level, 0 <= i, j, k <= 2^level. Moving a finer level after a coarser one edits "
                  "hierarchically: the finer level follows the coarser one's deformation.",
                  [](auto& s) -> auto& { return s.level; })},
          {{"points"}, {"select", "transform"}}};
}

void MoveStep::check_octree(ScriptChecks& checks, int levels) const {
  // A local level's nodes are at twice its source's resolution; the run checks them.
  const int top = 1 << std::min(level.value_or(levels), checks.octrees.at(lattice) + 1);
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int a = 0; a < 3; ++a)
      if (points[i].index[a] < 0 || points[i].index[a] > top)
        checks.fail(pointer + "/points/" + std::to_string(i) + "/index",
                    "point " + write_value(points[i].index).dump() + " is not movable (movable: " +
                        octree_points_text(level.value_or(levels), top) + ")");
}

void MoveStep::check(ScriptChecks& checks) const {
  if (const int levels = checks.check_lattice_level(lattice, level, pointer); levels >= 0)
    return check_octree(checks, levels);
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

void MoveStep::run_octree(Scene& scene, OctreeLattice& target, StepContext& ctx) const {
  const int l = level.value_or(target.num_levels() - 1);
  const Eigen::Matrix3Xd shown = target.points(l);
  std::vector<std::int32_t> ids;
  std::vector<Eigen::Vector3d> targets;
  if (select) {
    for (std::size_t p : select_octree_points(*select, target, l)) ids.push_back(static_cast<std::int32_t>(p));
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (std::int32_t id : ids) centroid += shown.col(id);
    centroid /= static_cast<double>(ids.size());
    for (std::int32_t id : ids) targets.push_back(transform->apply(shown.col(id), centroid));
  } else {
    for (std::size_t i = 0; i < points.size(); ++i) {
      const std::int32_t id = target.point_index(l, points[i].index);
      if (id < 0)
        throw InputError("point " + write_value(points[i].index).dump() + " is no corner of a cell of level " +
                             std::to_string(l) + " (its cells were cut: they hold no vertex of the region)",
                         {"points", i});
      ids.push_back(id);
      targets.push_back(points[i].by ? Eigen::Vector3d(shown.col(id) + *points[i].by) : *points[i].to);
    }
  }
  const OctreeMove moved = target.move_points(l, ids, targets);
  const WarpStack::Update update = scene.stack.update(scene.mesh, lattice);
  ctx.stats["lattice"] = lattice;
  ctx.stats["level"] = l;
  ctx.stats["points_moved"] = moved.points_moved;
  ctx.stats["cells_subdivided"] = moved.cells_subdivided;
  ctx.stats["cells_relocated"] = moved.cells_marked;
  report_update(scene, update, ctx);
  ctx.summary = "move '" + lattice + "' level " + std::to_string(l) + ": " + format_count(moved.points_moved) +
                " points, " + format_count(moved.cells_subdivided) + " cells subdivided, " +
                format_count(update.moved) + " vertices moved";
}

void MoveStep::run(Scene& scene, StepContext& ctx) const {
  if (OctreeLattice* octree = scene.octree(lattice)) return run_octree(scene, *octree, ctx);
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
