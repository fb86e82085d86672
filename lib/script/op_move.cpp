// The move op: control points of a deformer's level moved by index (`by` / `to`), a
// selection of movable points moved by a 9-dof transform about its centroid, or every
// point set from a file of positions (a control net the save op wrote, edited elsewhere).
#include <algorithm>

#include "common/numbers.h"
#include "script/lattice_reports.h"
#include "script/op.h"
#include "script/selection.h"

namespace ffd {
namespace {

struct MovePoint {
  PointIndex index;
  std::optional<Eigen::Vector3d> by, to;
};

/// The points a move changes and where they go.
struct MoveTargets {
  std::vector<std::size_t> ids;
  std::vector<Eigen::Vector3d> targets;
};

struct MoveStep final : Step {
  bool needs_vertex_normals() const override { return false; }
  std::string lattice;
  std::vector<MovePoint> points;
  std::optional<Selection> select;
  std::optional<Transform> transform;
  std::optional<PointPositions> positions;
  std::optional<int> level;

  void check(ScriptChecks& checks) const override;
  void run(Scene& scene, StepContext& ctx) const override;
  MoveTargets listed(const Deformer& target, int l) const;
  MoveTargets selected(const Deformer& target, int l) const;
  MoveTargets from_file(Scene& scene, const Deformer& target, int l, const StepContext& ctx) const;
};

KeyTable<MovePoint> point_keys() {
  using P = MovePoint;
  return {{key<P>("/index", schema_ref("point_index"), nullptr,
                  "The control point: [i, j, k] on a lattice, its number on scattered points (rbf, idw) and cages.",
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
           group_key<S>("/positions",
                        "Every point of the level, in the order the save op writes the lattice's net: each movable "
                        "point goes there (points already there stay untouched); a fixed point whose position differs "
                        "is reported in a warning. The lattice's net must be saved as it is (no lattice created after "
                        "it deforms it)."),
           key<S>("/positions/file", schema_text(), nullptr,
                  "An OBJ file's v lines (a control net the save op wrote, edited anywhere), or a text file of "
                  "x y z lines; relative to the script's folder.",
                  [](auto& s) -> auto& { return s.positions; })
               .required()
               .about("positions"),
           key<S>("/level", schema_integer(0), nullptr,
                  "Octree lattices: the level whose points move (default: the finest); index [i, j, k] is a grid "
                  "node of that level, 0 <= i, j, k <= 2^level. Moving a finer level after a coarser one edits "
                  "hierarchically: the finer level follows the coarser one's deformation.",
                  [](auto& s) -> auto& { return s.level; })},
          {{"points"}, {"select", "transform"}, {"positions"}}};
}

void MoveStep::check(ScriptChecks& checks) const {
  const int l = checks.check_lattice_level(lattice, level, pointer);
  const DeformerShape& shape = checks.deformers.at(lattice);
  for (std::size_t i = 0; i < points.size(); ++i)
    checks.check_point_index(shape, l, points[i].index, pointer + "/points/" + std::to_string(i) + "/index");
  if (select) check_point_selection(*select, shape, l);
}

// Listed points, in order; a point listed again moves on from where the list put it. The
// points' current positions come in one call (an octree level computes them all at once).
MoveTargets MoveStep::listed(const Deformer& target, int l) const {
  MoveTargets out;
  std::vector<std::size_t> slot(points.size());  // listed point i -> its entry in out
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::optional<std::size_t> id = target.find_point(l, points[i].index);
    if (!id) throw InputError(target.missing_point(l, points[i].index), {"points", i});
    slot[i] = static_cast<std::size_t>(std::find(out.ids.begin(), out.ids.end(), *id) - out.ids.begin());
    if (slot[i] == out.ids.size()) out.ids.push_back(*id);
  }
  const Eigen::Matrix3Xd now = target.points(l, out.ids);
  for (Eigen::Index c = 0; c < now.cols(); ++c) out.targets.push_back(now.col(c));
  for (std::size_t i = 0; i < points.size(); ++i) {
    Eigen::Vector3d& to = out.targets[slot[i]];
    to = points[i].by ? Eigen::Vector3d(to + *points[i].by) : *points[i].to;
  }
  return out;
}

MoveTargets MoveStep::selected(const Deformer& target, int l) const {
  MoveTargets out;
  out.ids = select_points(*select, target, l);
  const Eigen::Matrix3Xd current = target.points(l, out.ids);
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (Eigen::Index i = 0; i < current.cols(); ++i) centroid += current.col(i);
  centroid /= static_cast<double>(out.ids.size());
  for (Eigen::Index i = 0; i < current.cols(); ++i) out.targets.push_back(transform->apply(current.col(i), centroid));
  return out;
}

/// Fails unless the warps created after lattice `name` leave every point of `now` where it
/// is: positions are read as the save op writes the net, carried through those warps.
void check_net_not_carried(const Scene& scene, const std::string& name, const Eigen::Matrix3Xd& now) {
  const std::size_t k = scene.stack.index_of(name);
  if (k + 1 >= scene.stack.size()) return;
  for (Eigen::Index p = 0; p < now.cols(); ++p)
    if (scene.stack.carry_from(k, now.col(p)) != now.col(p)) {
      std::string later;
      for (std::size_t j = k + 1; j < scene.stack.size(); ++j) later += (later.empty() ? "'" : ", '") + scene.stack.name(j) + "'";
      throw InputError("lattice '" + name + "' is deformed by the lattices created after it (" + later +
                           "), so its saved net is not its own points; set its positions before creating them",
                       {"positions"});
    }
}

// Every point of the level from the file, in net order: the movable points that differ move
// there; a fixed point that differs stays, and a warning says so.
MoveTargets MoveStep::from_file(Scene& scene, const Deformer& target, int l, const StepContext& ctx) const {
  const std::vector<Eigen::Vector3d>& given = positions->points;
  const std::size_t n = target.num_points(l);
  if (given.size() != n)
    throw InputError("'" + positions->file + "' has " + format_count(given.size()) + " points; level " +
                         std::to_string(l) + " of lattice '" + lattice + "' has " + format_count(n),
                     {"positions"});
  const Eigen::Matrix3Xd now = target.points(l);
  check_net_not_carried(scene, lattice, now);
  MoveTargets out;
  std::vector<std::size_t> fixed;
  for (std::size_t id = 0; id < n; ++id) {
    if (given[id] == now.col(static_cast<Eigen::Index>(id))) continue;
    if (!target.point_movable(l, id)) {
      fixed.push_back(id);
      continue;
    }
    out.ids.push_back(id);
    out.targets.push_back(given[id]);
  }
  if (!fixed.empty())
    scene.warnings.push_back(ctx.pointer + ": " + format_count(fixed.size()) + " fixed points of lattice '" +
                             lattice + "' differ in '" + positions->file + "' (the first: its point " +
                             std::to_string(fixed[0] + 1) + ", index " + target.point_index(l, fixed[0]).text() +
                             "); they stay where they are (movable: " +
                             target.movable_text(l) + ")");
  return out;
}

void MoveStep::run(Scene& scene, StepContext& ctx) const {
  Deformer& target = scene.deformer(lattice);
  const int l = level.value_or(target.default_level());
  const MoveTargets move = select ? selected(target, l) : positions ? from_file(scene, target, l, ctx) : listed(target, l);
  const MoveReport moved = target.move_points(l, move.ids, move.targets);
  const WarpStack::Update update = scene.stack.update(scene.mesh, lattice);
  ctx.stats["lattice"] = lattice;
  if (target.has_levels()) ctx.stats["level"] = l;
  ctx.stats["points_moved"] = moved.points_moved;
  ctx.summary = "move '" + lattice + "'" + (target.has_levels() ? " level " + std::to_string(l) : "") + ": " +
                format_count(moved.points_moved) + " points, ";
  for (const MoveReport::Count& count : moved.counts) {
    ctx.stats[count.key] = count.value;
    if (!count.summary.empty()) ctx.summary += format_count(count.value) + " " + count.summary + ", ";
  }
  if (positions) ctx.stats["positions"] = positions->file;
  report_update(scene, update, ctx);
  warn_if_tearing(scene, target, lattice, ctx);
  ctx.summary += format_count(update.moved) + " vertices moved";
}

}  // namespace

const OpInfo& move_op() {
  static const OpDecl<MoveStep> op{"move",
                                   "Moves lattice control points: listed points by `by`/`to`, a selection by a "
                                   "transform, or every point to positions from a file.",
                                   move_keys()};
  return op;
}

}  // namespace ffd
