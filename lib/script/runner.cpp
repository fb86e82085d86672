#include "script/runner.h"

#include <sys/resource.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <omp.h>

#include "common/atomic_file.h"
#include "common/errors.h"
#include "common/numbers.h"
#include "common/timer.h"
#include "mesh/mesh_io.h"
#include "script/ops.h"
#include "script/scene.h"
#include "script/script.h"

namespace ffd {
namespace fs = std::filesystem;
using json = nlohmann::json;

std::size_t peak_memory_bytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<std::size_t>(usage.ru_maxrss) * 1024;
}

namespace {

bool same_file(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
  return fs::weakly_canonical(a, ec) == fs::weakly_canonical(b, ec);
}

// Every path the run will write, checked before any work: known format, existing folder,
// never the input mesh (unless it is the named output) or the script.
void check_outputs(const RunOptions& options, const Script& script, const std::string& output_folder) {
  mesh_format(options.output);
  require_output_folder(options.output, "output");
  if (same_file(options.output, options.script))
    throw InputError(options.output + ": the output would overwrite the script");
  if (!options.stats.empty()) {
    require_output_folder(options.stats, "stats");
    for (const std::string& input : {options.mesh, options.script})
      if (same_file(options.stats, input)) throw InputError(options.stats + ": the stats file would overwrite an input");
  }
  const json& steps = script.resolved["steps"];
  for (std::size_t i = 0; i < steps.size(); ++i) {
    if (!steps[i].contains("path") && !steps[i].contains("save")) continue;
    // A save step's path, or each frame's path of a transform step's save pattern.
    std::vector<std::string> paths;
    if (steps[i].contains("path")) {
      paths.push_back(steps[i]["path"]);
    } else {
      const std::size_t frames = steps[i].contains("frames") ? steps[i]["frames"].size() : 1;
      for (std::size_t f = 0; f < frames; ++f) paths.push_back(frame_path(steps[i]["save"], f));
    }
    const std::string where = script.path + ": /steps/" + std::to_string(i);
    for (const std::string& rel : paths) {
      const fs::path target = fs::path(output_folder) / rel;
      std::error_code ec;
      if (!fs::is_directory(target.parent_path().empty() ? "." : target.parent_path(), ec))
        throw InputError(where + ": the folder of '" + target.string() + "' does not exist");
      if (same_file(target, options.mesh) || same_file(target, options.script))
        throw InputError(where + ": '" + target.string() + "' would overwrite an input file");
    }
  }
}

std::string ms_text(double ms) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f ms", ms);
  return buf;
}

}  // namespace

nlohmann::ordered_json run_script(const RunOptions& options) {
  Stopwatch total;
  if (options.threads > 0) omp_set_num_threads(options.threads);
  const Script script = load_script(options.script);
  Scene scene;
  scene.script_path = options.script;
  scene.script_folder = script.folder;
  scene.output_folder = fs::path(options.output).parent_path().string();
  if (scene.output_folder.empty()) scene.output_folder = ".";
  check_outputs(options, script, scene.output_folder);

  Stopwatch read_clock;
  scene.mesh = read_mesh(options.mesh);
  const double read_ms = read_clock.ms();

  nlohmann::ordered_json stats;
  stats["tool"] = "ffdtool";
  stats["version"] = FFD_VERSION;
  stats["build"] = FFD_BUILD_FLAGS;
  stats["threads"] = omp_get_max_threads();
  stats["input"] = {{"mesh", options.mesh},
                    {"script", options.script},
                    {"vertices", scene.mesh.num_vertices()},
                    {"faces", scene.mesh.num_faces()},
                    {"read_ms", read_ms}};
#ifndef NDEBUG
  scene.warnings.push_back("this ffdtool is not an optimized build: expect it to be many times slower");
#endif
  if (!options.quiet)
    std::fprintf(stderr, "ffdtool: %s: %s vertices, %s faces (read in %s)\n", options.mesh.c_str(),
                 format_count(scene.mesh.num_vertices()).c_str(), format_count(scene.mesh.num_faces()).c_str(),
                 ms_text(read_ms).c_str());

  nlohmann::ordered_json steps = nlohmann::ordered_json::array();
  const json& script_steps = script.resolved["steps"];
  for (std::size_t i = 0; i < script_steps.size(); ++i) {
    const json& step = script_steps[i];
    const std::string op = step["op"];
    StepContext ctx;
    ctx.pointer = "/steps/" + std::to_string(i);
    const std::size_t warnings_before = scene.warnings.size();
    Stopwatch clock;
    find_op(op).run(scene, step, ctx);
    const double ms = clock.ms();
    nlohmann::ordered_json entry = {{"index", i}, {"op", op}, {"ms", ms}, {"vertices", scene.mesh.num_vertices()},
                  {"faces", scene.mesh.num_faces()}};
    entry.update(ctx.stats);
    steps.push_back(entry);
    if (!options.quiet) {
      std::fprintf(stderr, "  [%zu] %s (%s)\n", i, ctx.summary.c_str(), ms_text(ms).c_str());
      for (std::size_t w = warnings_before; w < scene.warnings.size(); ++w)
        std::fprintf(stderr, "  warning: %s\n", scene.warnings[w].c_str());
    }
  }
  stats["steps"] = steps;

  Stopwatch write_clock;
  const std::string output_name = fs::path(options.output).filename().string();
  stage_mesh(scene, output_name, scene.write_options());
  const double write_ms = write_clock.ms();

  double steps_ms = 0;
  for (const auto& s : steps) steps_ms += s["ms"].get<double>();
  stats["output"] = {{"mesh", options.output}, {"vertices", scene.mesh.num_vertices()},
                     {"faces", scene.mesh.num_faces()}, {"write_ms", write_ms}};
  stats["totals"] = {{"steps_ms", steps_ms}, {"ms", total.ms()}};
  stats["warnings"] = scene.warnings;
  stats["peak_memory_bytes"] = peak_memory_bytes();

  if (!options.stats.empty()) {
    StagedFile staged(options.stats);
    {
      std::ofstream os(staged.temp_path(), std::ios::binary | std::ios::trunc);
      os << stats.dump(2) << "\n";
      if (!os) throw RunError(options.stats + ": cannot write");
    }
    scene.staged.push_back(std::move(staged));
  }
  for (StagedFile& file : scene.staged) file.commit();
  if (!options.quiet)
    std::fprintf(stderr, "ffdtool: wrote %s: %s vertices, %s faces; steps %s, total %s\n", options.output.c_str(),
                 format_count(scene.mesh.num_vertices()).c_str(), format_count(scene.mesh.num_faces()).c_str(),
                 ms_text(steps_ms).c_str(), ms_text(total.ms()).c_str());
  return stats;
}

}  // namespace ffd
