// The users suite: what a command-line user pays, as whole `ffdtool run` child processes
// (wall time and peak RSS: child_run.h; the step times from the run's --stats), with the
// peer measured in the same run on the same files. Medians over ctx.repeats runs after a
// warm-up run (which also brings the input into the page cache).
// - sphere_job: a 1M-vertex UV sphere OBJ as a double-precision exporter writes it (17
//   significant digits, no normals: ~90 MB), a cubic B-spline lattice of 4^3 cells on the AABB
//   (padding 0.05) with its centre point moved, 1 and 2 threads: process wall time, peak
//   RSS per vertex, the stats' read, move step and write; against Blender doing the same
//   job with one thread (blender_peer.py `job`, as the io suite runs it).
// - sphere_move_step: the 1-thread move step against Blender's evaluation of the same file
//   with its Lattice modifier, and against the modifier alone (blender_peer.py `kernel`).
// - cloud_move_step: 1M points uniform in [0,1]^3 as binary PLY (doubles, no normals), a
//   lattice on that box with one point moved by 0.1 on each axis: cubic B-spline 4^3 cells
//   (centre point [2,2,2]) and Bernstein degree 3 ([1,1,1]), one thread; against PyGeM's
//   FFD on the same points (scripts/bench_users_pygem.py, when PYGEM_SOURCE names PyGeM's
//   source tree), with the largest |ffdtool - PyGeM| of ffdtool's output read back.
// - octree_first_moves: an octree lattice (OBB, 5 levels, 2 Catmull-Clark steps) on the
//   shared meshes and a generated 39k-vertex blob; one run moves the lattice point nearest
//   a mesh vertex at each level 0..5 in turn: each move step's ms.
// - bcm_detail_frame: a generated 33k-vertex head, a k = 3 bcm editor with detail on a
//   ~30k-vertex support around the nose, then 1 or 1001 transform frames of its handle:
//   per frame = (wall(1001 frames) - wall(1 frame)) / 1000, default threads (the target)
//   and one.
// --quick: a 100k-vertex sphere, 100k points, 101 frames, one run each.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>

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

// The sphere job: 4^3 cells, the centre point moved by kUsersDelta (the io suite's delta).
// Blender numbers a lattice's points from 0, ffdtool a cubic one from -1 (the phantom
// layer), so ffdtool's centre point 2 is Blender's 3.
constexpr int kUsersCells = 4;
constexpr int kCentre = 2;
constexpr int kBlenderCentre = kCentre + 1;
constexpr double kUsersDelta[3] = {0.1, 0.2, 0.3};
constexpr int kUsersBlenderRepeats = 3;

/// `ffdtool run`s of one script: their stats, and the medians of wall time and peak RSS.
struct ToolRuns {
  std::vector<json> stats;
  double ms = 0, peak_bytes = 0, minor_faults = 0;  // medians over the runs
  /// The median over the runs of the stats' number that `get` picks.
  double stat(const std::function<double(const json&)>& get) const {
    std::vector<double> values;
    for (const json& s : stats) values.push_back(get(s));
    return median(values);
  }
  /// The median of step k's "ms".
  double step_ms(std::size_t k) const {
    return stat([k](const json& s) { return s["steps"][k]["ms"].get<double>(); });
  }
};

/// `ffdtool run MESH SCRIPT -o OUT --stats ... --quiet`, with --threads `threads` (0: the
/// default, every core), `repeats` times after one warm-up run.
/// \throw InputError if a run fails.
ToolRuns run_ffdtool(const std::string& ffdtool, const TempFolder& dir, const std::string& mesh,
                     const std::string& script, const std::string& out, int threads, int repeats) {
  const std::string stats = dir.file("stats.json");
  std::vector<std::string> argv = {ffdtool, "run", mesh, script, "-o", out, "--stats", stats, "--quiet"};
  if (threads > 0) argv.insert(argv.end(), {"--threads", std::to_string(threads)});
  ToolRuns r;
  std::vector<ChildRun> runs;
  for (int i = 0; i <= std::max(1, repeats); ++i) {
    ChildRun run = run_measured(argv, dir.path.string());
    if (!run.ok) throw InputError("ffdtool run failed on " + mesh + " with " + script + ": " + last_line(run.err));
    if (i == 0) continue;
    std::ifstream is(stats);
    r.stats.push_back(json::parse(is));
    runs.push_back(std::move(run));
  }
  child_medians(runs, r.ms, r.peak_bytes, &r.minor_faults);
  return r;
}

/// Writes `steps` as the ffdtool script NAME.json in `dir`; returns its path.
std::string write_script(const TempFolder& dir, const std::string& name, const json& steps) {
  const std::string path = dir.file(name + ".json");
  write_file(path, json{{"version", 1}, {"steps", steps}}.dump(1) + "\n");
  return path;
}

/// A target's report: `what` -> `limit`, and whether `value` met it.
json target(const char* what, double limit, bool met) { return {{what, limit}, {"met", met}}; }

// ---------------------------------------------------------------------------------------
// sphere_job, sphere_move_step

/// Writes the UV sphere `soup` as a double-precision exporter does: v lines with 17
/// significant digits and `f a b c` faces, no normals (the file: a scan or a CAD
/// export often has none, and then a lattice job needs none). ffdtool's own writer prints
/// the shortest round-trip text instead, which is not what a user's file from elsewhere
/// looks like.
void write_sphere_obj(const std::string& path, const PolygonSoup& soup) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw IoError(At{path}, "cannot create");
  std::vector<char> buffer(1 << 20);
  std::setvbuf(f, buffer.data(), _IOFBF, buffer.size());
  for (const Eigen::Vector3d& p : soup.positions) std::fprintf(f, "v %.17g %.17g %.17g\n", p[0], p[1], p[2]);
  for (std::size_t e = 0; e < soup.elements.size(); ++e) {
    std::fputc('f', f);
    const std::uint32_t* v = soup.elements.vertices(e);
    for (std::uint32_t k = 0; k < soup.elements.degree(e); ++k) std::fprintf(f, " %u", v[k] + 1);
    std::fputc('\n', f);
  }
  const bool ok = std::fflush(f) == 0 && !std::ferror(f);
  if (std::fclose(f) != 0 || !ok) throw IoError(At{path}, "cannot write");
}

/// The sphere job's script: the lattice on the padded AABB, its centre point moved.
json sphere_steps() {
  return json::array({{{"op", "lattice"}, {"name", "l"}, {"cells", {kUsersCells, kUsersCells, kUsersCells}},
                       {"box", {{"fit", "aabb"}, {"padding", 0.05}}}},
                      {{"op", "move"}, {"lattice", "l"},
                       {"points", {{{"index", {kCentre, kCentre, kCentre}}, {"by", {kUsersDelta[0], kUsersDelta[1], kUsersDelta[2]}}}}}}});
}

/// The peer's lattice arguments: cells or point index three times, then the delta.
std::vector<std::string> blender_lattice_args(int cells_or_index, int point, bool per_axis_cells) {
  std::vector<std::string> a;
  for (int i = 0; i < (per_axis_cells ? 3 : 1); ++i) a.push_back(std::to_string(cells_or_index));
  for (int i = 0; i < 3; ++i) a.push_back(std::to_string(point));
  for (double d : kUsersDelta) a.push_back(json(d).dump());
  return a;
}

/// Blender's `job` (import, lattice, export; one thread) on the sphere OBJ, to OBJ.
json blender_job(const Context& ctx, const std::string& blender, const TempFolder& dir, const std::string& obj) {
  if (blender.empty()) return {{"blender", kNoBlender}};
  std::vector<std::string> args = {"job", obj, dir.file("blender-out.obj")};
  const std::vector<std::string> lattice = blender_lattice_args(kUsersCells, kBlenderCentre, true);
  args.insert(args.end(), lattice.begin(), lattice.end());
  return blender_medians(blender, args, dir, ctx.quick ? 1 : kUsersBlenderRepeats,
                         {"import_ms", "setup_ms", "modifier_ms", "export_ms", "total_ms"});
}

/// One sphere_job row: ffdtool's figures with `threads`, beside Blender's job `peer`.
json sphere_job_row(const ToolRuns& r, int threads, std::size_t vertices, double file_bytes, const json& peer) {
  const double read = r.stat([](const json& s) { return s["input"]["read_ms"].get<double>(); });
  const double write = r.stat([](const json& s) { return s["output"]["write_ms"].get<double>(); });
  const double steps = r.stat([](const json& s) { return s["totals"]["steps_ms"].get<double>(); });
  json row = {{"threads", threads},
              {"vertices", vertices},
              {"file_bytes", file_bytes},
              {"runs", r.stats.size()},
              {"process_ms", r.ms},
              {"peak_bytes", r.peak_bytes},
              {"peak_bytes_per_vertex", r.peak_bytes / static_cast<double>(vertices)},
              {"minor_faults", r.minor_faults},
              {"read_ms", read},
              {"lattice_step_ms", r.step_ms(0)},
              {"move_step_ms", r.step_ms(1)},
              {"write_ms", write},
              // What the stats do not cover: process start and exit, script parsing, the
              // stats file itself.
              {"process_minus_stats_ms", r.ms - read - steps - write},
              {"blender", peer}};
  if (peer.contains("blender_wall_ms")) {
    const double ratio = peer["blender_wall_ms"].get<double>() / r.ms;
    row["blender_wall_over_ffdtool_wall"] = ratio;
    row["target"] = target("blender_wall_over_ffdtool_wall_at_least", 10, ratio >= 10);
  }
  return row;
}

/// The sphere_move_step row: the 1-thread move step against Blender's `kernel` on the
/// same OBJ (its evaluation with the Lattice modifier, and the modifier alone).
json sphere_move_row(const Context& ctx, const std::string& blender, const TempFolder& dir, const std::string& obj,
                     std::size_t vertices, double move_ms) {
  json row = {{"vertices", vertices}, {"threads", 1}, {"ffdtool_move_step_ms", move_ms}};
  if (blender.empty()) {
    row["blender"] = kNoBlender;
    return row;
  }
  std::vector<std::string> args = {"kernel", obj, std::to_string(std::max(1, ctx.repeats))};
  const std::vector<std::string> lattice = blender_lattice_args(kUsersCells, kBlenderCentre, false);
  args.insert(args.end(), lattice.begin(), lattice.end());
  const json peer = blender_medians(blender, args, dir, 1, {"baseline_ms", "lattice_ms", "modifier_ms"});
  row["blender"] = peer;
  if (!peer.contains("modifier_ms")) return row;
  const double evaluation = peer["lattice_ms"].get<double>() / move_ms;
  const double modifier = peer["modifier_ms"].get<double>() / move_ms;
  row["blender_evaluation_over_move_step"] = evaluation;
  row["blender_modifier_over_move_step"] = modifier;
  // The modifier alone is the difference of two evaluations of the whole mesh; when it is
  // not above zero it is lost in their noise and says nothing.
  if (modifier <= 0) row["note"] = "Blender's evaluation was not slower with the modifier than without: its cost is within the noise";
  // The target is the speed issue's: 10x Blender's evaluation of the mesh with its Lattice
  // modifier (the issue measured 384 ms for it; `lattice_ms` here). The modifier alone is
  // reported beside it, not held to 10x: our move step also re-evaluates the normals.
  row["target"] = target("blender_evaluation_over_move_step_at_least", 10, evaluation >= 10);
  return row;
}

/// The sphere rows: writes the sphere, runs ffdtool with 1 and 2 threads and Blender.
void sphere_rows(const Context& ctx, const std::string& ffdtool, const std::string& blender, const TempFolder& dir,
                 json& out) {
  // 1265 x 791 gives 999,352 vertices (the python suite's sphere); quick: 99,602.
  const int slices = ctx.quick ? 400 : 1265, stacks = ctx.quick ? 250 : 791;
  const Eigen::Vector3d centre = Eigen::Vector3d::Constant(0.5);
  const std::string obj = dir.file("sphere.obj");
  std::size_t vertices = 0;
  {
    const PolygonSoup soup = uv_sphere(slices, stacks, centre, 0.4);
    vertices = soup.positions.size();
    write_sphere_obj(obj, soup);
  }
  const double bytes = static_cast<double>(fs::file_size(obj));
  std::fprintf(stderr, "ffdbench: users: sphere job, %zu vertices, %.0f MB\n", vertices, bytes / 1e6);
  const std::string script = write_script(dir, "sphere", sphere_steps());
  const ToolRuns one = run_ffdtool(ffdtool, dir, obj, script, dir.file("out.obj"), 1, ctx.repeats);
  const ToolRuns two = run_ffdtool(ffdtool, dir, obj, script, dir.file("out.obj"), 2, ctx.repeats);
  std::fprintf(stderr, "ffdbench: users: sphere job in Blender\n");
  const json peer = blender_job(ctx, blender, dir, obj);
  out["sphere_job"] = {sphere_job_row(one, 1, vertices, bytes, peer), sphere_job_row(two, 2, vertices, bytes, peer)};
  std::fprintf(stderr, "ffdbench: users: Lattice modifier in Blender\n");
  out["sphere_move_step"] = json::array({sphere_move_row(ctx, blender, dir, obj, vertices, one.step_ms(1))});
}

// ---------------------------------------------------------------------------------------
// cloud_move_step

/// A lattice of the cloud rows: cubic B-spline 4^3 cells or Bernstein degree 3 on [0,1]^3,
/// the point a user would move (the B-spline's centre; the Bernstein point PyGeM's
/// [1,1,1] is) by 0.1 on each axis.
struct CloudLattice {
  const char* basis;
  int cells, point;
};

json cloud_steps(const CloudLattice& l) {
  json lattice = {{"op", "lattice"}, {"name", "l"}, {"basis", l.basis}, {"cells", {l.cells, l.cells, l.cells}},
                  {"box", {{"min", {0, 0, 0}}, {"max", {1, 1, 1}}}}};
  if (std::string(l.basis) == "bspline") lattice["degree"] = 3;
  return json::array({lattice, {{"op", "move"}, {"lattice", "l"},
                                {"points", {{{"index", {l.point, l.point, l.point}}, {"by", {0.1, 0.1, 0.1}}}}}}});
}

/// `n` points uniform in [0,1]^3 (the python suite's seed), as the binary PLY ffdtool reads
/// (build_mesh's writer: doubles, no normals) and as raw float64 for PyGeM.
void write_cloud(const TempFolder& dir, std::size_t n) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  PolygonSoup soup;
  soup.positions.resize(n);
  for (Eigen::Vector3d& p : soup.positions) p = {u(rng), u(rng), u(rng)};
  std::ofstream raw(dir.file("cloud.f64"), std::ios::binary);
  for (const Eigen::Vector3d& p : soup.positions) raw.write(reinterpret_cast<const char*>(p.data()), 3 * sizeof(double));
  if (!raw.flush()) throw IoError(At{dir.file("cloud.f64")}, "cannot write");
  WriteOptions binary;
  binary.encoding = WriteOptions::Encoding::Binary;
  write_mesh(dir.file("cloud.ply"), build_mesh(std::move(soup), "cloud"), binary);
}

/// PyGeM's FFD on the cloud (scripts/bench_users_pygem.py) when PYGEM_SOURCE is set: its
/// JSON ("points", "ms"; its output in pygem.f64), or {"pygem": why not}.
json pygem_side(const Context& ctx, const TempFolder& dir) {
  const char* source = std::getenv("PYGEM_SOURCE");
  if (!source || !*source) return {{"pygem", "PYGEM_SOURCE not set"}};
  const std::vector<std::string> argv = {"/usr/bin/python3", std::string(FFD_SOURCE_ROOT) + "/scripts/bench_users_pygem.py",
                                         "--points", dir.file("cloud.f64"), "--out", dir.file("pygem.f64"),
                                         "--pygem", source, "--repeats", std::to_string(std::max(1, ctx.repeats / 2))};
  const ChildRun run = run_measured(argv, dir.path.string());
  if (!run.ok) return {{"pygem", "failed: " + last_line(run.err)}};
  return json::parse(run.out);
}

/// The largest |ffdtool - PyGeM| over the coordinates of ffdtool's output `ply` and
/// PyGeM's pygem.f64 (the same points in the same order; NaN if either has one), and how
/// many coordinates differ at all. \throw InputError on a size mismatch.
double max_difference(const TempFolder& dir, const std::string& ply, std::size_t& differing) {
  const Mesh mesh = read_mesh(ply);
  const auto pos = mesh.positions();
  std::vector<double> theirs(static_cast<std::size_t>(pos.size()));
  std::ifstream is(dir.file("pygem.f64"), std::ios::binary);
  is.read(reinterpret_cast<char*>(theirs.data()), static_cast<std::streamsize>(theirs.size() * sizeof(double)));
  if (!is || is.peek() != std::char_traits<char>::eof()) throw InputError("pygem.f64: not the output's size");
  double worst = 0;
  differing = 0;
  for (Eigen::Index i = 0; i < pos.size(); ++i) {
    const double d = std::abs(pos.data()[i] - theirs[i]);
    if (std::isnan(d) || d > worst) worst = d;  // a NaN sticks: nothing compares above it
    differing += d != 0;
  }
  return worst;
}

/// One cloud row; `pygem` is pygem_side's JSON, the comparison made on the Bernstein row
/// (PyGeM's lattice is a Bernstein one: a B-spline's output differs by design).
json cloud_row(const std::string& ffdtool, const TempFolder& dir, const CloudLattice& l, std::size_t points,
               int repeats, const json& pygem) {
  const bool bspline = std::string(l.basis) == "bspline";
  const std::string out = dir.file(std::string("cloud-") + l.basis + ".ply");
  std::fprintf(stderr, "ffdbench: users: cloud, %s\n", l.basis);
  const ToolRuns r = run_ffdtool(ffdtool, dir, dir.file("cloud.ply"), write_script(dir, l.basis, cloud_steps(l)), out, 1,
                                 repeats);
  const double move = r.step_ms(1);
  json row = {{"basis", l.basis}, {"cells", l.cells}, {"point", {l.point, l.point, l.point}}, {"points", points},
              {"threads", 1}, {"move_step_ms", move}, {"process_ms", r.ms}, {"peak_bytes", r.peak_bytes}};
  if (!pygem.contains("ms")) {
    row["pygem"] = pygem["pygem"];
  } else {
    row["pygem_ms"] = pygem["ms"];
    row["pygem_over_move_step"] = pygem["ms"].get<double>() / move;
    if (!bspline) {
      std::size_t differing = 0;
      row["max_abs_difference_vs_pygem"] = max_difference(dir, out, differing);
      row["coordinates_differing_from_pygem"] = differing;
    }
  }
  if (bspline) row["target"] = target("move_step_ms_at_most", 25, move <= 25);
  else if (row.contains("pygem_over_move_step"))
    row["target"] = target("pygem_over_move_step_at_least", 20, row["pygem_over_move_step"].get<double>() >= 20);
  return row;
}

json cloud_rows(const Context& ctx, const std::string& ffdtool, const TempFolder& dir) {
  const std::size_t n = ctx.quick ? 100'000 : 1'000'000;
  write_cloud(dir, n);
  std::fprintf(stderr, "ffdbench: users: PyGeM on %zu points\n", n);
  const json pygem = pygem_side(ctx, dir);
  json rows = json::array();
  for (const CloudLattice& l : {CloudLattice{"bspline", 4, 2}, CloudLattice{"bernstein", 3, 1}})
    rows.push_back(cloud_row(ffdtool, dir, l, n, ctx.repeats, pygem));
  return rows;
}

// ---------------------------------------------------------------------------------------
// Generated closed meshes: octree_first_moves' blob, bcm_detail_frame's head

/// A Gaussian bump on a unit sphere: `height` (fraction of the radius) at `dir`, `width` in
/// chord length.
struct Bump {
  Eigen::Vector3d dir;
  double height, width;
};

/// A closed UV sphere of `slices` x `stacks` scaled to `radii` and pushed out along its
/// normals by `bumps`: a deterministic organic mesh of a chosen size.
PolygonSoup bumpy_sphere(int slices, int stacks, const Eigen::Vector3d& radii, const std::vector<Bump>& bumps) {
  PolygonSoup soup = uv_sphere(slices, stacks, Eigen::Vector3d::Zero(), 1.0);
  for (Eigen::Vector3d& p : soup.positions) {
    double r = 1;
    for (const Bump& b : bumps) r += b.height * std::exp(-(p - b.dir.normalized()).squaredNorm() / (b.width * b.width));
    p = r * radii.cwiseProduct(p);
  }
  return soup;
}

/// Writes `soup` as OFF into `dir`; returns the path.
std::string write_off(const TempFolder& dir, const std::string& name, PolygonSoup soup) {
  const std::string path = dir.file(name + ".off");
  write_mesh(path, build_mesh(std::move(soup), path));
  return path;
}

/// The vertex farthest from the centroid of `mesh` (a blob's most prominent tip).
Eigen::Vector3d apex(const Mesh& mesh) {
  const auto pos = mesh.positions();
  const Eigen::Vector3d centroid = pos.rowwise().mean();
  Eigen::Index best = 0;
  (pos.colwise() - centroid).colwise().squaredNorm().maxCoeff(&best);
  return pos.col(best);
}

// ---------------------------------------------------------------------------------------
// octree_first_moves

constexpr int kOctreeLevels = 5;

/// The octree script on `mesh`: the lattice, then at each level 0..kOctreeLevels a move of
/// the level's point nearest the mesh's apex by 1% of the box's diagonal (along (1,1,1)).
json octree_steps(const Mesh& mesh) {
  const auto pos = mesh.positions();
  const double diagonal = (pos.rowwise().maxCoeff() - pos.rowwise().minCoeff()).norm();
  const double d = 0.01 * diagonal / std::sqrt(3.0);
  const Eigen::Vector3d at = apex(mesh);
  json steps = json::array({{{"op", "lattice"}, {"name", "o"}, {"basis", "octree"},
                             {"box", {{"fit", "obb"}, {"padding", 0.02}}}, {"levels", kOctreeLevels}, {"cc_steps", 2}}});
  for (int level = 0; level <= kOctreeLevels; ++level)
    steps.push_back({{"op", "move"}, {"lattice", "o"}, {"level", level},
                     {"select", {{"near", {at[0], at[1], at[2]}}}}, {"transform", {{"translate", {d, d, d}}}}});
  return steps;
}

json octree_row(const Context& ctx, const std::string& ffdtool, const TempFolder& dir, const std::string& name,
                const std::string& path) {
  if (!fs::exists(path)) return {{"mesh", name}, {"missing", path}};
  const Mesh mesh = read_mesh(path);
  std::fprintf(stderr, "ffdbench: users: octree, %s\n", name.c_str());
  const std::string script = write_script(dir, "octree", octree_steps(mesh));
  const ToolRuns r = run_ffdtool(ffdtool, dir, path, script, dir.file("octree-out.off"), 1, ctx.repeats);
  json moves = json::array(), work = json::array();
  double total = 0, worst = 0;
  for (int level = 0; level <= kOctreeLevels; ++level) {
    const double ms = r.step_ms(1 + level);
    moves.push_back(ms);
    total += ms;
    worst = std::max(worst, ms);
    // What each move did (the same in every run): where its time goes.
    const json& step = r.stats.front()["steps"][1 + level];
    json w = json::object();
    for (const char* key : {"vertices_moved", "cells_subdivided", "cells_relocated"})
      if (step.contains(key)) w[key] = step[key];
    work.push_back(w);
  }
  return {{"mesh", name},
          {"vertices", mesh.num_vertices()},
          {"threads", 1},
          {"process_ms", r.ms},
          {"peak_bytes", r.peak_bytes},
          {"minor_faults", r.minor_faults},
          {"lattice_step_ms", r.step_ms(0)},
          {"move_ms_by_level", moves},
          {"move_work_by_level", work},
          {"moves_total_ms", total},
          {"target", {{"move_ms_at_most", 10}, {"total_ms_at_most", 60}, {"met", worst <= 10 && total <= 60}}}};
}

json octree_rows(const Context& ctx, const std::string& ffdtool, const TempFolder& dir) {
  // 250 x 157 gives 39,002 vertices: an elongated blob (distinct principal axes, so the
  // OBB is well defined) with a few bumps.
  const std::string blob = write_off(dir, "blob39k", bumpy_sphere(250, 157, {1.0, 0.6, 0.4},
                                                                  {{{1, 0.3, 0.2}, 0.3, 0.4}, {{-0.5, 1, 0}, 0.2, 0.5},
                                                                   {{0, -0.4, 1}, 0.25, 0.3}}));
  json rows = json::array();
  for (const char* name : {"bunny00.off", "armadillo.off", "refined_elephant.off"})
    rows.push_back(octree_row(ctx, ffdtool, dir, name, ctx.meshes + "/" + name));
  rows.push_back(octree_row(ctx, ffdtool, dir, "blob39k.off (generated)", blob));
  return rows;
}

// ---------------------------------------------------------------------------------------
// bcm_detail_frame

constexpr std::size_t kSupport = 30'000, kHandle = 300;

/// The radius of the sphere around `centre` holding the `count` vertices of `mesh` nearest
/// it (halfway to the next one, so rounding cannot drop one).
double radius_holding(const Mesh& mesh, const Eigen::Vector3d& centre, std::size_t count) {
  const auto pos = mesh.positions();
  std::vector<double> d(mesh.num_vertices());
  for (std::size_t v = 0; v < d.size(); ++v) d[v] = (pos.col(static_cast<Eigen::Index>(v)) - centre).norm();
  std::sort(d.begin(), d.end());
  count = std::min(count, d.size() - 1);
  return 0.5 * (d[count - 1] + d[count]);
}

/// The bcm script on `head`: an editor whose support is the sphere around the nose tip
/// holding kSupport vertices, its handle the one holding kHandle; then `frames` poses of
/// the handle in one transform step (the nose pulled out and turned a little further each
/// frame).
json bcm_steps(const Mesh& head, int frames) {
  const Eigen::Vector3d tip = apex(head);
  const json centre = {tip[0], tip[1], tip[2]};
  json poses = json::array();
  for (int i = 1; i <= frames; ++i) {
    const double s = double(i) / frames;
    poses.push_back({{"translate", {0, 0.15 * s, 0.05 * s}}, {"rotate", {{"axis", {1, 0, 0}}, {"degrees", 10 * s}}}});
  }
  return json::array(
      {{{"op", "bcm"}, {"name", "head"},
        {"support", {{"sphere", {{"center", centre}, {"radius", radius_holding(head, tip, kSupport)}}}}},
        {"handles", {{{"name", "nose"}, {"select", {{"sphere", {{"center", centre}, {"radius", radius_holding(head, tip, kHandle)}}}}}}}},
        {"k", 3}, {"continuity", {{"outer", 2}, {"inner", 2}}}, {"detail", true}},
       {{"op", "transform"}, {"editor", "head"}, {"handle", "nose"}, {"frames", poses}}});
}

/// One bcm_detail_frame row with `threads` (0: default): runs of 1 and `frames` frames.
json bcm_row(const Context& ctx, const std::string& ffdtool, const TempFolder& dir, const std::string& head_path,
             const Mesh& head, int frames, int threads) {
  std::fprintf(stderr, "ffdbench: users: bcm frames, threads %s\n", threads ? std::to_string(threads).c_str() : "default");
  const std::string one_script = write_script(dir, "bcm1", bcm_steps(head, 1));
  const std::string many_script = write_script(dir, "bcm" + std::to_string(frames), bcm_steps(head, frames));
  const ToolRuns one = run_ffdtool(ffdtool, dir, head_path, one_script, dir.file("head-out.off"), threads, ctx.repeats);
  const ToolRuns many = run_ffdtool(ffdtool, dir, head_path, many_script, dir.file("head-out.off"), threads, ctx.repeats);
  const double per_frame = (many.ms - one.ms) / (frames - 1);
  const json& setup = many.stats.front()["steps"][0];
  json row = {{"threads", threads ? json(threads) : json("default")},
              {"vertices", head.num_vertices()},
              {"support_vertices", setup.value("support_vertices", 0)},
              {"handle_vertices", setup.value("handle_vertices", 0)},
              {"frames", frames},
              {"wall_1_frame_ms", one.ms},
              {"wall_frames_ms", many.ms},
              {"minor_faults_frames_run", many.minor_faults},
              {"per_frame_ms", per_frame},
              // The setup twice: its spread between the two runs is the per-frame figure's noise.
              {"bcm_step_ms", many.step_ms(0)},
              {"bcm_step_ms_1_frame_run", one.step_ms(0)},
              {"transform_step_ms", many.step_ms(1)},
              {"stats_frame_ms", many.stat([](const json& s) { return s["steps"][1].value("frame_ms", 0.0); })}};
  // The target is for default threads; one thread is reported beside it.
  if (threads == 0) row["target"] = target("per_frame_ms_at_most", 0.3, per_frame <= 0.3);
  return row;
}

json bcm_rows(const Context& ctx, const std::string& ffdtool, const TempFolder& dir) {
  // 230 x 144 gives 32,892 vertices: a head-sized ellipsoid (z up, facing +y) with a nose
  // (the apex the support is centred on), ears and a chin.
  const std::string path = write_off(dir, "head33k", bumpy_sphere(230, 144, {0.8, 0.9, 1.0},
                                                                   {{{0, 1, -0.1}, 0.25, 0.25}, {{1, 0, 0}, 0.12, 0.2},
                                                                    {{-1, 0, 0}, 0.12, 0.2}, {{0, 0.6, -0.8}, 0.1, 0.3}}));
  const Mesh head = read_mesh(path);
  const int frames = ctx.quick ? 101 : 1001;
  return json::array({bcm_row(ctx, ffdtool, dir, path, head, frames, 0), bcm_row(ctx, ffdtool, dir, path, head, frames, 1)});
}

}  // namespace

void bench_users(Context& ctx) {
  const std::string ffdtool = ffdtool_path(ctx.ffdtool);
  const std::string blender = blender_path(ctx.blender);
  if (blender.empty()) std::fprintf(stderr, "ffdbench: users: no blender on PATH (%s)\n", kNoBlender);
  const TempFolder dir("users");
  json out = json::object();
  sphere_rows(ctx, ffdtool, blender, dir, out);
  out["cloud_move_step"] = cloud_rows(ctx, ffdtool, dir);
  out["octree_first_moves"] = octree_rows(ctx, ffdtool, dir);
  out["bcm_detail_frame"] = bcm_rows(ctx, ffdtool, dir);
  ctx.out["users"] = out;
}

}  // namespace ffd::bench
