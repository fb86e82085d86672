// The drag op: direct manipulation (Hsu, Hughes & Kaufman 1992). Object points go to
// targets by the least-norm change of the lattice's movable points.
#include <cstdio>

#include "common/numbers.h"
#include "script/lattice_reports.h"
#include "script/op.h"
#include "warp/drag.h"

namespace ffd {
namespace {

struct DragPoint {
  std::optional<Eigen::Vector3d> at;
  std::optional<long long> vertex;
  Eigen::Vector3d to = Eigen::Vector3d::Zero();
};

struct DragStep final : Step {
  bool needs_vertex_normals() const override { return false; }
  std::string lattice;
  std::vector<DragPoint> points;
  std::optional<int> level;

  void check(ScriptChecks& checks) const override;
  void run(Scene& scene, StepContext& ctx) const override;
  void object_points(const Scene& scene, std::vector<Eigen::Vector3d>& at, std::vector<Eigen::Vector3d>& to) const;
  void report(Scene& scene, double scale, const DragResult& result, StepContext& ctx) const;
};

KeyTable<DragPoint> point_keys() {
  using P = DragPoint;
  return {{key<P>("/at", schema_ref("vec3"), nullptr, "An object point, where it is before this lattice deforms it.",
                  [](auto& p) -> auto& { return p.at; }),
           key<P>("/vertex", schema_integer(0), nullptr, "A mesh vertex as the object point.",
                  [](auto& p) -> auto& { return p.vertex; }),
           key<P>("/to", schema_ref("vec3"), nullptr, "Where the point must go.", [](auto& p) -> auto& { return p.to; })
               .required()},
          {{"at"}, {"vertex"}}};
}

KeyTable<DragStep> drag_keys() {
  using S = DragStep;
  return {{key<S>("/lattice", schema_text(), nullptr, "Name of a lattice created earlier.",
                  [](auto& s) -> auto& { return s.lattice; })
               .required()
               .about("lattice"),
           list_key<S>("/points", point_keys(), "Object points and their targets.",
                       [](auto& s) -> auto& { return s.points; })
               .required()
               .about("points", "/vertex"),
           key<S>("/level", schema_integer(0), nullptr,
                  "Octree lattices: the level whose points change (default: the finest).",
                  [](auto& s) -> auto& { return s.level; })}};
}

void DragStep::check(ScriptChecks& checks) const { checks.check_lattice_level(lattice, level, pointer); }

void DragStep::object_points(const Scene& scene, std::vector<Eigen::Vector3d>& at, std::vector<Eigen::Vector3d>& to) const {
  const std::size_t k = scene.stack.index_of(lattice);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const DragPoint& point = points[i];
    if (point.vertex) {
      const long long v = *point.vertex;
      if (static_cast<unsigned long long>(v) >= scene.mesh.num_vertices())
        throw InputError("vertex " + std::to_string(v) + " is out of range (the mesh has " +
                             std::to_string(scene.mesh.num_vertices()) + " vertices)",
                         {"points", i});
      at.push_back(scene.stack.input_position(scene.mesh, k, static_cast<std::uint32_t>(v)));
    } else {
      at.push_back(*point.at);
    }
    to.push_back(point.to);
  }
}

void DragStep::run(Scene& scene, StepContext& ctx) const {
  Deformer& target = scene.deformer(lattice);
  const int l = level.value_or(target.default_level());
  std::vector<Eigen::Vector3d> at, to;
  object_points(scene, at, to);
  MoveReport moved;
  const DragResult result = drag(target, l, at, to, &moved);
  if (target.has_levels()) ctx.stats["level"] = l;
  for (const MoveReport::Count& count : moved.counts) ctx.stats[count.key] = count.value;
  warn_if_tearing(scene, target, lattice, ctx);
  const WarpStack::Update update = scene.stack.update(scene.mesh, lattice);
  ctx.stats["lattice"] = lattice;
  ctx.stats["object_points"] = at.size();
  ctx.stats["points_changed"] = result.points_changed;
  ctx.stats["residual_max"] = result.max_residual;
  ctx.stats["residual_rms"] = result.rms_residual;
  ctx.stats["unreachable"] = result.unreachable;
  report_update(scene, update, ctx);
  report(scene, target.scale(), result, ctx);
  ctx.summary += format_count(update.moved) + " vertices moved";
}

// Warnings about unreachable or conflicting targets, and the summary's start.
void DragStep::report(Scene& scene, double scale, const DragResult& result, StepContext& ctx) const {
  if (result.unreachable)
    scene.warnings.push_back(ctx.pointer + ": " + std::to_string(result.unreachable) +
                             " object points lie where no movable control point reaches (outside the deformable zone)");
  else if (result.max_residual > 1e-9 * scale)
    scene.warnings.push_back(ctx.pointer + ": the targets conflict; least-squares residual " +
                             std::to_string(result.max_residual));
  char residual[32];
  std::snprintf(residual, sizeof residual, "%.3g", result.max_residual);
  ctx.summary = "drag '" + lattice + "': " + format_count(points.size()) + " object points, " +
                format_count(result.points_changed) + " control points changed, residual " + residual + ", ";
}

}  // namespace

const OpInfo& drag_op() {
  static const OpDecl<DragStep> op{"drag",
                                   "Direct manipulation (Hsu, Hughes & Kaufman 1992): object points go to targets by "
                                   "the least-norm change of the lattice's movable points.",
                                   drag_keys()};
  return op;
}

}  // namespace ffd
