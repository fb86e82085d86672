// What a script's steps must agree on before a run: names created before use, shapes
// that make the indices later steps name valid, output paths. One ScriptChecks walks a
// script's typed steps in order; each step's check() records and tests what it needs.
#pragma once

#include <array>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "warp/deformer.h"

namespace ffd {

struct OutputFile;

/// What later steps may rely on about a deformer a step creates, before any work.
struct DeformerShape {
  std::string kind;         // the lattice op's basis: "bspline", "bernstein", "octree"
  bool has_levels = false;  // whether steps may name a level
  int levels = 0;           // the highest level index (local levels included)
  int subdividable = -1;    // the highest level the subdivide op can split; -1: none
  /// For a point's script index at a level ([i, j, k], or n for scattered points): the
  /// text of which points are movable when it is none of them ("i in [2, 4], ..."), or
  /// nothing when it may be one (the run checks what only the mesh decides, such as an
  /// octree's cut cells).
  std::function<std::optional<std::string>(int, const PointIndex&)> unmovable;
  /// How its points are named: grid nodes [i, j, k] (lattices), or numbered among its
  /// `noun` (scattered points: "control points", "cage vertices").
  bool grid = true;
  std::string noun = "points";
};

class ScriptChecks {
public:
  explicit ScriptChecks(std::string script_path) : path_(std::move(script_path)) {}

  /// \throw InputError "script: pointer: what".
  [[noreturn]] void fail(const std::string& pointer, const std::string& what) const;
  /// A file a step writes: a mesh extension (a picture: .png), relative, inside the
  /// output folder.
  void check_output_path(const OutputFile& file, const std::string& pointer) const;
  /// The deformer called `name`; fails at `pointer` if no step created it earlier.
  const DeformerShape& deformer_of(const std::string& name, const std::string& pointer) const;
  /// A step's lattice `name` and its "level": fails at pointer + "/lattice" when no lattice
  /// is called so, and at pointer + "/level" when a level is given for a kind without levels
  /// or lies beyond the deformer's. Returns the level the step acts on (default: the finest).
  int check_lattice_level(const std::string& name, const std::optional<int>& level, const std::string& pointer) const;
  /// Fails at `pointer` when a lattice called `name` exists already.
  void check_new_lattice(const std::string& name, const std::string& pointer) const;
  /// Fails at `pointer` unless `index` may name a movable point of level `level` of a
  /// deformer of `shape`: its form ([i, j, k] or a number, index_form_problem), then its
  /// range (`shape.unmovable`), with the messages the run would give.
  void check_point_index(const DeformerShape& shape, int level, const PointIndex& index,
                         const std::string& pointer) const;

  /// Deformers by name, as the steps so far made them.
  std::map<std::string, DeformerShape> deformers;
  /// Handle names of each bcm editor, in order (bcm steps record them, transform steps check).
  std::map<std::string, std::vector<std::string>> editor_handles;

private:
  std::string path_;
};

}  // namespace ffd
