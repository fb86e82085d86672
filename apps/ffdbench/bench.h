// ffdbench: benchmark suites that print one JSON table. Every target is reported as a
// ratio against a baseline measured in the same run, on the same machine.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mesh/mesh.h"
#include "mesh/soup.h"

#include "child_run.h"

namespace ffd::bench {

struct Context {
  std::string meshes;  // folder with armadillo.off, bunny00.off, refined_elephant.off
  std::string test_data;
  bool quick = false;  // smaller sizes and fewer repeats, for a smoke run
  int repeats = 5;
  std::string ffdtool;  // the io suite's ffdtool (empty: the one next to ffdbench)
  std::string blender;  // the io suite's Blender (empty: blender on PATH, if any)
  nlohmann::ordered_json out = nlohmann::ordered_json::object();
};

struct Suite {
  const char* name;
  const char* what;
  void (*run)(Context&);
};

/// All suites, in the order `--suite all` runs them.
const std::vector<Suite>& suites();

/// Median wall time in ms of `repeats` runs of `fn` (after one warm-up run).
double median_ms(int repeats, const std::function<void()>& fn);

/// A mesh from the benchmark mesh folder (by file name), or the bundled bunny for
/// "bunny.obj". \throw InputError if missing.
Mesh load(const Context& ctx, const std::string& name);

/// `mesh` refined by Loop subdivision until it has at least `min_vertices` vertices
/// (CGAL's Subdivision_method_3), with rest = current positions and fresh normals.
Mesh subdivided(const Mesh& mesh, std::size_t min_vertices);

/// A height field on an n × n grid over [0,1]² (n² vertices, two triangles a cell), z a
/// few smooth bumps; every coordinate rounded to 6 decimals (as float exporters write
/// them). The io and pictures suites' grid mesh.
PolygonSoup height_field(int n);

/// A UV sphere: `slices` around, `stacks` from pole to pole, outward triangles.
PolygonSoup uv_sphere(int slices, int stacks, const Eigen::Vector3d& centre, double radius);

/// The last non-empty line of a child's output (its error line).
std::string last_line(const std::string& text);

/// The executable the suites run as ffdtool: `configured`, or the ffdtool next to this
/// binary (<dir of /proc/self/exe>/../ffdtool/ffdtool). \throw InputError if missing.
std::string ffdtool_path(const std::string& configured);

/// MB/s (MB = 10^6 bytes) of `bytes` in `ms`.
double mb_per_s(double bytes, double ms);

/// Where a suite keeps its files: temp_directory_path()/ffdbench-SUITE-PID, removed with
/// everything in it when the suite ends (also on an exception).
struct TempFolder {
  std::filesystem::path path;
  explicit TempFolder(const std::string& suite);
  ~TempFolder();
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;
  std::string file(const std::string& name) const { return (path / name).string(); }
};

/// The median of `values` (the upper one of an even count, as median_ms).
double median(std::vector<double> values);

/// Writes `bytes` to `path`. \throw IoError if that fails.
void write_file(const std::string& path, const std::string& bytes);

/// `argv` run `warmups` + `repeats` times; the runs after the warm-ups, or the first
/// failed one alone.
std::vector<ChildRun> run_repeated(const std::vector<std::string>& argv, const TempFolder& dir, int warmups,
                                   int repeats);

/// Median wall time and median peak RSS of `runs`, and their median minor page faults
/// where `minor_faults` is given.
void child_medians(const std::vector<ChildRun>& runs, double& ms, double& peak_bytes,
                   double* minor_faults = nullptr);

/// What a Blender row says when there is no Blender.
inline constexpr const char* kNoBlender = "not installed: apt-get install blender";

/// The Blender the io and users suites run: `configured` (\throw InputError if it is not
/// an executable), else `blender` on PATH, else empty (not installed).
std::string blender_path(const std::string& configured);

/// The argv of a Blender run (one thread) of blender_peer.py in `mode` with `args`.
std::vector<std::string> blender_argv(const std::string& blender, const std::vector<std::string>& peer_args);

/// The peer's `FFDBENCH_JSON {...}` line of a Blender run, parsed (null if absent).
nlohmann::ordered_json peer_json(const ChildRun& run);

/// Why a Blender run gave no result, for the row.
std::string blender_failure(const ChildRun& run);

/// The peer (blender_argv) run `repeats` times: "blender" (its version, or why a run
/// failed) and, when every run gave its JSON, "runs", "blender_wall_ms" and the medians of
/// the peer's `keys` (in name order) and of the peak RSS ("peak_bytes").
nlohmann::ordered_json blender_medians(const std::string& blender, const std::vector<std::string>& peer_args,
                                       const TempFolder& dir, int repeats, const std::vector<std::string>& keys);

/// The bcm suites' regions on a mesh: the support is the `support_size` vertices nearest
/// to the vertex farthest from the centroid (a geodesic-like cap over most of the
/// model), the handle the nearest `handle_size` of them; everything else is fixed.
struct Regions {
  std::vector<std::uint32_t> support, handle;  // sorted vertex indices
  double diagonal = 0;                         // of the mesh's bounding box
};
Regions cap_regions(const Mesh& mesh, std::size_t support_size, std::size_t handle_size);

// Suites (one file each).
void bench_ffd(Context& ctx);
void bench_remesh(Context& ctx);
void bench_bcm(Context& ctx);
void bench_cholesky(Context& ctx);
void bench_io(Context& ctx);
/// The io suite's glTF rows (bench_gltf_io.cpp): `mesh` as GLB in each coding, read and
/// written, against plain glTF.
nlohmann::ordered_json gltf_coding_rows(const Mesh& mesh, const TempFolder& dir, int repeats);
void bench_pictures(Context& ctx);
void bench_multires(Context& ctx);
void bench_seam(Context& ctx);
void bench_deformers(Context& ctx);
void bench_compare(Context& ctx);
void bench_python(Context& ctx);
void bench_users(Context& ctx);
void bench_volume(Context& ctx);

}  // namespace ffd::bench
