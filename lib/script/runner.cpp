#include "script/runner.h"

#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <omp.h>

#include "common/atomic_file.h"
#include "common/errors.h"
#include "common/numbers.h"
#include "common/timer.h"
#include "mesh/file_normals.h"
#include "mesh/mesh_io.h"
#include "render/png_io.h"
#include "script/output_files.h"
#include "script/scene.h"
#include "script/script.h"
#include "script/volume_guard.h"

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

// The files the steps will write, checked before any work: an existing folder, never the
// input mesh or the script.
void check_step_outputs(const Script& script, const std::string& output_folder, const std::string& mesh) {
  for (const auto& step : script.steps)
    for (const OutputFile& file : step->outputs()) {
      const fs::path target = fs::path(output_folder) / file.path;
      const std::string where = script.path + ": " + step->pointer;
      std::error_code ec;
      if (!fs::is_directory(target.parent_path().empty() ? "." : target.parent_path(), ec))
        throw InputError(At{where}, "the folder of '" + target.string() + "' does not exist");
      if ((!mesh.empty() && same_file(target, mesh)) || same_file(target, script.path))
        throw InputError(At{where}, "'" + target.string() + "' would overwrite an input file");
    }
}

// Every path the run will write, checked before any work: known format, existing folder,
// never the input mesh (unless it is the named output) or the script.
void check_outputs(const RunOptions& options, const Script& script, const std::string& output_folder) {
  mesh_format(options.output);
  require_output_folder(options.output, "output");
  if (same_file(options.output, options.script))
    throw InputError(At{options.output}, "the output would overwrite the script");
  if (!options.stats.empty()) {
    require_output_folder(options.stats, "stats");
    for (const std::string& input : {options.mesh, options.script})
      if (same_file(options.stats, input)) throw InputError(At{options.stats}, "the stats file would overwrite an input");
  }
  if (!options.preview.empty()) {
    if (!has_png_extension(options.preview))
      throw InputError(At{options.preview}, "a preview is a PNG picture: give it the extension .png");
    require_output_folder(options.preview, "preview");
    for (const std::string& input : {options.mesh, options.script})
      if (same_file(options.preview, input)) throw InputError(At{options.preview}, "the preview would overwrite an input");
  }
  check_step_outputs(script, output_folder, options.mesh);
}

// Whether the run reads or writes vertex normals: a step that does, a preview, a glTF
// output (it holds normals whatever the input had), or file normals that miss a vertex
// (an OFF or PLY writer fills it in from the computed ones). File normals at every
// vertex are carried by the writers themselves, through the warps' Jacobians: a 44k-vertex
// OBJ with one vn per vertex no longer computes and moves normals it never writes.
bool needs_vertex_normals(const Script& script, const RunOptions& options, const Mesh& mesh) {
  const MeshFormat format = mesh_format(options.output);
  if (!options.preview.empty() || format == MeshFormat::Gltf || format == MeshFormat::Glb) return true;
  if (mesh.has_file_normals() && !every_vertex_has_file_normal(mesh)) return true;
  return std::any_of(script.steps.begin(), script.steps.end(),
                     [](const auto& step) { return step->needs_vertex_normals(); });
}

// Passes on the glTF reader's notes (skinned, morph-targeted meshes) as warnings;
// returns whether the mesh came from glTF.
bool gltf_notes(const RunOptions& options, Scene& scene) {
  const GltfSummary gltf = gltf_summary(scene.mesh);
  for (const std::string& note : gltf.notes) {
    scene.warnings.push_back(options.mesh + ": " + note);
    if (!options.quiet) std::fprintf(stderr, "  note: %s\n", note.c_str());
  }
  return gltf.instances > 0;
}

// Says what the reader kept without interpreting it (an OBJ's `vw`, `mg`, ... statements).
void reader_warnings(const RunOptions& options, Scene& scene) {
  for (const std::string& note : uninterpreted_data(scene.mesh)) {
    scene.warnings.push_back(options.mesh + ": " + note);
    if (!options.quiet) std::fprintf(stderr, "  warning: %s\n", scene.warnings.back().c_str());
  }
}

// A glTF written after a connectivity change cannot keep its source's structure: says so.
void warn_if_gltf_flattened(const RunOptions& options, Scene& scene, bool from_gltf) {
  const MeshFormat format = mesh_format(options.output);
  if (!from_gltf || scene.mesh.gltf_scene() || (format != MeshFormat::Gltf && format != MeshFormat::Glb)) return;
  scene.warnings.push_back(options.output + ": the steps changed the connectivity, so it is written as one plain "
                           "primitive (the source's nodes, materials and attributes other than normals are not kept)");
  if (!options.quiet) std::fprintf(stderr, "  warning: %s\n", scene.warnings.back().c_str());
}

// The stats' header: tool, build, threads and the input (`mesh`: its file, or null).
nlohmann::ordered_json input_stats(nlohmann::ordered_json mesh_file, const std::string& script, const Mesh& mesh,
                                   double read_ms) {
  nlohmann::ordered_json stats;
  stats["tool"] = "ffdtool";
  stats["version"] = FFD_VERSION;
  stats["build"] = FFD_BUILD_FLAGS;
  stats["threads"] = omp_get_max_threads();
  stats["input"] = {{"mesh", std::move(mesh_file)},
                    {"script", script},
                    {"vertices", mesh.num_vertices()},
                    {"faces", mesh.num_faces()},
                    {"read_ms", read_ms}};
  return stats;
}

// The stats' tail: the output (`mesh`: its file, or null), the totals, warnings and memory.
void output_stats(nlohmann::ordered_json& stats, nlohmann::ordered_json mesh_file, const Scene& scene,
                  double write_ms, double total_ms) {
  double steps_ms = 0;
  for (const auto& s : stats["steps"]) steps_ms += s["ms"].get<double>();
  stats["output"] = {{"mesh", std::move(mesh_file)}, {"vertices", scene.mesh.num_vertices()},
                     {"faces", scene.mesh.num_faces()}, {"write_ms", write_ms}};
  stats["totals"] = {{"steps_ms", steps_ms}, {"ms", total_ms}};
  stats["warnings"] = scene.warnings;
  stats["peak_memory_bytes"] = peak_memory_bytes();
}

// Runs every step in order, reporting to a progress reporter of `options.progress`;
// returns their stats.
nlohmann::ordered_json run_steps(const Script& script, Scene& scene, const RunOptions& options) {
  const bool quiet = options.quiet;
  Progress progress(quiet && options.progress == ProgressMode::Auto ? ProgressMode::None : options.progress);
  nlohmann::ordered_json steps = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < script.steps.size(); ++i) {
    const Step& step = *script.steps[i];
    StepContext ctx;
    ctx.pointer = step.pointer;
    ctx.progress = progress.step_callback();
    const std::size_t warnings_before = scene.warnings.size();
    progress.step_start(i, script.steps.size(), step.op->name());
    Stopwatch clock;
    try {
      run_step(script, step, scene, ctx);
    } catch (...) {
      progress.step_end(clock.ms(), false);
      throw;
    }
    const double ms = clock.ms();
    progress.step_end(ms);  // clears a terminal's line before the step's own line
    nlohmann::ordered_json entry = {{"index", i}, {"op", step.op->name()}, {"ms", ms},
                                    {"vertices", scene.mesh.num_vertices()}, {"faces", scene.mesh.num_faces()}};
    entry.update(ctx.stats);
    if (scene.mesh.volume_source()) entry["guard"] = guard_scene(scene);
    steps.push_back(entry);
    if (quiet) continue;
    std::fprintf(stderr, "  [%zu] %s (%s)\n", i, ctx.summary.c_str(), format_ms(ms).c_str());
    if (scene.quality) std::fprintf(stderr, "      %s\n", guard_line(*scene.quality).c_str());
    for (std::size_t w = warnings_before; w < scene.warnings.size(); ++w)
      std::fprintf(stderr, "  warning: %s\n", scene.warnings[w].c_str());
  }
  return steps;
}

// A volume mesh's facts and its guard verdict as read, into the stats' input.
void volume_input_stats(Scene& scene, nlohmann::ordered_json& stats, bool quiet) {
  if (!scene.mesh.volume_source()) return;
  stats["input"]["volume"] = volume_stats(scene.mesh);
  stats["input"]["guard"] = guard_scene(scene);
  if (!quiet) std::fprintf(stderr, "  as read: %s\n", guard_line(*scene.quality).c_str());
}

// Stages the stats file with the run's other outputs.
void stage_stats(const std::string& path, const nlohmann::ordered_json& stats, Scene& scene) {
  StagedFile staged(path);
  staged.write([&](std::ostream& os) { os << stats.dump(2) << "\n"; });
  scene.staged.push_back(std::move(staged));
}

}  // namespace

void run_step(const Script& script, const Step& step, Scene& scene, StepContext& ctx) {
  try {
    step.run(scene, ctx);
  } catch (Error& e) {
    if (!e.placed()) e.set_place(script.path + ": " + step.pointer + key_of(step.op->keys(), e.subject()));
    throw;
  }
}

nlohmann::ordered_json run_script(const RunOptions& options) {
  Stopwatch total;
  if (options.threads > 0) omp_set_num_threads(options.threads);
  const Script script = load_script(options.script);
  Scene scene;
  scene.output_folder =
      options.save_folder.empty() ? fs::path(options.output).parent_path().string() : options.save_folder;
  if (scene.output_folder.empty()) scene.output_folder = ".";
  check_outputs(options, script, scene.output_folder);

  Stopwatch read_clock;
  scene.mesh = read_mesh(options.mesh, /*defer_normals=*/true);
  if (needs_vertex_normals(script, options, scene.mesh)) scene.mesh.compute_deferred_normals();
  check_writable(scene.mesh, mesh_format(options.output), options.output);  // before any work
  nlohmann::ordered_json stats = input_stats(options.mesh, options.script, scene.mesh, read_clock.ms());
#ifndef NDEBUG
  scene.warnings.push_back("this ffdtool is not an optimized build: expect it to be many times slower");
#endif
  if (!options.quiet)
    std::fprintf(stderr, "ffdtool: %s: %s vertices, %s faces (read in %s)\n", options.mesh.c_str(),
                 format_count(scene.mesh.num_vertices()).c_str(), format_count(scene.mesh.num_faces()).c_str(),
                 format_ms(stats["input"]["read_ms"].get<double>()).c_str());
  const bool from_gltf = gltf_notes(options, scene);
  reader_warnings(options, scene);
  volume_input_stats(scene, stats, options.quiet);
  stats["steps"] = run_steps(script, scene, options);
  warn_if_gltf_flattened(options, scene, from_gltf);
  Stopwatch write_clock;
  const std::size_t warnings_before = scene.warnings.size();
  check_inverted_cells(scene, options.output, options.allow_inverted || script.allow_inverted);
  stage_mesh_at(scene, options.output, scene.write_options());
  for (std::size_t w = warnings_before; w < scene.warnings.size() && !options.quiet; ++w)
    std::fprintf(stderr, "  warning: %s\n", scene.warnings[w].c_str());
  if (!options.preview.empty()) stage_preview(scene, options.preview);
  output_stats(stats, options.output, scene, write_clock.ms(), total.ms());
  if (!options.stats.empty()) stage_stats(options.stats, stats, scene);
  // Each file goes in place in one step, but the files one after another: a run killed
  // in this loop leaves the ones before it in place, whole, and none of the rest.
  for (StagedFile& file : scene.staged) file.commit();
  if (!options.quiet)
    std::fprintf(stderr, "ffdtool: wrote %s: %s vertices, %s faces; steps %s, total %s\n", options.output.c_str(),
                 format_count(scene.mesh.num_vertices()).c_str(), format_count(scene.mesh.num_faces()).c_str(),
                 format_ms(stats["totals"]["steps_ms"].get<double>()).c_str(), format_ms(total.ms()).c_str());
  return stats;
}

nlohmann::ordered_json run_in_memory(const Script& script, Scene& scene, const MemoryRunOptions& options) {
  Stopwatch total;
  if (scene.output_folder.empty()) scene.output_folder = ".";
  check_step_outputs(script, scene.output_folder, options.mesh);
  nlohmann::ordered_json mesh_file;  // null: a mesh made from arrays
  if (!options.mesh.empty()) mesh_file = options.mesh;
  nlohmann::ordered_json stats = input_stats(mesh_file, script.path, scene.mesh, options.read_ms);
#ifndef NDEBUG
  scene.warnings.push_back("this ffdtool is not an optimized build: expect it to be many times slower");
#endif
  RunOptions step_options;
  step_options.mesh = options.mesh.empty() ? "mesh" : options.mesh;
  step_options.quiet = options.quiet;
  gltf_notes(step_options, scene);
  reader_warnings(step_options, scene);
  volume_input_stats(scene, stats, options.quiet);
  stats["steps"] = run_steps(script, scene, step_options);
  output_stats(stats, nullptr, scene, 0.0, total.ms());
  for (StagedFile& file : scene.staged) file.commit();
  scene.staged.clear();
  return stats;
}

}  // namespace ffd
