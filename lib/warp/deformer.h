// Deformer: a warp driven by control points, the one seam every control-point kind plugs
// into (Bernstein and B-spline lattices, octree lattices, RBF, IDW and cages). The
// ops (move, drag, save's nets and sensitivities, selections, previews) see only this.
//
// Named Deformer, not ControlWarp or Lattice: a lattice is one kind among several (RBF
// centres and cage vertices are scattered points), and "deformer" is what the field's
// tools call a thing with handles that deforms space (Blender's modifiers, pyGeo's DVGeo).
//
// Promises:
// - Control points come in levels 0..num_levels()-1 (1 for a tensor lattice, a cage or
//   an RBF; an octree lattice's levels). A level's points have ids 0..num_points()-1, the
//   order the save op writes its net in.
// - The deformation is linear in a level's points: moving point j by d changes F(x) by
//   w_j(x) d, with w_j(x) = movable_weights(). For a tensor lattice F(x) = sum_j w_j(x) p_j
//   exactly; an octree level's w_j are the trilinear weights in the subdivided cell carried
//   back through the Catmull-Clark steps (its points as shown, the other levels' own moves
//   held: what move does). So dF/dp_j = w_j(x) I exactly, which is what drag solves with
//   and what the sensitivity save writes.
// - An unmoved deformer is the identity; only movable points move.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "warp/warp.h"

namespace ffd {

/// How a script names one control point: a grid node [i, j, k], or a plain index n for
/// scattered points (RBF centres, cage vertices).
struct PointIndex {
  bool grid = true;
  std::array<int, 3> ijk{0, 0, 0};
  long long n = 0;
  /// "[2, 3, 4]" or "7", for messages and headers.
  std::string text() const;
};

/// Why `index` cannot name a point of a deformer whose points are grid nodes [i, j, k]
/// (`grid`) or numbered among its `noun` ("control points") when it has the other form:
/// "expected a lattice index [i, j, k]"; nothing when the form is right. Deformers'
/// missing_point and the script's checks before a run say the same.
std::optional<std::string> index_form_problem(const PointIndex& index, bool grid, const std::string& noun);

/// Control-point weights at one point of the input space: (point id, weight), ids ascending.
using PointWeights = std::vector<std::pair<std::size_t, double>>;

/// What moving points did: how many moved, and the counts the kind reports beside it, in
/// order (an octree lattice: cells subdivided, cells relocated), for a step's stats.
struct MoveReport {
  struct Count {
    std::string key;      // "cells_subdivided": the stats key
    std::size_t value = 0;
    std::string summary;  // "cells subdivided": shown in the step's summary line; "" not shown
  };
  std::size_t points_moved = 0;
  std::vector<Count> counts;
};

class Deformer : public Warp {
public:
  /// The kind's name as the lattice op's basis spells it: "bspline", "bernstein", "octree".
  virtual std::string kind() const = 0;
  /// Whether scripts address levels (the "level" key); a kind without levels has level 0 only.
  virtual bool has_levels() const { return false; }
  virtual int num_levels() const { return 1; }
  /// The level move, drag and save use when the script names none: the finest.
  int default_level() const { return num_levels() - 1; }

  virtual std::size_t num_points(int level) const = 0;
  /// The level's points as they are now (rest + moves), one column per id.
  virtual Eigen::Matrix3Xd points(int level) const = 0;
  /// Columns `ids` of points(level), without computing the others where the kind can.
  virtual Eigen::Matrix3Xd points(int level, const std::vector<std::size_t>& ids) const;
  virtual bool point_movable(int level, std::size_t id) const { return true; }
  /// Whether points are named [i, j, k] (grids) or by a plain index (scattered points).
  virtual bool grid_indexed() const { return true; }
  /// The id of the point the script calls `index`, or none when the level has no such point.
  virtual std::optional<std::size_t> find_point(int level, const PointIndex& index) const = 0;
  /// Why find_point found nothing at `index`, one line: "point [5, 0, 0] is not movable (...)".
  virtual std::string missing_point(int level, const PointIndex& index) const = 0;
  virtual PointIndex point_index(int level, std::size_t id) const = 0;
  /// Which points are movable, for messages: "i in [2, 4], j in [2, 4], k in [2, 6]".
  virtual std::string movable_text(int level) const = 0;

  /// Moves the movable points `ids` (each once) to `targets` and brings the deformation up
  /// to date; the warp stack's next update re-evaluates what changed.
  /// \throw std::logic_error for a point that is not movable (scripts check that first).
  virtual MoveReport move_points(int level, const std::vector<std::size_t>& ids,
                                 const std::vector<Eigen::Vector3d>& targets) = 0;
  /// The weights w_j(x) != 0 of the level's movable points at x (input space), ids ascending.
  virtual void movable_weights(int level, const Eigen::Vector3d& x, PointWeights& out) const = 0;
  /// Each edge of the level's net once (pairs of ids), for drawing and the save op's l lines.
  virtual std::vector<std::array<std::uint32_t, 2>> net_edges(int level) const = 0;
  /// The level's net as polygons (ids), for kinds whose net is a surface (a cage): the
  /// save op writes them as faces. None for the others.
  virtual std::vector<std::vector<std::uint32_t>> net_faces(int level) const { return {}; }
  /// A length that sets the deformer's scale (its box's diagonal), for tolerances.
  virtual double scale() const = 0;

  /// Whether the deformation, as moved, tears where the mesh leaves in_support() (a
  /// Bernstein lattice whose face points moved); false for kinds that cannot tear.
  virtual bool tears() const { return false; }
  /// Whether x (input space) lies where the deformer acts.
  virtual bool in_support(const Eigen::Vector3d& x) const { return true; }
  /// The warning when tears() and `outside` vertices of the mesh lie outside in_support():
  /// what happens there and what to do, naming the deformer `name`.
  virtual std::string tearing_warning(const std::string& name, std::size_t outside) const { return {}; }
};

}  // namespace ffd
