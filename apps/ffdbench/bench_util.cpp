// Benchmark helpers: timing, mesh loading, subdivision to a target size, child runs of
// ffdtool and Blender.
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Subdivision_method_3/subdivision_methods_3.h>

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <map>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "bench.h"
#include "common/errors.h"
#include "common/timer.h"
#include "mesh/mesh_io.h"
#include "mesh/halfedge_view_cgal.h"

#ifndef FFD_BENCH_SOURCE_DIR
#define FFD_BENCH_SOURCE_DIR "apps/ffdbench"
#endif

namespace ffd::bench {

double median_ms(int repeats, const std::function<void()>& fn) {
  fn();
  std::vector<double> times;
  for (int i = 0; i < std::max(1, repeats); ++i) {
    Stopwatch clock;
    fn();
    times.push_back(clock.ms());
  }
  std::sort(times.begin(), times.end());
  return times[times.size() / 2];
}

Mesh load(const Context& ctx, const std::string& name) {
  if (name == "bunny.obj") return read_mesh(ctx.test_data + "/bunny.obj");
  const std::string path = ctx.meshes + "/" + name;
  if (!std::filesystem::exists(path))
    throw InputError(path + ": benchmark mesh missing (scripts/bench.sh fetches the meshes)");
  return read_mesh(path);
}

Mesh subdivided(const Mesh& mesh, std::size_t min_vertices) {
  SurfaceMesh sm = surface_mesh(mesh);
  while (sm.number_of_vertices() < min_vertices)
    CGAL::Subdivision_method_3::Loop_subdivision(sm, CGAL::parameters::number_of_iterations(1));
  return mesh_from_surface(sm, mesh.source());
}

namespace {

/// x rounded to 6 decimals, as float exporters (Blender's) write coordinates.
double round6(double x) { return std::round(x * 1e6) / 1e6; }

}  // namespace

PolygonSoup height_field(int n) {
  PolygonSoup soup;
  soup.positions.reserve(static_cast<std::size_t>(n) * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = double(i) / (n - 1), y = double(j) / (n - 1);
      const double z = 0.08 * std::sin(2 * M_PI * x) * std::cos(2 * M_PI * y) +
                       0.03 * std::sin(7 * x + 1) * std::cos(5 * y + 0.5);
      soup.positions.emplace_back(round6(x), round6(y), round6(z));
    }
  soup.elements.reserve(2 * static_cast<std::size_t>(n - 1) * (n - 1), 3);
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const std::uint32_t a = j * n + i, b = a + 1, c = a + n, d = c + 1;
      soup.elements.add_polygon({a, b, d});
      soup.elements.add_polygon({a, d, c});
    }
  return soup;
}

double mb_per_s(double bytes, double ms) { return bytes / 1e3 / ms; }

std::string last_line(const std::string& text) {
  std::istringstream is(text);
  std::string line, last;
  while (std::getline(is, line))
    if (!line.empty()) last = line;
  return last;
}

std::string ffdtool_path(const std::string& configured) {
  std::string path = configured;
  if (path.empty()) {
    std::error_code ec;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    path = (self.parent_path() / ".." / "ffdtool" / "ffdtool").lexically_normal().string();
  }
  if (::access(path.c_str(), X_OK) != 0)
    throw InputError(path + ": no ffdtool there (build it with scripts/build.sh, or pass --ffdtool PATH)");
  return path;
}

TempFolder::TempFolder(const std::string& suite)
    : path(std::filesystem::temp_directory_path() / ("ffdbench-" + suite + "-" + std::to_string(::getpid()))) {
  std::filesystem::create_directories(path);
}

TempFolder::~TempFolder() {
  std::error_code ec;
  std::filesystem::remove_all(path, ec);
}

// A UV sphere: `slices` around, `stacks` from pole to pole, outward triangles.
PolygonSoup uv_sphere(int slices, int stacks, const Eigen::Vector3d& centre, double radius) {
  PolygonSoup soup;
  soup.positions.push_back(centre + Eigen::Vector3d(0, 0, radius));
  for (int i = 1; i < stacks; ++i)
    for (int j = 0; j < slices; ++j) {
      const double t = M_PI * i / stacks, p = 2 * M_PI * j / slices;
      soup.positions.push_back(centre + radius * Eigen::Vector3d(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)));
    }
  soup.positions.push_back(centre - Eigen::Vector3d(0, 0, radius));
  const auto ring = [&](int i, int j) { return static_cast<std::uint32_t>(1 + (i - 1) * slices + (j % slices)); };
  const std::uint32_t south = static_cast<std::uint32_t>(soup.positions.size() - 1);
  for (int j = 0; j < slices; ++j) {
    soup.elements.add_polygon({0, ring(1, j), ring(1, j + 1)});
    soup.elements.add_polygon({south, ring(stacks - 1, j + 1), ring(stacks - 1, j)});
    for (int i = 1; i + 1 < stacks; ++i) {
      soup.elements.add_polygon({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
      soup.elements.add_polygon({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
    }
  }
  return soup;
}

// Shared by the suites that run ffdtool and Blender as child processes (io, users).

/// The median of `values` (the upper one of an even count, as median_ms).
double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values.empty() ? 0 : values[values.size() / 2];
}

/// Writes `bytes` to `path`. \throw IoError if that fails.
void write_file(const std::string& path, const std::string& bytes) {
  std::ofstream os(path, std::ios::binary);
  os.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!os.flush()) throw IoError(At{path}, "cannot write");
}

/// `argv` run `warmups` + `repeats` times; the runs after the warm-ups, or the first
/// failed one alone.
std::vector<ChildRun> run_repeated(const std::vector<std::string>& argv, const TempFolder& dir,
                                   int warmups, int repeats) {
  std::vector<ChildRun> runs;
  for (int i = 0; i < warmups + std::max(1, repeats); ++i) {
    ChildRun run = run_measured(argv, dir.path.string());
    if (!run.ok) return {run};
    if (i >= warmups) runs.push_back(std::move(run));
  }
  return runs;
}

void child_medians(const std::vector<ChildRun>& runs, double& ms, double& peak_bytes, double* minor_faults) {
  std::vector<double> times, peaks, faults;
  for (const ChildRun& r : runs) {
    times.push_back(r.ms);
    peaks.push_back(static_cast<double>(r.peak_bytes));
    faults.push_back(static_cast<double>(r.minor_faults));
  }
  ms = median(times);
  peak_bytes = median(peaks);
  if (minor_faults) *minor_faults = median(faults);
}

/// The Blender the io and users suites run: `configured` (\throw InputError if it is not an
/// executable), else `blender` on PATH, else empty (not installed).
std::string blender_path(const std::string& configured) {
  if (!configured.empty()) {
    if (::access(configured.c_str(), X_OK) != 0) throw InputError(configured + ": no Blender executable there");
    return configured;
  }
  const char* env = std::getenv("PATH");
  std::istringstream dirs(env ? env : "");
  std::string d;
  while (std::getline(dirs, d, ':')) {
    const std::string candidate = (std::filesystem::path(d.empty() ? "." : d) / "blender").string();
    if (::access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return "";
}

/// The argv of a Blender run of blender_peer.py in `mode` with `args`.
std::vector<std::string> blender_argv(const std::string& blender, const std::vector<std::string>& peer_args) {
  std::vector<std::string> argv = {blender, "-b", "--factory-startup", "-noaudio", "-t", "1", "--python-exit-code",
                                   "2", "-P", std::string(FFD_BENCH_SOURCE_DIR) + "/blender_peer.py", "--"};
  argv.insert(argv.end(), peer_args.begin(), peer_args.end());
  return argv;
}

/// The peer's `FFDBENCH_JSON {...}` line of a Blender run, parsed (null if absent).
nlohmann::ordered_json peer_json(const ChildRun& run) {
  const std::string prefix = "FFDBENCH_JSON ";
  std::istringstream is(run.out);
  std::string line;
  while (std::getline(is, line))
    if (line.rfind(prefix, 0) == 0) return nlohmann::ordered_json::parse(line.substr(prefix.size()), nullptr, false);
  return nullptr;
}

/// Why a Blender run gave no result, for the row.
std::string blender_failure(const ChildRun& run) {
  const std::string err = last_line(run.err);
  return "failed: " + (err.empty() ? last_line(run.out) : err);
}

/// The peer run `repeats` times: "blender" (its version, or why a run failed) and, when
/// every run gave its JSON, "runs", "blender_wall_ms" and the medians of the peer's `keys`
/// (in name order) and of the peak RSS ("peak_bytes").
nlohmann::ordered_json blender_medians(const std::string& blender, const std::vector<std::string>& peer_args,
                                       const TempFolder& dir, int repeats, const std::vector<std::string>& keys) {
  nlohmann::ordered_json r = nlohmann::ordered_json::object();
  const std::vector<ChildRun> runs = run_repeated(blender_argv(blender, peer_args), dir, 0, repeats);
  std::map<std::string, std::vector<double>> phases;
  for (const ChildRun& run : runs) {
    const nlohmann::ordered_json j = peer_json(run);
    if (!run.ok || !j.is_object()) return {{"blender", blender_failure(run)}};
    for (const std::string& key : keys) phases[key].push_back(j.value(key, 0.0));
    r["blender"] = j.value("blender", "");
  }
  double wall = 0, peak = 0;
  child_medians(runs, wall, peak);
  r["runs"] = runs.size();
  r["blender_wall_ms"] = wall;
  for (const auto& [key, values] : phases) r[key] = median(values);
  r["peak_bytes"] = peak;
  return r;
}

}  // namespace ffd::bench
