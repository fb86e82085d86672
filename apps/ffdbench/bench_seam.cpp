// The seam suite: what the Deformer seam costs and what it cleaned up.
// - sensitivity: `ffdtool run` on a height field of 1M vertices (100k with --quick), binary
//   PLY, with a 10^3-cell cubic B-spline lattice: a move of its centre point, then a save of
//   dx/dp (Matrix Market). From the run's own stats: the save's ms against the same run's
//   move step (which re-evaluates every vertex the point reaches), the file's MB and MB/s,
//   and the whole process, on one thread and on two.
// - code: lines of lib/script, branches on a deformer's kind left in the ops, selections,
//   previews and drag (lines naming OctreeLattice or the octree map outside the kind's own
//   files), and includes from a lower lib folder to a higher one.
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include "bench.h"
#include "child_run.h"
#include "common/errors.h"
#include "mesh/build_mesh.h"
#include "mesh/mesh_io.h"

#ifndef FFD_SOURCE_ROOT
#define FFD_SOURCE_ROOT "."
#endif

namespace ffd::bench {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

std::string write_sensitivity_script(const TempFolder& dir) {
  const json script = {
      {"version", 1},
      {"steps",
       {{{"op", "lattice"}, {"name", "l"}, {"cells", {10, 10, 10}}},
        {{"op", "move"}, {"lattice", "l"}, {"points", {{{"index", {5, 5, 5}}, {"by", {0.02, 0.03, 0.05}}}}}},
        {{"op", "save"}, {"path", "dxdp.mtx"}, {"sensitivity", {{"lattice", "l"}}}}}}};
  const std::string path = dir.file("sensitivity.json");
  std::ofstream(path) << script.dump(2) << "\n";
  return path;
}

json sensitivity_row(const std::string& ffdtool, const std::string& mesh, std::size_t vertices,
                     const std::string& script, const TempFolder& dir, int threads) {
  const std::string stats = dir.file("stats.json");
  const std::vector<std::string> argv = {ffdtool, "run", mesh, script, "-o", dir.file("out.ply"), "--stats", stats,
                                         "--threads", std::to_string(threads), "--quiet"};
  const ChildRun run = run_measured(argv, dir.path.string());
  if (!run.ok) throw InputError("ffdtool run failed on " + mesh + ": " + last_line(run.err));
  std::ifstream is(stats);
  const json s = json::parse(is);
  const json& move = s["steps"][1];
  const json& save = s["steps"][2];
  const double bytes = save["bytes"].get<double>(), save_ms = save["ms"].get<double>();
  fs::remove(dir.file("dxdp.mtx"));
  return {{"vertices", vertices},
          {"threads", threads},
          {"movable_points", save["movable_points"]},
          {"entries", save["entries"]},
          {"move_ms", move["ms"]},
          {"sensitivity_ms", save_ms},
          {"sensitivity_vs_move", save_ms / move["ms"].get<double>()},
          {"MB", bytes / 1e6},
          {"MB_per_s", mb_per_s(bytes, save_ms)},
          {"process_ms", run.ms},
          {"peak_bytes", run.peak_bytes}};
}

std::size_t count_lines(const fs::path& file) {
  std::ifstream is(file);
  std::size_t n = 0;
  std::string line;
  while (std::getline(is, line)) ++n;
  return n;
}

/// The lint's layer-include findings (scripts/lint.py, whose LAYERS table says which lib
/// folder may include which): "file:line" of each include from a folder above.
std::vector<std::string> upward_includes(const fs::path& root) {
  const std::string command = "python3 " + (root / "scripts" / "lint.py").string() + " " + root.string();
  std::vector<std::string> found;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) throw InputError("cannot run " + command);
  char line[4096];
  while (std::fgets(line, sizeof line, pipe))
    if (std::strstr(line, "a folder above it")) found.push_back(std::string(line, std::strcspn(line, " ")));
  ::pclose(pipe);
  return found;
}

/// Lines of lib/script, kind branches outside the kinds' own files, and upward includes.
json code_row(const fs::path& root) {
  const fs::path lib = root / "lib";
  std::size_t script_lines = 0, branches = 0;
  json branch_lines = json::array();
  const std::regex kind(R"(OctreeLattice|\boctrees\b|run_octree|check_octree|select_octree_points|octree_drag)");
  for (const auto& entry : fs::recursive_directory_iterator(lib)) {
    const fs::path& p = entry.path();
    if (!entry.is_regular_file() || (p.extension() != ".cpp" && p.extension() != ".h")) continue;
    const std::string folder = p.parent_path().filename().string();
    const std::string rel = folder + "/" + p.filename().string();
    if (folder == "script") script_lines += count_lines(p);
    // The kinds' own files: their classes (lib/multires) and their ops (lattice, subdivide).
    const bool own = folder == "multires" || rel == "script/op_lattice.cpp" || rel == "script/op_subdivide.cpp" ||
                     rel == "script/selection.cpp" || rel == "script/selection.h";
    std::ifstream is(p);
    std::string line;
    for (std::size_t n = 1; std::getline(is, line); ++n) {
      if (!own && (folder == "script" || folder == "render" || folder == "warp") && std::regex_search(line, kind)) {
        ++branches;
        branch_lines.push_back(rel + ":" + std::to_string(n));
      }
    }
  }
  const std::vector<std::string> upward = upward_includes(root);
  return {{"script_lines", script_lines},
          {"kind_branches", branches},
          {"kind_branch_lines", branch_lines},
          {"upward_includes", upward.size()},
          {"upward_include_lines", upward}};
}

}  // namespace

void bench_seam(Context& ctx) {
  const TempFolder dir("seam");
  const std::string ffdtool = ffdtool_path(ctx.ffdtool);
  const int side = ctx.quick ? 317 : 1001;
  const std::string mesh_path = dir.file("field.ply");
  std::size_t vertices = 0;
  {
    Mesh mesh = build_mesh(height_field(side), mesh_path);
    vertices = mesh.num_vertices();
    WriteOptions binary;
    binary.encoding = WriteOptions::Encoding::Binary;
    write_mesh(mesh_path, mesh, binary);
  }
  const std::string script = write_sensitivity_script(dir);
  json rows = json::array();
  for (int threads : {1, 2}) {
    std::fprintf(stderr, "ffdbench: seam: dx/dp of %zu vertices, %d thread(s)\n", vertices, threads);
    rows.push_back(sensitivity_row(ffdtool, mesh_path, vertices, script, dir, threads));
  }
  ctx.out["seam"] = {{"sensitivity", rows}, {"code", code_row(fs::path(FFD_SOURCE_ROOT))}};
}

}  // namespace ffd::bench
