// ffdtool.Deformer: made by its op, moved by index or by writing into points(), dragged,
// and applied to points with Jacobians, weights and sensitivities (warp/deformer.h).
#include "py_deformer.h"

#include <pybind11/stl.h>

#include <stdexcept>

#include "common/errors.h"
#include "mesh/build_mesh.h"
#include "py_arrays.h"
#include "py_mesh.h"
#include "script/op.h"
#include "script/runner.h"
#include "script/script.h"
#include "warp/drag.h"

namespace ffd::py {

void PyDeformer::refresh() {
  for (int l = 0; l < deformer->num_levels(); ++l) {
    const Eigen::Matrix3Xd now = deformer->points(l);
    auto at = static_cast<std::size_t>(l);
    if (at >= shown.size()) {
      shown.push_back(now);
      known.push_back(now);
    } else {
      // Views of shown[at] are out there: its memory must stay. A level's point count is
      // fixed once made (only a subdivide step adds a level, and Python has none).
      if (now.cols() != shown[at].cols()) throw std::logic_error("a deformer level changed its point count");
      shown[at] = now;
      known[at] = now;
    }
  }
}

void PyDeformer::sync() {
  std::vector<std::vector<std::size_t>> ids(shown.size());
  for (std::size_t l = 0; l < shown.size(); ++l)
    for (Eigen::Index i = 0; i < shown[l].cols(); ++i) {
      if (shown[l].col(i) == known[l].col(i)) continue;
      const auto id = static_cast<std::size_t>(i);
      if (!deformer->point_movable(static_cast<int>(l), id)) {
        shown[l].col(i) = known[l].col(i);
        const PointIndex index = deformer->point_index(static_cast<int>(l), id);
        throw InputError(At{label + ".points(" + std::to_string(l) + ")[" + std::to_string(i) + "]"},
                         deformer->missing_point(static_cast<int>(l), index) + "; it was put back");
      }
      ids[l].push_back(id);
    }
  bool moved = false;
  for (std::size_t l = 0; l < ids.size(); ++l) {
    if (ids[l].empty()) continue;
    std::vector<Eigen::Vector3d> targets;
    for (std::size_t id : ids[l]) targets.push_back(shown[l].col(static_cast<Eigen::Index>(id)));
    deformer->move_points(static_cast<int>(l), ids[l], targets);
    moved = true;
  }
  if (moved) refresh();
}

Deformer& PyDeformer::made() const {
  if (!deformer) throw InputError("this deformer was never made: its constructor raised");
  return *deformer;
}

int PyDeformer::level_of(const std::optional<int>& level) const {
  const Deformer& d = made();
  if (!level) return d.default_level();
  if (*level < 0 || *level >= d.num_levels())
    throw InputError(At{label}, "level " + std::to_string(*level) + " does not exist (levels 0 to " +
                                    std::to_string(d.num_levels() - 1) + ")");
  return *level;
}

namespace {

// The mesh a deformer is made around: a Mesh, (n, 3) points as a point cloud, or none.
Mesh construction_mesh(const pb::object& around, const std::string& label) {
  if (around.is_none()) return build_mesh(PolygonSoup{}, label);
  if (pb::isinstance<PyMesh>(around)) return run_input(around.cast<const PyMesh&>());
  PolygonSoup soup;
  soup.positions = point_list(around.cast<Float64Array>(), label + ": mesh");
  check_finite(soup.positions, label + ": mesh");
  return build_mesh(std::move(soup), label);
}

// A script error placed in the one-step script ("L: /steps/0/cells") placed at the
// keyword instead ("L: /cells").
void place_at_keyword(Error& e, const std::string& label) {
  const std::string prefix = label + ": /steps/0";
  if (e.place().rfind(prefix, 0) != 0) return;
  const std::string key = e.place().substr(prefix.size());
  e.set_place(key.empty() ? label : label + ": " + key);
}

// Makes d's deformer: the one-step scene of `step` around `around`.
void make_deformer(PyDeformer& d, const std::string& step, const pb::object& around, const std::string& label) {
  if (d.deformer) throw InputError(At{label}, "the deformer is made already");
  d.label = label;
  auto scene = std::make_unique<Scene>();
  scene->mesh = construction_mesh(around, label);
  pb::gil_scoped_release unlocked;
  try {
    const Script script = parse_script(R"({"version": 1, "steps": [)" + step + "]}", label);
    const std::string op = script.steps.at(0)->op->name();
    if (op != "lattice" && op != "rbf" && op != "idw" && op != "cage")
      throw InputError(At{label}, "a deformer is made by a lattice, rbf, idw or cage step, not " + op);
    StepContext ctx;
    run_step(script, *script.steps.at(0), *scene, ctx);
  } catch (Error& e) {
    place_at_keyword(e, label);
    throw;
  }
  scene->mesh = Mesh();  // move and apply never look at it again
  d.deformer = scene->deformers.begin()->second;
  d.scene = std::move(scene);
  d.refresh();
}

}  // namespace

void bind_deformer_evaluation(pb::class_<PyDeformer>& c);
void bind_deformer_moves(pb::class_<PyDeformer>& c);

void bind_deformers(pb::module_& m) {
  pb::class_<PyDeformer> c(m, "Deformer",
                           "A deformer with control points (a lattice, an RBF, an IDW or a cage). Make one with the "
                           "classes BSplineLattice, BernsteinLattice, OctreeLattice, RBF, IDW and Cage.");
  // Made in two steps, so that a Python object whose making raised still holds a (empty)
  // PyDeformer, which every method checks (made()), rather than no C++ object at all.
  c.def(pb::init<>());
  c.def("_make", &make_deformer, pb::arg("step"), pb::arg("around"), pb::arg("label"),
        "Makes the deformer a script step (JSON text of one lattice, rbf, idw or cage step) makes around "
        "`around` (a Mesh, (n, 3) points or None); errors name `label` and the step's key.");
  c.def_property_readonly("kind", [](const PyDeformer& d) { return d.made().kind(); },
                          "The kind: 'bspline', 'bernstein', 'octree', 'rbf', 'idw' or 'cage'.");
  c.def_property_readonly("num_levels", [](const PyDeformer& d) { return d.made().num_levels(); },
                          "Levels of control points (an octree lattice's levels; 1 for the other kinds).");
  c.def_property_readonly("scale", [](const PyDeformer& d) { return d.made().scale(); },
                          "A length that sets the deformer's scale (its box's diagonal).");
  bind_deformer_moves(c);
  bind_deformer_evaluation(c);
}

}  // namespace ffd::py
