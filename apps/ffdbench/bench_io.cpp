// Mesh file I/O, per format (OBJ, OFF, ASCII and binary PLY, ASCII and binary STL), on a
// height-field grid of 100k and 1M vertices (--quick: 20k, one repeat):
// - files: read and write MB/s (MB = 10^6 bytes), against read(2) of the same file's
//   bytes measured in the same run, into a buffer touched beforehand (the page-cache
//   copy) and into a fresh mapping (with the page faults a new process pays);
// - ffdtool_run: the end-to-end `ffdtool run` of a one-point lattice edit, one thread, as
//   a child process (wall time, peak RSS: child_run.h), against the in-process read + write
//   of the same files;
// - blender_job: the same job in Blender (blender_peer.py `job`), side by side;
// - kernel: BSplineLattice::apply (positions + normals, one thread) against Blender's
//   Lattice modifier (blender_peer.py `kernel`);
// - gltf: the largest grid as GLB, plain, Draco, meshopt and quantized, read and written,
//   against plain (bench_gltf_io.cpp).
// Without Blender the Blender rows say how to install it and the suite still succeeds.
#include <fcntl.h>
#include <omp.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <numeric>
#include <sstream>

#include "bench.h"
#include "child_run.h"
#include "common/errors.h"
#include "common/timer.h"
#include "mesh/build_mesh.h"
#include "mesh/mesh_io.h"
#include "warp/bspline_lattice.h"

namespace ffd::bench {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

// The job both tools run: a cubic lattice of kCells³ cells on the mesh's padded box,
// point (kPoint, kPoint, kPoint) moved by kDelta. Blender numbers a lattice's points from
// 0, ffdtool a cubic one from -1 (the phantom layer), so the same point is kPoint + 1 there.
constexpr int kCells = 6;
constexpr int kPoint = 3;
constexpr int kBlenderPoint = kPoint + 1;
constexpr double kDelta[3] = {0.1, 0.2, 0.3};
constexpr int kBlenderRepeats = 3;

/// A file format of the suite: its row name, file extension, whether ffdtool writes the
/// input file (else the bench's own float32 writer below does, as exporters write binary
/// PLY and STL; ffdtool's binary writer is then timed on a file of its own), and whether
/// Blender reads it.
struct Format {
  const char* name;
  const char* ext;
  bool ffdtool_writes;
  bool blender_reads;
};

const std::vector<Format>& formats() {
  static const std::vector<Format> all = {
      {"obj", ".obj", true, true},          {"off", ".off", true, false},
      {"ply_ascii", ".ply", true, false},   {"stl_ascii", ".stl", true, false},
      {"ply_binary", ".ply", false, true},  {"stl_binary", ".stl", false, true},
  };
  return all;
}

/// The format ffdtool writes for an input of format `f`: the same (PLY and STL keep the
/// input's encoding).
std::string output_format(const Format& f) { return f.name; }

bool is_binary(const Format& f) { return std::string(f.name).find("binary") != std::string::npos; }

/// Median ms over `repeats` (after one warm-up run, as median_ms) of build_mesh on a
/// copy of `soup` (the copy not timed): the step every reader ends with, the same for
/// every format.
double build_mesh_ms(const PolygonSoup& soup, int repeats) {
  std::vector<double> times;
  for (int i = 0; i <= std::max(1, repeats); ++i) {
    PolygonSoup copy = soup;
    Stopwatch clock;
    const Mesh mesh = build_mesh(std::move(copy), "grid");
    if (i > 0) times.push_back(clock.ms());
  }
  return median(times);
}

/// Appends the bytes of `value` (host order: little-endian on the machines we run on).
template <class T>
void append(std::string& out, T value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof value);
}

/// Writes `mesh` as binary little-endian PLY: float x y z, `property list uchar int
/// vertex_indices` (the layout Blender's exporter writes, without normals).
void write_ply_binary(const std::string& path, const Mesh& mesh) {
  const auto pos = mesh.positions();
  std::string out = "ply\nformat binary_little_endian 1.0\nelement vertex " +
                    std::to_string(mesh.num_vertices()) +
                    "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                    std::to_string(mesh.num_faces()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  out.reserve(out.size() + 12 * mesh.num_vertices() + 13 * mesh.num_faces());
  for (Eigen::Index v = 0; v < pos.cols(); ++v)
    for (int a = 0; a < 3; ++a) append(out, static_cast<float>(pos(a, v)));
  std::vector<std::uint32_t> face;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    mesh.face_vertices(f, face);
    append(out, static_cast<std::uint8_t>(face.size()));
    for (std::uint32_t v : face) append(out, static_cast<std::int32_t>(v));
  }
  write_file(path, out);
}

/// Writes `mesh` as binary STL: 80-byte header, uint32 count, per triangle (polygons as
/// fans) a float normal, three float corners and a zero uint16.
void write_stl_binary(const std::string& path, const Mesh& mesh) {
  const auto pos = mesh.positions();
  std::vector<std::uint32_t> face;
  std::string body;
  std::uint32_t triangles = 0;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    mesh.face_vertices(f, face);
    for (std::size_t k = 1; k + 1 < face.size(); ++k, ++triangles) {
      const Eigen::Vector3f p[3] = {pos.col(face[0]).cast<float>(), pos.col(face[k]).cast<float>(),
                                    pos.col(face[k + 1]).cast<float>()};
      const Eigen::Vector3f n = (p[1] - p[0]).cross(p[2] - p[0]).normalized();
      for (int a = 0; a < 3; ++a) append(body, n[a]);
      for (const auto& q : p)
        for (int a = 0; a < 3; ++a) append(body, q[a]);
      append(body, std::uint16_t{0});
    }
  }
  std::string out(80, '\0');
  out.replace(0, 22, "ffdbench binary STL io");
  append(out, triangles);
  write_file(path, out + body);
}

/// Writes `mesh` to `path` in format `f`: ffdtool's writer, or the bench's binary one.
void write_format(const Format& f, const std::string& path, const Mesh& mesh) {
  const std::string name = f.name;
  if (f.ffdtool_writes) write_mesh(path, mesh);
  else if (name == "ply_binary") write_ply_binary(path, mesh);
  else write_stl_binary(path, mesh);
}

/// `path`'s bytes read with read(2) into buf[0, capacity); returns the bytes read.
/// \throw IoError if it cannot be read.
std::size_t read_file_bytes(const std::string& path, char* buf, std::size_t capacity) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw IoError(At{path}, std::strerror(errno));
  std::size_t done = 0;
  while (done < capacity) {
    const ssize_t got = ::read(fd, buf + done, capacity - done);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) break;
    done += static_cast<std::size_t>(got);
  }
  ::close(fd);
  return done;
}

/// The baselines for reading `path` (`bytes` long), medians over `repeats`: `copy_ms`,
/// read(2) into a buffer allocated and touched beforehand (the page-cache copy alone),
/// and `fresh_ms`, into a fresh anonymous mapping each time (plus the page faults a new
/// process such as ffdtool run pays; malloc may or may not hand out touched memory).
void read_baselines(const std::string& path, std::size_t bytes, int repeats, double& copy_ms, double& fresh_ms) {
  std::vector<char> buf(bytes + 1, 1);
  copy_ms = median_ms(repeats, [&] { read_file_bytes(path, buf.data(), buf.size()); });
  fresh_ms = median_ms(repeats, [&] {
    void* p = ::mmap(nullptr, bytes + 1, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) throw IoError(At{path}, "mmap: " + std::string(std::strerror(errno)));
    read_file_bytes(path, static_cast<char*>(p), bytes + 1);
    ::munmap(p, bytes + 1);
  });
}

/// The grid's file for format `f` in `dir`.
std::string grid_file(const TempFolder& dir, const Format& f, std::size_t vertices) {
  return dir.file("grid-" + std::to_string(vertices) + "-" + f.name + f.ext);
}

/// One files row: writes the grid in format `f` (timed when ffdtool writes it), then
/// times read_mesh and the read(2) baselines of the same file; medians over `repeats`.
/// `build_ms` (build_mesh_ms) is the part of read_ms common to all formats.
json file_row(const Format& f, const Mesh& mesh, const TempFolder& dir, int repeats, double build_ms) {
  const std::string path = grid_file(dir, f, mesh.num_vertices());
  WriteOptions options;
  options.encoding = is_binary(f) ? WriteOptions::Encoding::Binary : WriteOptions::Encoding::Ascii;
  const std::string written = f.ffdtool_writes ? path : dir.file(std::string("ffdtool-") + f.name + f.ext);
  const double write_ms = median_ms(repeats, [&] { write_mesh(written, mesh, options); });
  const double write_rate = mb_per_s(static_cast<double>(fs::file_size(written)), write_ms);
  if (!f.ffdtool_writes) write_format(f, path, mesh);
  const double bytes = static_cast<double>(fs::file_size(path));
  std::size_t read_vertices = 0;
  const double read_ms = median_ms(repeats, [&] { read_vertices = read_mesh(path).num_vertices(); });
  double bytes_ms = 0, fresh_ms = 0;
  read_baselines(path, static_cast<std::size_t>(bytes), repeats, bytes_ms, fresh_ms);
  json r = {{"format", f.name},
            {"vertices", mesh.num_vertices()},
            {"bytes", bytes},
            {"read_ms", read_ms},
            {"read_mb_per_s", mb_per_s(bytes, read_ms)},
            {"write_ms", write_ms},
            {"write_bytes", static_cast<double>(fs::file_size(written))},
            {"write_mb_per_s", write_rate},
            {"read_bytes_ms", bytes_ms},
            {"read_bytes_mb_per_s", mb_per_s(bytes, bytes_ms)},
            {"read_vs_page_cache", read_ms / bytes_ms},
            {"read_bytes_fresh_buffer_ms", fresh_ms},
            {"read_vs_fresh_buffer", read_ms / fresh_ms},
            {"build_mesh_ms", build_ms}};
  if (read_vertices != mesh.num_vertices()) r["vertices_read"] = read_vertices;
  return r;
}

/// The job script for ffdtool, written into `dir`; returns its path.
std::string write_job_script(const TempFolder& dir) {
  const json script = {
      {"version", 1},
      {"steps",
       {{{"op", "lattice"}, {"name", "l"}, {"cells", {kCells, kCells, kCells}}},
        {{"op", "move"},
         {"lattice", "l"},
         {"points", {{{"index", {kPoint, kPoint, kPoint}}, {"by", {kDelta[0], kDelta[1], kDelta[2]}}}}}}}}};
  const std::string path = dir.file("job.json");
  write_file(path, script.dump(2) + "\n");
  return path;
}

/// One ffdtool_run row: `ffdtool run` on the grid file of format `f`, one thread, output
/// in the same extension; median wall time and peak RSS over ctx.repeats (one warm-up),
/// against `io_ms` (in-process read of the input + write of the output, from the files rows).
json ffdtool_row(const Context& ctx, const Format& f, std::size_t vertices, const std::string& ffdtool,
                 const std::string& script, const TempFolder& dir, double io_ms) {
  const std::string out = dir.file(std::string("ffdtool-out-") + f.name + f.ext);
  const std::vector<std::string> argv = {ffdtool, "run", grid_file(dir, f, vertices), script, "-o", out,
                                         "--threads", "1", "--quiet"};
  const std::vector<ChildRun> runs = run_repeated(argv, dir, 1, ctx.repeats);
  if (!runs.front().ok) throw InputError("ffdtool run failed on " + argv[2] + ": " + last_line(runs.front().err));
  double ms = 0, peak = 0;
  child_medians(runs, ms, peak);
  json r = {{"format", f.name},
            {"vertices", vertices},
            {"output", output_format(f)},
            {"ms", ms},
            {"peak_bytes", peak},
            {"bytes_per_vertex", peak / vertices},
            {"read_plus_write_ms", io_ms},
            {"ms_vs_read_plus_write", ms / io_ms}};
  if (std::string(f.name) == "obj") {
    r["target_ms"] = 500;
    r["target_bytes_per_vertex"] = 200;
  }
  return r;
}

/// The lattice arguments of the peer's `job` mode after IN OUT.
std::vector<std::string> job_lattice_args() {
  std::vector<std::string> a;
  for (int i = 0; i < 3; ++i) a.push_back(std::to_string(kCells));
  for (int i = 0; i < 3; ++i) a.push_back(std::to_string(kBlenderPoint));
  for (double d : kDelta) a.push_back(json(d).dump());
  return a;
}

/// One blender_job row: the peer's `job` on the grid file of format `f` (output in the
/// same extension), median over the runs of the wall time, peak RSS and the peer's phases,
/// against ffdtool's wall time `ffdtool_ms` on the same file.
json blender_job_row(const Context& ctx, const Format& f, std::size_t vertices, const std::string& blender,
                     const TempFolder& dir, double ffdtool_ms) {
  json r = {{"format", f.name}, {"vertices", vertices}};
  if (blender.empty()) {
    r["blender"] = kNoBlender;
    return r;
  }
  std::vector<std::string> args = {"job", grid_file(dir, f, vertices), dir.file(std::string("blender-out-") + f.name + f.ext)};
  const std::vector<std::string> lattice = job_lattice_args();
  args.insert(args.end(), lattice.begin(), lattice.end());
  const json b = blender_medians(blender, args, dir, ctx.quick ? 1 : kBlenderRepeats,
                                 {"import_ms", "setup_ms", "modifier_ms", "export_ms", "total_ms"});
  r.update(b);
  if (!b.contains("blender_wall_ms")) return r;
  const double wall = b["blender_wall_ms"], peak = b["peak_bytes"];
  r["bytes_per_vertex"] = peak / vertices;
  r["ffdtool_ms"] = ffdtool_ms;
  r["ffdtool_speedup_wall"] = wall / ffdtool_ms;
  r["ffdtool_speedup_in_script"] = r["total_ms"].get<double>() / ffdtool_ms;
  if (std::string(f.name) == "obj") r["target_speedup_wall"] = 5;
  return r;
}

/// ffdtool's kernel: BSplineLattice::apply with positions and normals on every vertex of
/// `mesh`, one thread, the job's lattice on the box ffdtool run fits (aabb, padding 0.05);
/// median ms over `repeats`, and how many vertices the lattice evaluated (it skips cells
/// without a moved point). With `every_point`, all 27 movable points move (by kDelta
/// scaled by ±1 in a fixed pattern), so that every cell, hence every vertex, is evaluated,
/// as Blender's modifier evaluates them all whatever moved.
double ffdtool_kernel_ms(const Mesh& mesh, int repeats, bool every_point, std::size_t& evaluated) {
  omp_set_num_threads(1);
  const Eigen::Matrix3Xd pos = mesh.positions(), nrm = mesh.normals();
  BSplineLattice lattice(fit_aabb(pos, {}, 0.05), {kCells, kCells, kCells}, 3);
  const Eigen::Vector3d delta(kDelta[0], kDelta[1], kDelta[2]);
  for (std::size_t f = 0; f < lattice.num_points(); ++f) {
    const Index3 ijk = lattice.index(f);
    const bool job_point = ijk == Index3{kPoint, kPoint, kPoint};
    if (!lattice.movable(ijk) || (!every_point && !job_point)) continue;
    lattice.move_point(ijk, lattice.point(ijk) + ((ijk[0] + ijk[1] + ijk[2]) % 2 ? -0.5 : 1.0) * delta);
  }
  lattice.prepare();
  std::vector<std::uint32_t> ids(mesh.num_vertices());
  std::iota(ids.begin(), ids.end(), 0u);
  Eigen::Matrix3Xd out_pos(3, pos.cols()), out_nrm(3, pos.cols());
  WarpCounts counts;
  const double ms = median_ms(repeats, [&] {
    counts = {};
    lattice.apply(pos, nrm, ids, out_pos, out_nrm, counts);
  });
  omp_set_num_threads(omp_get_num_procs());
  evaluated = counts.evaluated;
  return ms;
}

/// The kernel row: ffdtool's kernel on `mesh` against the peer's `kernel` mode on the
/// same grid as OBJ (`obj_path`): Blender's evaluation with the Lattice modifier, and the
/// modifier alone (minus the evaluation without it).
json kernel_row(const Context& ctx, const Mesh& mesh, const std::string& obj_path, const std::string& blender,
                const TempFolder& dir) {
  std::size_t evaluated = 0, evaluated_all = 0;
  const double ms = ffdtool_kernel_ms(mesh, ctx.repeats, false, evaluated);
  const double all_ms = ffdtool_kernel_ms(mesh, ctx.repeats, true, evaluated_all);
  json r = {{"vertices", mesh.num_vertices()},         {"ffdtool_ms", ms},
            {"ffdtool_vertices_evaluated", evaluated}, {"ffdtool_every_point_ms", all_ms},
            {"ffdtool_every_point_vertices_evaluated", evaluated_all}};
  if (blender.empty()) {
    r["blender"] = kNoBlender;
    return r;
  }
  const std::vector<std::string> args = {"kernel", obj_path, std::to_string(std::max(1, ctx.repeats)),
                                         std::to_string(kCells), std::to_string(kBlenderPoint),
                                         std::to_string(kBlenderPoint), std::to_string(kBlenderPoint),
                                         json(kDelta[0]).dump(), json(kDelta[1]).dump(),
                                         json(kDelta[2]).dump()};
  const ChildRun run = run_measured(blender_argv(blender, args), dir.path.string());
  const json j = peer_json(run);
  if (!run.ok || !j.is_object()) {
    r["blender"] = blender_failure(run);
    return r;
  }
  r["blender"] = j.value("blender", "");
  r["blender_repeats"] = j.value("repeats", 0);
  for (const char* key : {"baseline_ms", "lattice_ms", "modifier_ms"}) r[std::string("blender_") + key] = j.value(key, 0.0);
  r["speedup_vs_blender_evaluation"] = j.value("lattice_ms", 0.0) / ms;
  r["speedup_vs_blender_modifier_only"] = j.value("modifier_ms", 0.0) / ms;
  r["every_point_speedup_vs_blender_evaluation"] = j.value("lattice_ms", 0.0) / all_ms;
  r["every_point_speedup_vs_blender_modifier_only"] = j.value("modifier_ms", 0.0) / all_ms;
  r["target_speedup"] = 10;
  return r;
}

/// Grid sides: n = 317 (100,489 vertices) and 1001 (1,002,001); quick: 142 (20,164).
std::vector<int> grid_sides(bool quick) { return quick ? std::vector<int>{142} : std::vector<int>{317, 1001}; }

}  // namespace

void bench_io(Context& ctx) {
  const std::string ffdtool = ffdtool_path(ctx.ffdtool);
  const std::string blender = blender_path(ctx.blender);
  if (blender.empty()) std::fprintf(stderr, "ffdbench: io: no blender on PATH (%s)\n", kNoBlender);
  const TempFolder dir("io");
  json files = json::array(), runs = json::array(), jobs = json::array();
  std::map<std::string, json> largest;  // format -> its files row at the largest size
  Mesh mesh;
  for (int n : grid_sides(ctx.quick)) {
    PolygonSoup soup = height_field(n);
    const double build_ms = build_mesh_ms(soup, ctx.repeats);
    mesh = build_mesh(std::move(soup), "grid");
    for (const Format& f : formats()) {
      std::fprintf(stderr, "ffdbench: io: %s, %zu vertices\n", f.name, mesh.num_vertices());
      files.push_back(file_row(f, mesh, dir, ctx.repeats, build_ms));
      largest[f.name] = files.back();
    }
  }
  const std::string script = write_job_script(dir);
  std::map<std::string, double> ffdtool_ms;
  for (const Format& f : formats()) {
    std::fprintf(stderr, "ffdbench: io: ffdtool run, %s\n", f.name);
    const double io_ms = largest[f.name]["read_ms"].get<double>() +
                         largest[output_format(f)]["write_ms"].get<double>();
    runs.push_back(ffdtool_row(ctx, f, mesh.num_vertices(), ffdtool, script, dir, io_ms));
    ffdtool_ms[f.name] = runs.back()["ms"].get<double>();
  }
  for (const Format& f : formats()) {
    if (!f.blender_reads) continue;
    std::fprintf(stderr, "ffdbench: io: blender job, %s\n", f.name);
    jobs.push_back(blender_job_row(ctx, f, mesh.num_vertices(), blender, dir, ffdtool_ms[f.name]));
  }
  std::fprintf(stderr, "ffdbench: io: kernel\n");
  const json kernel = kernel_row(ctx, mesh, grid_file(dir, formats().front(), mesh.num_vertices()), blender, dir);
  const json gltf = gltf_coding_rows(mesh, dir, ctx.repeats);
  ctx.out["io"] = {{"files", files},      {"ffdtool_run", runs}, {"blender_job", jobs},
                   {"kernel", json::array({kernel})}, {"gltf", gltf}};
}

}  // namespace ffd::bench
