// Running a script on a mesh: the `ffdtool run` command without its CLI.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "common/progress.h"

namespace ffd {

struct RunOptions {
  std::string mesh;    // input mesh file
  std::string script;  // JSON script
  std::string output;  // final mesh file; its folder is the output folder for `save`
  std::string save_folder;  // where `save` paths are relative to, if not the output's folder
  std::string stats;   // stats JSON file, or empty
  std::string preview;  // PNG of the final mesh with every lattice's control net, or empty
  bool quiet = false;  // no per-step lines on stderr
  int threads = 0;     // 0: OpenMP's default
  /// A volume mesh's result may have inverted cells (written with a warning); also the
  /// script's "allow_inverted". Without either such a run is an InputError.
  bool allow_inverted = false;
  /// Progress of the steps on stderr (common/progress.h): Auto is a live line when stderr
  /// is a terminal, and nothing when it is not or when `quiet`; Json is step events.
  ProgressMode progress = ProgressMode::None;
};

/// Checks everything that can be checked first (script, output paths, input files), then
/// reads the mesh, runs every step, and writes the output mesh, every saved mesh and the
/// stats file, all put in place only after the last step succeeded. Returns the
/// stats. \throw InputError for bad input (nothing is written), SolverError or IoError for a failure
/// while running (nothing is written).
nlohmann::ordered_json run_script(const RunOptions& options);

struct Script;
class Step;
struct Scene;
struct StepContext;

/// How run_in_memory names its input in the stats and messages, and how it reports.
struct MemoryRunOptions {
  std::string mesh;     // the mesh's file, or "" for a mesh made from arrays (stats: null)
  double read_ms = 0;   // what reading it took, when it was read for this run
  bool quiet = true;    // no per-step lines on stderr
};

/// run_script on a mesh in memory (the Python module's run): checks the steps' output
/// files against `scene.output_folder`, runs every step on `scene`, and puts the steps'
/// files in place only when all succeeded. Returns the stats run_script writes, with an
/// output section that names no file ("mesh": null, "write_ms": 0). The scene keeps the
/// warp stack, so Scene::write_options() writes the mesh as the CLI would.
/// \throw InputError, SolverError, IoError as run_script; nothing is written then.
nlohmann::ordered_json run_in_memory(const Script& script, Scene& scene, const MemoryRunOptions& options);

/// Runs one of `script`'s steps on `scene`. An error the step raises without a place is
/// placed at the key its op's table gives the error's subject, or else at the step.
void run_step(const Script& script, const Step& step, Scene& scene, StepContext& ctx);

/// Peak resident memory of this process in bytes.
std::size_t peak_memory_bytes();

}  // namespace ffd
