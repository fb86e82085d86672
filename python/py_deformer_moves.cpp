// Deformer's control points from Python: views of them, their indices, and moves by
// index, by writing into the views, and by dragging object points.
#include <pybind11/stl.h>

#include <algorithm>

#include "common/errors.h"
#include "py_arrays.h"
#include "py_deformer.h"
#include "warp/drag.h"

namespace ffd::py {
namespace {

// An int or a numpy integer; not a numpy array, which has __index__ too (for size 1).
bool is_integer(const pb::handle& h) { return PyIndex_Check(h.ptr()) && !PySequence_Check(h.ptr()); }

// One script-style point index: an integer n, or [i, j, k] (any sequence of three
// integers). \throw InputError at `at` for anything else.
PointIndex point_index(const pb::handle& item, const At& at) try {
  PointIndex index;
  if (is_integer(item)) {
    index.grid = false;
    index.n = item.cast<long long>();
    return index;
  }
  std::size_t a = 0;
  bool integers = pb::isinstance<pb::sequence>(item);
  if (integers)
    for (const pb::handle h : item) {
      integers = integers && is_integer(h) && a < 3;
      if (integers) index.ijk[a++] = h.cast<int>();
    }
  if (!integers || a != 3) throw InputError(at, "a point index is an integer n or a lattice index [i, j, k]");
  return index;
} catch (const pb::cast_error&) {
  throw InputError(at, "a point index is out of range");
}

// `index` as a list: one index (n, or [i, j, k] on a grid), or a sequence of them.
std::vector<PointIndex> point_indices(const pb::object& index, bool grid, const std::string& label) {
  bool one = is_integer(index);
  if (grid && !one && pb::isinstance<pb::sequence>(index) && pb::len(index) == 3) {
    one = true;
    for (const pb::handle h : index) one = one && is_integer(h);
  }
  if (one) return {point_index(index, At{label + ".move: index"})};
  if (!pb::isinstance<pb::sequence>(index))
    throw InputError(At{label + ".move: index"}, "an integer, [i, j, k], or a list of them");
  std::vector<PointIndex> out;
  for (const pb::handle item : index)
    out.push_back(point_index(item, At{label + ".move: index[" + std::to_string(out.size()) + "]"}));
  return out;
}

// The ids of `indices` at `level`. \throw InputError at "L.move: index[i]" for a point that
// is not there or not movable, or is listed twice.
std::vector<std::size_t> find_points(const PyDeformer& d, int level, const std::vector<PointIndex>& indices) {
  std::vector<std::size_t> ids;
  for (std::size_t i = 0; i < indices.size(); ++i) {
    const At at{d.label + ".move: index[" + std::to_string(i) + "]"};
    if (auto problem = index_form_problem(indices[i], d.deformer->grid_indexed(), "control points"))
      throw InputError(at, *problem);
    const std::optional<std::size_t> id = d.deformer->find_point(level, indices[i]);
    if (!id) throw InputError(at, d.deformer->missing_point(level, indices[i]));
    if (std::find(ids.begin(), ids.end(), *id) != ids.end())
      throw InputError(at, "point " + indices[i].text() + " is listed twice");
    ids.push_back(*id);
  }
  return ids;
}

pb::dict report(const MoveReport& r) {
  pb::dict out;
  out["points_moved"] = r.points_moved;
  for (const MoveReport::Count& c : r.counts) out[c.key.c_str()] = c.value;
  return out;
}

pb::dict move(PyDeformer& d, const pb::object& index, const std::optional<Float64Array>& to,
              const std::optional<Float64Array>& by, const std::optional<int>& level) {
  if (to.has_value() == by.has_value()) throw InputError(At{d.label + ".move"}, "give exactly one of to and by");
  const std::vector<PointIndex> indices = point_indices(index, d.deformer->grid_indexed(), d.label);
  const std::vector<Eigen::Vector3d> given = point_list(to ? *to : *by, d.label + ".move: " + (to ? "to" : "by"), true);
  const std::size_t count = indices.size();
  if (given.size() != count && given.size() != 1)
    throw InputError(At{d.label + ".move"}, std::to_string(count) + " points but " + std::to_string(given.size()) +
                                                (to ? " targets" : " displacements"));
  const bool absolute = to.has_value();
  MoveReport moved;
  with_deformer(d, 0, [&] {
    const int l = d.level_of(level);
    const std::vector<std::size_t> ids = find_points(d, l, indices);
    const Eigen::Matrix3Xd now = d.deformer->points(l, ids);
    std::vector<Eigen::Vector3d> targets(count);
    for (std::size_t i = 0; i < count; ++i) {
      const Eigen::Vector3d& g = given[given.size() == 1 ? 0 : i];
      targets[i] = absolute ? g : Eigen::Vector3d(now.col(static_cast<Eigen::Index>(i)) + g);
    }
    moved = d.deformer->move_points(l, ids, targets);
    d.refresh();
  });
  return report(moved);
}

pb::dict drag_points(PyDeformer& d, const Float64Array& at, const Float64Array& to, const std::optional<int>& level) {
  const std::vector<Eigen::Vector3d> from = point_list(at, d.label + ".drag: at", true);
  const std::vector<Eigen::Vector3d> targets = point_list(to, d.label + ".drag: to", true);
  if (from.size() != targets.size())
    throw InputError(At{d.label + ".drag"}, std::to_string(from.size()) + " object points but " +
                                                std::to_string(targets.size()) + " targets");
  DragResult result;
  with_deformer(d, 0, [&] {
    result = drag(*d.deformer, d.level_of(level), from, targets);
    d.refresh();
  });
  pb::dict out;
  out["max_residual"] = result.max_residual;
  out["rms_residual"] = result.rms_residual;
  out["points_changed"] = result.points_changed;
  out["unreachable"] = result.unreachable;
  return out;
}

// Each point's script index at `level`: (n, 3) [i, j, k] on a grid, else (n,) numbers.
pb::array_t<std::int64_t> indices(const PyDeformer& d, int level) {
  const std::size_t n = d.deformer->num_points(level);
  const bool grid = d.deformer->grid_indexed();
  std::vector<long long> values;
  for (std::size_t id = 0; id < n; ++id) {
    const PointIndex index = d.deformer->point_index(level, id);
    if (grid) values.insert(values.end(), index.ijk.begin(), index.ijk.end());
    else values.push_back(index.n);
  }
  if (grid) return int_array(values, {static_cast<pb::ssize_t>(n), 3});
  return int_array(values, {static_cast<pb::ssize_t>(n)});
}

}  // namespace

void bind_deformer_moves(pb::class_<PyDeformer>& c) {
  c.def(
      "points",
      [](pb::object self, std::optional<int> level) {
        PyDeformer& d = self.cast<PyDeformer&>();
        Eigen::Matrix3Xd& shown = d.shown[static_cast<std::size_t>(d.level_of(level))];
        return vec3_view(shown.data(), static_cast<std::size_t>(shown.cols()), self, true);
      },
      pb::arg("level") = pb::none(),
      "points(level=None) -> (n, 3) float64 view of the level's control points as they are now (default: the "
      "finest level). It follows every move; writing into it moves those points at the next call that uses the "
      "deformer (a point that is not movable raises InputError and is put back).");
  c.def("num_points", [](PyDeformer& d, std::optional<int> level) { return d.made().num_points(d.level_of(level)); },
        pb::arg("level") = pb::none(), "The number of control points of the level.");
  c.def(
      "movable",
      [](PyDeformer& d, std::optional<int> level) {
        const int l = d.level_of(level);
        const Deformer& deformer = d.made();
        pb::array_t<bool> out(static_cast<pb::ssize_t>(deformer.num_points(l)));
        for (std::size_t id = 0; id < deformer.num_points(l); ++id) out.mutable_at(id) = deformer.point_movable(l, id);
        return out;
      },
      pb::arg("level") = pb::none(), "(n,) bool: which of the level's points may move.");
  c.def("indices", [](PyDeformer& d, std::optional<int> level) { return indices(d, d.level_of(level)); },
        pb::arg("level") = pb::none(),
        "Each point's index as scripts name it: (n, 3) int64 [i, j, k] on a lattice, (n,) int64 numbers for "
        "scattered points and cage vertices.");
  c.def("move", &move, pb::arg("index"), pb::arg("to") = pb::none(), pb::arg("by") = pb::none(),
        pb::arg("level") = pb::none(),
        "move(index, to=None, by=None, level=None) -> dict: moves control points as the script's move op does. "
        "index: [i, j, k] or n, or a list of them; to: targets (k, 3) or (3,); by: displacements. Returns the "
        "move's counts (points_moved and the kind's own).");
  c.def("drag", &drag_points, pb::arg("at"), pb::arg("to"), pb::arg("level") = pb::none(),
        "drag(at, to, level=None) -> dict: direct manipulation, the least-norm change of the level's movable "
        "points that takes object points `at` (k, 3) (input space) to `to` (k, 3). Returns max_residual, "
        "rms_residual, points_changed and unreachable.");
}

}  // namespace ffd::py
