// ffdtool.run's compiled half: a script's steps on a mesh in memory (script/runner.h).
#include <pybind11/stl.h>

#include "common/timer.h"
#include "mesh/mesh_io.h"
#include "py_mesh.h"
#include "script/runner.h"
#include "script/script.h"

namespace ffd::py {
namespace {

struct RunArgs {
  std::string script_text;  // the script, or "" to read script_path
  std::string script_path;  // its file, or how messages name it
  std::string save_folder;  // where save steps' paths are relative to
  int threads = 0;
  bool quiet = true;
};

// Runs the script on the mesh `source` or on the file `path`; returns the result and the
// stats as JSON text.
std::pair<PyMesh, std::string> run_on(const PyMesh* source, const std::string& path, const RunArgs& args) {
  ThreadScope threads(args.threads);
  const Script script = args.script_text.empty() ? load_script(args.script_path)
                                                  : parse_script(args.script_text, args.script_path);
  PyMesh out{std::make_shared<Scene>(), ""};
  Scene& scene = *out.scene;
  scene.output_folder = args.save_folder.empty() ? "." : args.save_folder;
  MemoryRunOptions options;
  options.quiet = args.quiet;
  Stopwatch read_clock;
  if (source) {
    scene.mesh = run_input(*source);
    options.mesh = source->file;
  } else {
    scene.mesh = read_mesh(path);
    options.mesh = path;
    options.read_ms = read_clock.ms();
  }
  const nlohmann::ordered_json stats = run_in_memory(script, scene, options);
  return {std::move(out), stats.dump()};
}

}  // namespace

void bind_run(pb::module_& m) {
  m.def(
      "_run",
      [](const pb::object& mesh, const std::string& text, const std::string& path, const std::string& save_folder,
         int threads, bool quiet) {
        RunArgs args{text, path, save_folder, threads, quiet};
        const PyMesh* source = pb::isinstance<PyMesh>(mesh) ? &mesh.cast<const PyMesh&>() : nullptr;
        const std::string file = source ? std::string() : mesh.cast<std::string>();
        pb::gil_scoped_release unlocked;
        return run_on(source, file, args);
      },
      pb::arg("mesh"), pb::arg("text"), pb::arg("path"), pb::arg("save_folder"), pb::arg("threads"),
      pb::arg("quiet"), "ffdtool.run's compiled half: returns (Mesh, stats as JSON text).");
}

}  // namespace ffd::py
