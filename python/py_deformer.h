// ffdtool.Deformer: one deformer of any kind, made by its script op (lattice, rbf, idw,
// cage) on a mesh or points, then moved, dragged and applied to any points.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "py_module.h"

namespace ffd::py {

struct PyDeformer {
  std::unique_ptr<Scene> scene;  // holds the deformer on its warp stack; its mesh is dropped once made
  Deformer* deformer = nullptr;
  std::string label;  // the Python class, for messages: "BSplineLattice"
  /// Per level: the points as Python sees them (points() views these, and writes to them
  /// move the points at the next use), and as the deformer had them when last shown.
  std::vector<Eigen::Matrix3Xd> shown, known;
  /// One caller at a time (the GIL is released while the deformer works).
  std::mutex lock;

  /// Moves the points written into `shown` since the last refresh, level by level from
  /// the coarsest. \throw InputError for a point that is not movable (nothing moves).
  void sync();
  /// Sets `shown` and `known` to the deformer's points (in place: views stay valid).
  void refresh();
  /// `level`, or the default level when none. \throw InputError when out of range.
  int level_of(const std::optional<int>& level) const;
  /// The deformer. \throw InputError when making it failed (a Python object whose
  /// constructor raised can still be reached through the traceback).
  Deformer& made() const;
};

/// Runs f() on `d` with the GIL released, d's lock held (taken after the GIL is let go, so
/// two Python threads never wait on each other), `threads` OpenMP threads (0: as set), and
/// the points written into d's views moved first.
template <class F>
void with_deformer(PyDeformer& d, int threads, F&& f) {
  d.made();
  pb::gil_scoped_release unlocked;
  std::lock_guard<std::mutex> guard(d.lock);
  ThreadScope scope(threads);
  d.sync();
  f();
}

}  // namespace ffd::py
