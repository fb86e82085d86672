// What a script's steps must agree on before a run: names created before use, shapes
// that make the indices later steps name valid, output paths. One ScriptChecks walks a
// script's typed steps in order; each step's check() records and tests what it needs.
#pragma once

#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "warp/lattice_spec.h"

namespace ffd {

struct OutputFile;

class ScriptChecks {
public:
  explicit ScriptChecks(std::string script_path) : path_(std::move(script_path)) {}

  /// \throw InputError "script: pointer: what".
  [[noreturn]] void fail(const std::string& pointer, const std::string& what) const;
  /// A file a step writes: a mesh extension (a picture: .png), relative, inside the
  /// output folder.
  void check_output_path(const OutputFile& file, const std::string& pointer) const;
  /// The lattice called `name`; fails at `pointer` if no step created it earlier.
  const LatticeSpec& lattice_of(const std::string& name, const std::string& pointer) const;

  /// The highest level index of the octree lattice called `name` (local levels included),
  /// or -1 when it is not one (a tensor-product lattice, or none: then lattice_of says so).
  int octree_levels(const std::string& name) const;
  /// A step's lattice `name` and its "level": fails at pointer + "/lattice" when no lattice
  /// is called so, and at pointer + "/level" when a level is given for a B-spline or
  /// Bernstein lattice or lies beyond an octree lattice's. Returns the octree lattice's
  /// highest level, or -1 for a tensor-product lattice.
  int check_lattice_level(const std::string& name, const std::optional<int>& level, const std::string& pointer) const;
  /// Fails at `pointer` when a lattice called `name` exists already.
  void check_new_lattice(const std::string& name, const std::string& pointer) const;

  std::map<std::string, LatticeSpec> lattices;
  /// Octree lattices: name -> levels (octree subdivisions); and how many local levels
  /// subdivide steps added after them.
  std::map<std::string, int> octrees;
  std::map<std::string, int> octree_local_levels;
  /// Handle names of each bcm editor, in order (bcm steps record them, transform steps check).
  std::map<std::string, std::vector<std::string>> editor_handles;

private:
  std::string path_;
};

}  // namespace ffd
