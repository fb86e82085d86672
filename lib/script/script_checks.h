// What a script's steps must agree on before a run: names created before use, shapes
// that make the indices later steps name valid. One ScriptChecks walks a script's steps
// in order; each op's check function (ops.h) records and tests what it needs.
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "warp/lattice.h"

namespace ffd {

/// A lattice as the script declares it, enough to check indices without building it.
struct LatticeShape {
  std::string basis;  // "bspline" | "bernstein"
  int degree = 3;
  Index3 cells{0, 0, 0};
  /// Movable index range along `axis`.
  void movable_span(int axis, int& lo, int& hi) const;
  /// "i in [2, 4], j in [2, 4], k in [2, 6]".
  std::string movable_text() const;
};

class ScriptChecks {
public:
  ScriptChecks(std::string script_path, std::string folder)
      : path_(std::move(script_path)), folder_(std::move(folder)) {}

  /// \throw InputError "script: pointer: what".
  [[noreturn]] void fail(const std::string& pointer, const std::string& what) const;
  /// Selection `file` entries must exist and parse.
  void check_selection_files(const nlohmann::json& selection, const std::string& pointer) const;
  /// Paths written by a step: a mesh extension, relative, inside the output folder.
  void check_output_path(const std::string& path, const std::string& pointer) const;

  std::map<std::string, LatticeShape> lattices;
  std::set<std::string> editors;
  /// Handle names of each editor, in order (bcm steps record them, transform steps check).
  std::map<std::string, std::vector<std::string>> editor_handles;

  /// The lattice a step names in its "lattice" key; fails if not created earlier.
  const LatticeShape& lattice_of(const nlohmann::json& step, const std::string& pointer) const;

private:
  std::string path_;
  std::string folder_;
};

}  // namespace ffd
