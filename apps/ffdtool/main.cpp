// ffdtool: the command line. Subcommands only; the work is in lib/.
// Exit codes: 0 done (compare: within tolerance), 1 compare found a difference,
// 2 bad input (usage, file, script), 3 failure while running.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <cstdlib>
#include <iostream>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "batch/batch.h"
#include "batch/batch_junit.h"
#include "batch/batch_report.h"
#include "common/atomic_file.h"
#include "common/errors.h"
#include "common/numbers.h"
#include "mesh/mesh_info.h"
#include "mesh/mesh_io.h"
#include "compare_command.h"
#include "pictures.h"
#include "script/runner.h"
#include "script/schema.h"
#include "script/schema_markdown.h"
#include "script/scene.h"
#include "script/script.h"
#include "script/volume_guard.h"

namespace {

int fail(int code, const std::string& message) {
  std::fprintf(stderr, "ffdtool: error: %s\n", message.c_str());
  return code;
}

// `info --json`: the mesh's facts as JSON (keys sorted, as nlohmann::json keeps them).
nlohmann::json mesh_info_json(const ffd::MeshInfo& info) {
  nlohmann::json by_degree = nlohmann::json::object();
  for (const auto& [degree, count] : info.faces_by_degree) by_degree[std::to_string(degree)] = count;
  return {{"vertices", info.vertices},
          {"faces", info.faces},
          {"edges", info.edges},
          {"faces_by_degree", by_degree},
          {"lines", info.lines},
          {"points", info.points},
          {"boundary_edges", info.boundary_edges},
          {"non_manifold_edges", info.non_manifold_edges},
          {"manifold", info.manifold_problem.empty()},
          {"boundary_loops", info.boundary_loops},
          {"components", info.components},
          {"isolated_vertices", info.isolated_vertices},
          {"degenerate_faces", info.degenerate_faces},
          {"euler_characteristic", info.euler},
          {"closed", info.boundary_edges == 0 && info.faces > 0},
          {"bbox_min", {info.min[0], info.min[1], info.min[2]}},
          {"bbox_max", {info.max[0], info.max[1], info.max[2]}},
          {"bbox_diagonal", info.diagonal},
          {"edge_length", {{"min", info.min_edge}, {"mean", info.mean_edge}, {"max", info.max_edge}}},
          {"uvs", info.has_uvs},
          {"normals", info.has_normals},
          {"colors", info.has_colors}};
}

// `info`'s glTF facts, for a mesh read from glTF.
nlohmann::json gltf_json(const ffd::GltfSummary& g) {
  return {{"nodes", g.nodes},         {"meshes", g.meshes},       {"primitives", g.primitives},
          {"instances", g.instances}, {"materials", g.materials}, {"textures", g.textures},
          {"images", g.images},       {"animations", g.animations}, {"skins", g.skins},
          {"binary", g.binary},       {"notes", g.notes}};
}

void print_gltf_info(const ffd::GltfSummary& g) {
  std::printf("  glTF       %s: %zu nodes, %zu meshes drawn by %zu nodes, %zu primitives\n",
              g.binary ? "binary (GLB)" : "JSON", g.nodes, g.meshes, g.instances, g.primitives);
  std::printf("             %zu materials, %zu textures, %zu images, %zu animations, %zu skins\n", g.materials,
              g.textures, g.images, g.animations, g.skins);
  for (const std::string& note : g.notes) std::printf("  note       %s\n", note.c_str());
}

// `info` on a volume mesh: its facts (script/volume_guard.h) and the guard's verdict.
int volume_info(ffd::Mesh read, const std::string& path, bool as_json) {
  ffd::Scene scene;
  scene.mesh = std::move(read);
  const ffd::Mesh& mesh = scene.mesh;
  const nlohmann::ordered_json facts = ffd::volume_stats(scene.mesh);
  const nlohmann::ordered_json guard = ffd::guard_scene(scene);
  if (as_json) {
    nlohmann::ordered_json j = {{"path", path}, {"vertices", mesh.num_vertices()}, {"volume", facts}, {"guard", guard}};
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::string kinds, markers;
  for (const auto& [kind, count] : facts["cells_by_type"].items())
    kinds += (kinds.empty() ? "" : ", ") + ffd::format_count(count.get<std::size_t>()) + " " + kind;
  for (const auto& m : facts["markers"])
    markers += (markers.empty() ? "" : ", ") + m["name"].get<std::string>() + " (" +
               ffd::format_count(m["elements"].get<std::size_t>()) + " elements)";
  const auto& lo = facts["bbox_min"];
  const auto& hi = facts["bbox_max"];
  std::printf("%s\n", path.c_str());
  std::printf("  format     %s %s, %s, %dD\n", facts["format"].get<std::string>().c_str(),
              facts["version"].get<std::string>().c_str(), facts["encoding"].get<std::string>().c_str(),
              facts["dimension"].get<int>());
  std::printf("  nodes      %s\n", ffd::format_count(mesh.num_vertices()).c_str());
  std::printf("  cells      %s (%s)\n", ffd::format_count(facts["cells"].get<std::size_t>()).c_str(), kinds.c_str());
  std::printf("  markers    %s\n", markers.empty() ? "none" : markers.c_str());
  std::printf("  bbox       [%g, %g, %g] .. [%g, %g, %g]\n", lo[0].get<double>(), lo[1].get<double>(),
              lo[2].get<double>(), hi[0].get<double>(), hi[1].get<double>(), hi[2].get<double>());
  std::printf("  quality    %s\n", ffd::guard_line(*scene.quality).c_str());
  std::printf("  steps      every space warp moves the nodes; remesh and bcm refuse a volume mesh\n");
  return 0;
}

int command_info(const std::string& path, bool as_json) {
  ffd::Mesh mesh = ffd::read_mesh(path);
  if (mesh.volume_source()) return volume_info(std::move(mesh), path, as_json);
  const ffd::MeshInfo info = ffd::mesh_info(mesh);
  const bool gltf = mesh.gltf_scene() != nullptr;
  if (as_json) {
    nlohmann::json j = mesh_info_json(info);
    j["path"] = path;
    if (gltf) j["gltf"] = gltf_json(ffd::gltf_summary(mesh));
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::string kinds;
  for (const auto& [degree, count] : info.faces_by_degree)
    kinds += (kinds.empty() ? "" : ", ") + ffd::format_count(count) + " with " + std::to_string(degree) + " sides";
  std::printf("%s\n", path.c_str());
  std::printf("  vertices   %s (%s isolated)\n", ffd::format_count(info.vertices).c_str(),
              ffd::format_count(info.isolated_vertices).c_str());
  std::printf("  faces      %s (%s)\n", ffd::format_count(info.faces).c_str(), kinds.c_str());
  if (info.lines || info.points)
    std::printf("  also       %s lines, %s point elements\n", ffd::format_count(info.lines).c_str(),
                ffd::format_count(info.points).c_str());
  std::printf("  edges      %s (%s on the boundary, %zu boundary loops)\n", ffd::format_count(info.edges).c_str(),
              ffd::format_count(info.boundary_edges).c_str(), info.boundary_loops);
  std::printf("  pieces     %zu connected, Euler characteristic %ld, %s\n", info.components, info.euler,
              info.boundary_edges == 0 && info.faces ? "closed" : "open");
  std::printf("  bbox       [%g, %g, %g] .. [%g, %g, %g], diagonal %g\n", info.min[0], info.min[1], info.min[2],
              info.max[0], info.max[1], info.max[2], info.diagonal);
  std::printf("  edges len  min %g, mean %g, max %g\n", info.min_edge, info.mean_edge, info.max_edge);
  std::printf("  degenerate %s zero-area faces\n", ffd::format_count(info.degenerate_faces).c_str());
  std::printf("  topology   %s\n", info.manifold_problem.empty()
                                         ? "an oriented 2-manifold (remesh and bcm accept it)"
                                         : ("not a 2-manifold, so remesh and bcm refuse it: " + info.manifold_problem).c_str());
  std::printf("  carries    %s%s%s\n", info.has_uvs ? "UVs " : "", info.has_normals ? "normals " : "",
              info.has_colors ? "colours" : (info.has_uvs || info.has_normals ? "" : "positions only"));
  if (gltf) print_gltf_info(ffd::gltf_summary(mesh));
  return 0;
}

int command_validate(const std::string& path, bool resolved) {
  const ffd::Script script = ffd::load_script(path);
  if (resolved)
    std::cout << script.resolved.dump(2) << "\n";
  else
    std::printf("%s: valid (%zu steps)\n", path.c_str(), script.resolved["steps"].size());
  return 0;
}

// Every subcommand's options, filled by CLI11.
struct Commands {
  ffd::RunOptions run;
  ffdcli::CompareArgs compare;
  std::string info_path;
  bool info_json = false;
  std::string validate_path;
  bool resolved = false;
  bool markdown = false;
  ffd::BatchOptions batch;
  std::string shard, max_memory;
  std::string report_folder, report_junit;
  bool report_json = false;
  ffdcli::PictureArgs picture;
  CLI::App *render_cmd = nullptr;
  CLI::App *run_cmd = nullptr, *compare_cmd = nullptr, *info_cmd = nullptr, *validate_cmd = nullptr,
           *schema_cmd = nullptr, *batch_cmd = nullptr, *report_cmd = nullptr;
};

// `--progress auto|json|none` (default auto) into `mode`.
void add_progress(CLI::App* command, ffd::ProgressMode& mode, const std::string& doc) {
  mode = ffd::ProgressMode::Auto;
  command
      ->add_option_function<std::string>(
          "--progress", [&mode](const std::string& name) { mode = ffd::progress_mode_names().at(name); }, doc)
      ->check(CLI::IsMember({"auto", "json", "none"}))
      ->default_str("auto");
}

void add_batch(CLI::App& app, Commands& c) {
  ffd::BatchOptions& b = c.batch;
  c.batch_cmd = app.add_subcommand("batch", "Run a script on many meshes (each in a process of its own)");
  c.batch_cmd->add_option("script", b.script, "JSON deformation script")->required();
  c.batch_cmd->add_option("inputs", b.inputs, "Mesh files, folders or @list.txt files")->required();
  c.batch_cmd->add_option("-o,--output", b.output_folder, "Output folder: OUT/name.ext, saves in OUT/name/")->required();
  c.batch_cmd->add_option("--jobs", b.jobs, "Meshes at once (default: one per core)")->check(CLI::PositiveNumber);
  c.batch_cmd->add_option("--shard", c.shard, "I/N: only items whose index is I mod N (default: from SLURM_ARRAY_TASK_ID)");
  c.batch_cmd->add_flag("--resume", b.resume, "Skip meshes done before with the same input and script");
  c.batch_cmd->add_option("--format", b.format, "Output extension (obj, off, ply, stl, gltf, glb; default: the input's)");
  c.batch_cmd->add_flag("--recursive", b.recursive, "Take meshes from the folders' subfolders too");
  c.batch_cmd->add_option("--timeout", b.timeout_s, "Seconds per mesh; past it the mesh fails")->check(CLI::PositiveNumber);
  c.batch_cmd->add_option("--max-memory", c.max_memory, "Memory per mesh (bytes, or with K, M, G); past it the mesh fails");
  add_progress(c.batch_cmd, b.progress, "auto: a live line on a terminal's stderr; json: NDJSON events on stderr; none");
  c.batch_cmd->add_option("--junit", b.junit, "Also write the meshes as a JUnit XML report (one test case each) here");
  c.report_cmd = app.add_subcommand("report", "Summarize a batch's results files");
  c.report_cmd->add_option("folder", c.report_folder, "The batch's output folder")->required();
  c.report_cmd->add_flag("--json", c.report_json, "Print as JSON");
  c.report_cmd->add_option("--junit", c.report_junit, "Also write the results as a JUnit XML report here");
}

// "512M" -> bytes. \throw InputError for anything else.
std::size_t parse_bytes(const std::string& text) {
  std::size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  const std::string unit = text.substr(used);
  const double scale = unit.empty() ? 1 : unit == "K" ? 1024.0 : unit == "M" ? 1048576.0 : unit == "G" ? 1073741824.0 : -1;
  if (used == 0 || scale < 0 || !(value > 0)) throw ffd::InputError("--max-memory: expected bytes, or a number with K, M or G, found '" + text + "'");
  return static_cast<std::size_t>(value * scale);
}

int command_batch(Commands& c) {
  if (!c.shard.empty()) c.batch.shard = ffd::parse_shard(c.shard);
  if (!c.max_memory.empty()) c.batch.max_memory = parse_bytes(c.max_memory);
  if (const char* runner = std::getenv("FFD_BATCH_RUNNER")) c.batch.runner = runner;  // a seam for tests
  return ffd::run_batch(c.batch);
}

int command_report(const std::string& folder, bool as_json, const std::string& junit) {
  if (!junit.empty()) ffd::require_output_folder(junit, "--junit");
  const ffd::BatchReport report = ffd::batch_report(folder);
  if (!junit.empty()) ffd::write_junit(junit, ffd::batch_junit(ffd::read_results(folder), folder));
  if (as_json)
    std::cout << ffd::report_json(report).dump(2) << "\n";
  else
    std::cout << ffd::report_text(report);
  return 0;
}

void add_run(CLI::App& app, Commands& c) {
  ffd::RunOptions& run = c.run;
  c.run_cmd = app.add_subcommand("run", "Run a deformation script on a mesh");
  c.run_cmd->add_option("mesh", run.mesh, "Input mesh (.obj .off .ply .stl .gltf .glb; volume: .vtu .vtk .msh .su2, or an OpenFOAM polyMesh folder)")->required();
  c.run_cmd->add_option("script", run.script, "JSON deformation script")->required();
  c.run_cmd->add_option("-o,--output", run.output, "Output mesh; its folder receives the script's saves")->required();
  c.run_cmd->add_option("--stats", run.stats, "Write the stats report (JSON) here");
  c.run_cmd->add_option("--preview", run.preview, "Render the final mesh with every lattice's control net to this PNG");
  c.run_cmd->add_option("--save-dir", run.save_folder, "Folder the script's save paths are relative to (default: OUT's)");
  c.run_cmd->add_flag("--quiet", run.quiet, "No per-step lines on stderr");
  c.run_cmd->add_flag("--allow-inverted", run.allow_inverted,
                      "Volume meshes: write the result even if it has inverted cells (a warning names them)");
  c.run_cmd->add_option("--threads", run.threads, "Threads for evaluation (default: all cores)")
      ->check(CLI::NonNegativeNumber);
  add_progress(c.run_cmd, run.progress,
               "auto: the step in progress on a terminal's stderr (not with --quiet); json: NDJSON events on stderr; none");
}

void add_script_commands(CLI::App& app, Commands& c) {
  c.info_cmd = app.add_subcommand("info", "Print counts and measures of a mesh");
  c.info_cmd->add_option("mesh", c.info_path, "Mesh file")->required();
  c.info_cmd->add_flag("--json", c.info_json, "Print as JSON");
  c.validate_cmd = app.add_subcommand("validate", "Check a script without running it");
  c.validate_cmd->add_option("script", c.validate_path, "JSON script")->required();
  c.validate_cmd->add_flag("--resolved", c.resolved, "Print the script with every default filled in");
  c.schema_cmd = app.add_subcommand("schema", "Print the script format's JSON Schema");
  c.schema_cmd->add_flag("--markdown", c.markdown, "Print the script reference in Markdown instead");
}

// Runs the chosen subcommand; returns its exit code.
int dispatch(Commands& c) {
  if (*c.batch_cmd) return command_batch(c);
  if (*c.report_cmd) return command_report(c.report_folder, c.report_json, c.report_junit);
  if (*c.run_cmd) {
    ffd::run_script(c.run);
    return 0;
  }
  if (*c.compare_cmd) return ffdcli::command_compare(c.compare);
  if (*c.render_cmd) return ffdcli::command_render(c.picture);
  if (*c.info_cmd) return command_info(c.info_path, c.info_json);
  if (*c.validate_cmd) return command_validate(c.validate_path, c.resolved);
  if (c.markdown)
    std::cout << ffd::script_reference_markdown();
  else
    std::cout << ffd::script_schema().dump(2) << "\n";
  return 0;
}

// A run frees large arrays and then allocates others of about the same size: the reader's
// polygon soup, then the deformed positions and normals and the tags of the moves. By
// default glibc maps each array of 128 KiB or more from the kernel and unmaps it when
// freed, so every new array is fresh pages that the kernel must fault in and zero (about
// 1 us per 4 KiB here). With arrays up to 32 MiB (glibc's largest threshold) taken from the
// heap, and freed memory kept rather than trimmed, the later arrays reuse the pages of the
// earlier ones. Measured on the 1M-vertex sphere (one thread): the move step 33.0 -> 28.9
// ms, peak memory unchanged (185 bytes per vertex). Only this program: the library, which
// Python loads, leaves the allocator as the host set it.
void keep_freed_memory() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
#endif
}

}  // namespace

int main(int argc, char** argv) {
  keep_freed_memory();
  CLI::App app{"ffdtool: deform polygon meshes with lattice FFD scripts"};
  app.set_version_flag("--version", std::string("ffdtool ") + FFD_VERSION + " (" + FFD_BUILD_FLAGS + ")");
  app.require_subcommand(1);
  Commands commands;
  add_run(app, commands);
  commands.compare_cmd = ffdcli::add_compare(app, commands.compare);
  add_script_commands(app, commands);
  add_batch(app, commands);
  commands.render_cmd = ffdcli::add_render(app, commands.picture);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return fail(2, std::string(e.what()) + " (see ffdtool --help)");
  }

  try {
    return dispatch(commands);
  } catch (const ffd::InputError& e) {
    return fail(2, e.what());
  } catch (const ffd::Error& e) {
    return fail(3, e.what());
  } catch (const std::bad_alloc&) {
    return fail(3, "out of memory");
  } catch (const std::exception& e) {
    return fail(3, std::string("internal error: ") + e.what());
  }
}
