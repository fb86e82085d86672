// The `run` fuzz target's work, shared with the ctest replay of its corpus
// (tests/fuzz_corpus_test.cpp): one JSON script run by the library's runner, exactly as
// `ffdtool run` runs it, on a small closed sphere, inside a private folder.
#pragma once

#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace ffd::fuzz {

/// Why a resolved script (Script::resolved) would take too long for one fuzz input, or ""
/// when it is within the budget: at most 12 steps, 4 lattices of at most 8 cells per axis
/// (octree lattices: levels + cc_steps at most 6),
/// 3 remesh steps with max_level at most 3, 3 bcm editors of at most 4 handles, 4 frames
/// per transform, 4 saves, 16 drag points, 64 moved points, and no min_volume box fit
/// (CGAL's optimal box on exact predicates takes seconds under ASan even on this mesh;
/// tests/box_fit_test.cpp covers it). A cheap filter of the harness, not a rule of the tool.
std::string over_budget(const nlohmann::json& resolved);

/// A private folder under the system's temp folder holding `mesh.obj` (a UV sphere of
/// radius 1 at the origin: 164 vertices, 324 triangles, closed) and `out/`, removed when
/// the sandbox goes.
class RunSandbox {
public:
  RunSandbox();
  ~RunSandbox();
  RunSandbox(const RunSandbox&) = delete;
  RunSandbox& operator=(const RunSandbox&) = delete;

  /// What became of a script: refused by the loader, over the budget (not run), failed
  /// while running with one of ffdtool's errors, or run to the end.
  enum class Outcome { Refused, OverBudget, Failed, Ran };

  /// Parses `script` and, when it is within the budget, writes it to the folder and runs
  /// it as `ffdtool run mesh.obj s.json -o out/out.obj --stats out/stats.json --quiet
  /// --threads 1` would; empties out/ after the run, however it ended. An ffd::Error is
  /// an outcome (its text in error()); any other exception goes to the caller.
  Outcome run(std::string_view script);

  const std::string& folder() const { return folder_; }
  /// The text of the last Refused or Failed outcome's error.
  const std::string& error() const { return error_; }

private:
  Outcome run_parsed(std::string_view script);

  std::string folder_;
  std::string error_;
};

/// The sphere's OBJ text.
std::string sphere_obj();

}  // namespace ffd::fuzz
