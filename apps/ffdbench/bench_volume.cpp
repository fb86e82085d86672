// The volume suite: what a volume mesh costs a user, as `ffdtool run` of a cubic B-spline
// move on a tetrahedral mesh of the unit cube (scripts/bench_volume_meshio.py: 1M nodes,
// 5.8M tets; --quick 27k nodes), in binary VTU (base64 without compression, and zlib:
// meshio's default), MSH 4.1 binary and SU2 ASCII. From the run's stats: read, FFD (the lattice and move steps), guard (as
// read and after each step), write; the whole process's wall time and peak bytes per node
// (child_run.h). Against meshio (Debian's python3-meshio) reading and writing the same
// file in the same run: the goal is ffdtool's read + write ≥ 5× faster than meshio's on
// binary VTU (held on the base64 file, the harder case for it), and the guard under 20%
// of the run (held on every format's row).
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>

#include <unistd.h>

#include "bench.h"
#include "child_run.h"
#include "common/errors.h"

namespace ffd::bench {
namespace {

using json = nlohmann::ordered_json;

// The move: a 5^3-cell cubic B-spline lattice on the mesh's box, point [3, 3, 3] moved.
json ffd_script() {
  return {{"version", 1},
          {"steps",
           {{{"op", "lattice"}, {"name", "L"}, {"cells", {5, 5, 5}}, {"box", {{"fit", "aabb"}, {"padding", 0.05}}}},
            {{"op", "move"}, {"lattice", "L"}, {"points", {{{"index", {3, 3, 3}}, {"by", {0.02, -0.01, 0.03}}}}}}}}};
}

// The mesh's files and meshio's times, from the generator.
json make_meshes(const TempFolder& dir, int n) {
  const std::vector<std::string> argv = {"/usr/bin/python3", std::string(FFD_SOURCE_ROOT) + "/scripts/bench_volume_meshio.py",
                                         dir.path.string(), std::to_string(n)};
  const ChildRun run = run_measured(argv, dir.path.string());
  if (!run.ok) throw InputError("scripts/bench_volume_meshio.py failed: " + last_line(run.err));
  return json::parse(run.out);
}

// The guard's ms over the run: as read and after each step.
double guard_ms(const json& stats) {
  double ms = stats["input"]["guard"]["guard_ms"].get<double>();
  for (const json& step : stats["steps"]) ms += step["guard"]["guard_ms"].get<double>();
  return ms;
}

// The row of one of the generator's files (`name`: vtu, vtu_zlib, msh, su2).
json format_row(const std::string& ffdtool, const TempFolder& dir, const std::string& name, const json& made) {
  const std::string script = dir.file("volume.json"), stats_path = dir.file("stats.json");
  std::ofstream(script) << ffd_script().dump(2) << "\n";
  std::fprintf(stderr, "ffdbench: volume: %s\n", name.c_str());
  const json& peer = made["meshio"][name];
  const std::string file = peer["file"].get<std::string>();
  const std::vector<std::string> argv = {ffdtool, "run", dir.file(file), script, "-o", dir.file("out_" + file),
                                         "--stats", stats_path, "--quiet"};
  ::sync();  // the writes before (meshio's files, the last row's output) go to disk first, not during the run
  const ChildRun run = run_measured(argv, dir.path.string());
  if (!run.ok) throw InputError("ffdtool run failed on " + file + ": " + last_line(run.err));
  std::ifstream is(stats_path);
  const json s = json::parse(is);
  const double read = s["input"]["read_ms"].get<double>(), write = s["output"]["write_ms"].get<double>();
  const double ffd = s["steps"][0]["ms"].get<double>() + s["steps"][1]["ms"].get<double>();
  const double guard = guard_ms(s);
  const double peer_ms = peer["read_ms"].get<double>() + peer["write_ms"].get<double>();
  const double nodes = made["nodes"].get<double>();
  const std::map<std::string, const char*> kinds = {{"vtu", "VTU binary (base64)"}, {"vtu_zlib", "VTU binary (zlib)"},
                                                     {"msh", "MSH 4.1 binary"}, {"su2", "SU2 ASCII"}};
  return {{"format", kinds.at(name)},
          {"bytes", peer["bytes"]}, {"read_ms", read}, {"ffd_ms", ffd}, {"guard_ms", guard}, {"write_ms", write},
          {"run_ms", run.ms}, {"peak_bytes_per_node", static_cast<double>(run.peak_bytes) / nodes},
          {"guard_share_of_run", guard / run.ms},
          {"meshio_read_ms", peer["read_ms"]}, {"meshio_write_ms", peer["write_ms"]},
          {"meshio_over_ffdtool_read_write", peer_ms / (read + write)},
          {"meshio_over_ffdtool_whole_run", peer_ms / run.ms}};
}

}  // namespace

void bench_volume(Context& ctx) {
  const std::string ffdtool = ffdtool_path(ctx.ffdtool);
  TempFolder dir("volume");
  const int n = ctx.quick ? 30 : 100;
  std::fprintf(stderr, "ffdbench: volume: making a %d^3-node tetrahedral mesh with meshio\n", n);
  const json made = make_meshes(dir, n);
  json rows = json::array();
  for (const char* name : {"vtu", "vtu_zlib", "msh", "su2"}) rows.push_back(format_row(ffdtool, dir, name, made));
  const json& vtu = rows[0];
  double guard_share = 0;  // the largest over the formats
  for (const json& row : rows) guard_share = std::max(guard_share, row["guard_share_of_run"].get<double>());
  ctx.out["volume"] = {
      {"nodes", made["nodes"]},
      {"cells", made["cells"]},
      {"rows", rows},
      {"targets",
       {{"vtu_read_write_vs_meshio", {{"goal", 5.0}, {"value", vtu["meshio_over_ffdtool_read_write"]},
                                      {"met", vtu["meshio_over_ffdtool_read_write"].get<double>() >= 5.0}}},
        {"guard_share_of_run", {{"goal", 0.2}, {"value", guard_share}, {"met", guard_share < 0.2}}}}}};
}

}  // namespace ffd::bench
