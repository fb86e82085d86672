// The FFD ops: lattice, move, drag.
#include <cmath>
#include <memory>

#include "common/errors.h"
#include "common/numbers.h"
#include "script/ops.h"
#include "script/transform.h"
#include "warp/bernstein_lattice.h"
#include "warp/bspline_lattice.h"
#include "warp/drag.h"

namespace ffd {
namespace {

using json = nlohmann::json;

json vec_json(const Eigen::Vector3d& v) { return json::array({v[0], v[1], v[2]}); }

Parallelepiped make_box(Scene& scene, const json& box, const std::string& pointer) {
  try {
    if (box.contains("min")) return Parallelepiped::from_min_max(parse_vec3(box["min"]), parse_vec3(box["max"]));
    if (box.contains("origin")) {
      Eigen::Matrix3d axes;
      for (int a = 0; a < 3; ++a) axes.col(a) = parse_vec3(box["axes"][a]);
      return Parallelepiped(parse_vec3(box["origin"]), axes);
    }
    std::vector<std::uint32_t> ids;
    if (box.contains("select"))
      ids = select_vertices(box["select"], scene.mesh.positions(), scene.selection_context(pointer + "/select"));
    const double padding = box["padding"];
    return box["fit"] == "obb" ? fit_obb(scene.mesh.positions(), ids, padding)
                               : fit_aabb(scene.mesh.positions(), ids, padding);
  } catch (const InputError& e) {
    const std::string what = e.what();
    if (what.rfind(scene.script_path, 0) == 0) throw;  // already placed (a selection)
    throw InputError(scene.script_path + ": " + pointer + ": " + what);
  }
}

// Warns when a warp that can tear (Bernstein with face points moved) meets mesh vertices
// outside its box: the surface opens where it leaves the box.
void warn_if_tearing(Scene& scene, const Lattice& lattice, const std::string& name, StepContext& ctx) {
  if (lattice.boundary_continuity() >= 0) return;
  const std::size_t k = scene.stack.index_of(name);
  std::size_t outside = 0;
  for (std::uint32_t v = 0; v < scene.mesh.num_vertices(); ++v)
    if (!Lattice::inside(lattice.box().to_local(scene.stack.input_position(scene.mesh, k, v)))) ++outside;
  if (outside == 0) return;
  scene.warnings.push_back(ctx.pointer + ": lattice '" + name + "' moved points on its box's faces while " +
                           format_count(outside) +
                           " vertices lie outside the box: a Bernstein lattice tears the mesh there "
                           "(use basis \"bspline\", or move only interior points)");
}

void report_update(Scene& scene, const WarpStack::Update& update, StepContext& ctx) {
  ctx.stats["vertices_moved"] = update.moved;
  ctx.stats["inverted_jacobians"] = update.folded;
  if (update.folded)
    scene.warnings.push_back(ctx.pointer + ": " + format_count(update.folded) +
                             " vertices where the warp folds space over (Jacobian determinant <= 0); "
                             "the surface self-intersects there");
}

}  // namespace

void check_lattice(ScriptChecks& checks, const json& step, const std::string& p) {
  const std::string name = step["name"];
  if (checks.lattices.count(name)) checks.fail(p + "/name", "a lattice named '" + name + "' already exists");
  LatticeShape shape{step["basis"], step["degree"],
                     {step["cells"][0].get<int>(), step["cells"][1].get<int>(), step["cells"][2].get<int>()}};
  double points = 1;
  for (int a = 0; a < 3; ++a) {
    const std::string cell = p + "/cells/" + std::to_string(a);
    if (shape.basis == "bernstein" && shape.cells[a] > BernsteinLattice::kMaxDegree)
      checks.fail(cell, "a Bernstein lattice's degree per axis is at most " +
                            std::to_string(BernsteinLattice::kMaxDegree) + "; use basis \"bspline\" for finer lattices");
    if (shape.basis == "bspline" && shape.cells[a] < shape.degree + 1)
      checks.fail(cell, "a degree-" + std::to_string(shape.degree) + " B-spline lattice needs at least " +
                            std::to_string(shape.degree + 1) +
                            " cells per axis to have a movable point (its influenced and phantom zones stay fixed)");
    points *= shape.cells[a] + (shape.basis == "bspline" ? shape.degree : 1);
  }
  if (points > 16.0 * 1024 * 1024) checks.fail(p + "/cells", "the lattice would have more than 16M control points");
  if (step["box"].contains("select")) checks.check_selection_files(step["box"]["select"], p + "/box/select");
  checks.lattices[name] = shape;
}

void run_lattice(Scene& scene, const json& step, StepContext& ctx) {
  const std::string name = step["name"];
  const Parallelepiped box = make_box(scene, step["box"], ctx.pointer + "/box");
  const Index3 cells{step["cells"][0].get<int>(), step["cells"][1].get<int>(), step["cells"][2].get<int>()};
  std::unique_ptr<Lattice> lattice;
  if (step["basis"] == "bernstein")
    lattice = std::make_unique<BernsteinLattice>(box, cells);
  else
    lattice = std::make_unique<BSplineLattice>(box, cells, step["degree"].get<int>());
  Lattice* raw = lattice.get();
  scene.stack.push(scene.mesh, name, std::move(lattice));
  scene.lattices[name] = raw;

  std::size_t movable = 0, inside = 0;
  for (std::size_t f = 0; f < raw->num_points(); ++f) movable += raw->movable(raw->index(f));
  const auto positions = scene.mesh.positions();
  for (Eigen::Index v = 0; v < positions.cols(); ++v) inside += Lattice::inside(box.to_local(positions.col(v)));
  const Index3 degree = raw->degree();
  ctx.stats["name"] = name;
  ctx.stats["basis"] = step["basis"];
  ctx.stats["degree"] = {degree[0], degree[1], degree[2]};
  ctx.stats["cells"] = step["cells"];
  ctx.stats["control_points"] = raw->num_points();
  ctx.stats["movable_points"] = movable;
  ctx.stats["vertices_inside"] = inside;
  ctx.stats["box"] = {{"origin", vec_json(box.origin())},
                      {"axes", {vec_json(box.axes().col(0)), vec_json(box.axes().col(1)), vec_json(box.axes().col(2))}}};
  ctx.stats["boundary_continuity"] = raw->boundary_continuity();
  ctx.summary = "lattice '" + name + "': " + step["basis"].get<std::string>() +
                (step["basis"] == "bspline" ? " degree " + std::to_string(degree[0]) : std::string()) + ", " +
                std::to_string(cells[0]) + "x" + std::to_string(cells[1]) + "x" + std::to_string(cells[2]) +
                " cells, " + format_count(raw->num_points()) + " points (" + format_count(movable) + " movable), " +
                format_count(inside) + " vertices inside";
  if (inside == 0)
    scene.warnings.push_back(ctx.pointer + ": lattice '" + name + "' contains no mesh vertex");
}

void check_move(ScriptChecks& checks, const json& step, const std::string& p) {
  const LatticeShape& shape = checks.lattice_of(step, p);
  if (step.contains("select")) checks.check_selection_files(step["select"], p + "/select");
  if (!step.contains("points")) return;
  for (std::size_t i = 0; i < step["points"].size(); ++i) {
    const json& index = step["points"][i]["index"];
    for (int a = 0; a < 3; ++a) {
      int lo, hi;
      shape.movable_span(a, lo, hi);
      const int v = index[a].get<int>();
      if (v < lo || v > hi)
        checks.fail(p + "/points/" + std::to_string(i) + "/index",
                    "point " + index.dump() + " is not movable (movable: " + shape.movable_text() + ")");
    }
  }
}

void run_move(Scene& scene, const json& step, StepContext& ctx) {
  const std::string name = step["lattice"];
  Lattice& lattice = scene.lattice(name, ctx.pointer);
  std::size_t moved_points = 0;
  if (step.contains("points")) {
    for (const json& point : step["points"]) {
      const Index3 ijk{point["index"][0].get<int>(), point["index"][1].get<int>(), point["index"][2].get<int>()};
      const Eigen::Vector3d target =
          point.contains("by") ? Eigen::Vector3d(lattice.point(ijk) + parse_vec3(point["by"])) : parse_vec3(point["to"]);
      lattice.move_point(ijk, target);
      ++moved_points;
    }
  } else {
    const std::vector<std::size_t> picked =
        select_lattice_points(step["select"], lattice, scene.selection_context(ctx.pointer + "/select"));
    Transform transform;
    if (!parse_transform(step["transform"], transform))
      throw InputError(scene.script_path + ": " + ctx.pointer + "/transform/rotate/axis: the rotation axis is zero");
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    std::vector<Eigen::Vector3d> current;
    for (std::size_t f : picked) {
      current.push_back(lattice.point(lattice.index(f)));
      centroid += current.back();
    }
    centroid /= static_cast<double>(picked.size());
    for (std::size_t i = 0; i < picked.size(); ++i)
      lattice.move_point(lattice.index(picked[i]), transform.apply(current[i], centroid));
    moved_points = picked.size();
  }
  const WarpStack::Update update = scene.stack.update(scene.mesh, name);
  ctx.stats["lattice"] = name;
  ctx.stats["points_moved"] = moved_points;
  report_update(scene, update, ctx);
  warn_if_tearing(scene, lattice, name, ctx);
  ctx.summary = "move '" + name + "': " + format_count(moved_points) + " points, " + format_count(update.moved) +
                " vertices moved";
}

void check_drag(ScriptChecks& checks, const json& step, const std::string& p) { checks.lattice_of(step, p); }

void run_drag(Scene& scene, const json& step, StepContext& ctx) {
  const std::string name = step["lattice"];
  Lattice& lattice = scene.lattice(name, ctx.pointer);
  const std::size_t k = scene.stack.index_of(name);
  std::vector<Eigen::Vector3d> at, to;
  for (std::size_t i = 0; i < step["points"].size(); ++i) {
    const json& point = step["points"][i];
    if (point.contains("vertex")) {
      const auto v = point["vertex"].get<std::size_t>();
      if (v >= scene.mesh.num_vertices())
        throw InputError(scene.script_path + ": " + ctx.pointer + "/points/" + std::to_string(i) +
                         "/vertex: vertex " + std::to_string(v) + " is out of range (the mesh has " +
                         std::to_string(scene.mesh.num_vertices()) + " vertices)");
      at.push_back(scene.stack.input_position(scene.mesh, k, static_cast<std::uint32_t>(v)));
    } else {
      at.push_back(parse_vec3(point["at"]));
    }
    to.push_back(parse_vec3(point["to"]));
  }
  const DragResult result = drag(lattice, at, to);
  const WarpStack::Update update = scene.stack.update(scene.mesh, name);
  ctx.stats["lattice"] = name;
  ctx.stats["object_points"] = at.size();
  ctx.stats["points_changed"] = result.points_changed;
  ctx.stats["residual_max"] = result.max_residual;
  ctx.stats["residual_rms"] = result.rms_residual;
  ctx.stats["unreachable"] = result.unreachable;
  report_update(scene, update, ctx);
  warn_if_tearing(scene, lattice, name, ctx);
  const double scale = lattice.box().extents().norm();
  if (result.unreachable)
    scene.warnings.push_back(ctx.pointer + ": " + std::to_string(result.unreachable) +
                             " object points lie where no movable control point reaches (outside the deformable zone)");
  else if (result.max_residual > 1e-9 * scale)
    scene.warnings.push_back(ctx.pointer + ": the targets conflict; least-squares residual " +
                             std::to_string(result.max_residual));
  char residual[32];
  std::snprintf(residual, sizeof residual, "%.3g", result.max_residual);
  ctx.summary = "drag '" + name + "': " + format_count(at.size()) + " object points, " +
                format_count(result.points_changed) + " control points changed, residual " + residual + ", " +
                format_count(update.moved) + " vertices moved";
}

}  // namespace ffd
