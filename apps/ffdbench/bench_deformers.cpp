// The deformers suite: what the scattered-point and cage deformers cost a user, measured
// as `ffdtool run` on generated files (default threads), from the run's own stats: the
// creating step's ms (set-up: the RBF's factorization, the cage's binding), the move
// step's ms (evaluation: every point re-evaluated, positions and, where the mesh has
// them, normals), the whole process and its peak memory.
// - rbf: PyGeM's sizes; points uniform in [0,1]^3 (binary PLY), control points uniform,
//   targets moved by up to 0.02. 1k x 100k gaussian (radius 0.1, about the spacing) and
//   thin-plate (radius 0.5, k 2); 5k x 1M, the same kernels (gaussian radius 0.06);
//   Wendland C2 10k x 1M at radius 0.106 (about 50 control points within it). PyGeM on
//   the same 1k x 100k cases: scripts/pygem_rbf_timing.py (PyGeM's source, Debian's numpy).
// - idw: 1k x 100k, power 2.
// - cage: a 100k-vertex UV sphere (radius 0.4), and the 100k-point cloud, in UV-sphere
//   cages of 200 and 2,000 triangles (radius 1): binding, a pose of one vertex from rest, then a pose of every
//   cage vertex (from a posed cage's file); against a 4^3-cell cubic B-spline move of its centre
//   point on the same mesh in the same run.
// --quick: 10x fewer points, the smaller control sets and cage.
#include <cstdio>
#include <fstream>
#include <random>
#include <tuple>

#include "bench.h"
#include "child_run.h"
#include "common/errors.h"
#include "mesh/build_mesh.h"
#include "mesh/mesh_io.h"

namespace ffd::bench {
namespace {

using json = nlohmann::ordered_json;

/// `count` points uniform in [0,1]^3 (seeded), moved by up to `jitter` when given.
std::vector<Eigen::Vector3d> random_points(std::size_t count, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Eigen::Vector3d> out(count);
  for (Eigen::Vector3d& p : out) p = {u(rng), u(rng), u(rng)};
  return out;
}

void write_points(const std::string& path, const std::vector<Eigen::Vector3d>& points) {
  std::ofstream os(path);
  char line[96];
  for (const Eigen::Vector3d& p : points) {
    std::snprintf(line, sizeof line, "%.17g %.17g %.17g\n", p[0], p[1], p[2]);
    os << line;
  }
}

/// Control points x.txt and their targets y.txt (moved by up to 0.02), named by count.
void write_control(const TempFolder& dir, std::size_t count) {
  std::vector<Eigen::Vector3d> x = random_points(count, 11 + static_cast<unsigned>(count)), y = x;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-0.02, 0.02);
  for (Eigen::Vector3d& p : y) p += Eigen::Vector3d(u(rng), u(rng), u(rng));
  write_points(dir.file("x" + std::to_string(count) + ".txt"), x);
  write_points(dir.file("y" + std::to_string(count) + ".txt"), y);
}

void write_binary(const std::string& path, PolygonSoup soup) {
  WriteOptions binary;
  binary.encoding = WriteOptions::Encoding::Binary;
  write_mesh(path, build_mesh(std::move(soup), path), binary);
}

/// A cage of `slices` x `stacks` around [0,1]^3's centre, and the same cage posed.
std::size_t write_cage(const TempFolder& dir, const std::string& name, int slices, int stacks) {
  PolygonSoup cage = uv_sphere(slices, stacks, Eigen::Vector3d::Constant(0.5), 1.0);
  const std::size_t triangles = cage.elements.size();
  std::vector<Eigen::Vector3d> posed = cage.positions;
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  for (Eigen::Vector3d& p : posed) p += Eigen::Vector3d(u(rng), u(rng), u(rng));
  write_mesh(dir.file(name + ".obj"), build_mesh(std::move(cage), name));
  write_points(dir.file(name + "_posed.txt"), posed);
  return triangles;
}

/// Runs `steps` on `mesh`; the creating step's and each later step's ms from the stats.
json run_steps(const std::string& ffdtool, const TempFolder& dir, const std::string& mesh, const json& steps) {
  const std::string script = dir.file("script.json"), stats = dir.file("stats.json");
  std::ofstream(script) << json{{"version", 1}, {"steps", steps}}.dump(2) << "\n";
  const std::vector<std::string> argv = {ffdtool, "run", mesh, script, "-o", dir.file("out.ply"), "--stats", stats, "--quiet"};
  const ChildRun run = run_measured(argv, dir.path.string());
  if (!run.ok) throw InputError("ffdtool run failed on " + mesh + ": " + last_line(run.err));
  std::ifstream is(stats);
  const json s = json::parse(is);
  json row = {{"setup_ms", s["steps"][0]["ms"]}};
  for (std::size_t k = 1; k < s["steps"].size(); ++k) row["step" + std::to_string(k) + "_ms"] = s["steps"][k]["ms"];
  row["process_ms"] = run.ms;
  row["peak_bytes"] = run.peak_bytes;
  row["created"] = s["steps"][0];
  return row;
}

json scattered_row(const std::string& ffdtool, const TempFolder& dir, const std::string& cloud, std::size_t points,
                   const json& op, std::size_t control, double target_s) {
  json create = op;
  create["name"] = "R";
  create["points"] = {{"file", dir.file("x" + std::to_string(control) + ".txt")}};
  const json move = {{"op", "move"}, {"lattice", "R"}, {"positions", {{"file", dir.file("y" + std::to_string(control) + ".txt")}}}};
  std::fprintf(stderr, "ffdbench: deformers: %s %zu x %zu\n", op.value("kernel", op["op"].get<std::string>()).c_str(),
               control, points);
  json r = run_steps(ffdtool, dir, cloud, json::array({create, move}));
  const double total = r["setup_ms"].get<double>() + r["step1_ms"].get<double>();
  json row = {{"op", op}, {"control_points", control}, {"points", points}, {"setup_ms", r["setup_ms"]},
              {"evaluation_ms", r["step1_ms"]}, {"process_ms", r["process_ms"]}, {"peak_bytes", r["peak_bytes"]}};
  if (r["created"].contains("condition_number")) row["condition_number"] = r["created"]["condition_number"];
  if (r["created"].contains("matrix_entries"))
    row["entries_per_row"] = r["created"]["matrix_entries"].get<double>() / static_cast<double>(control + 4);
  if (target_s > 0) row["target"] = {{"setup_plus_evaluation_s", target_s}, {"met", total < 1000 * target_s}};
  return row;
}

json rbf_rows(const std::string& ffdtool, const TempFolder& dir, bool quick) {
  const std::size_t small = quick ? 10000 : 100000, large = quick ? 100000 : 1000000;
  PolygonSoup cloud;
  cloud.positions = random_points(small, 1);
  write_binary(dir.file("small.ply"), cloud);
  cloud.positions = random_points(large, 2);
  write_binary(dir.file("large.ply"), cloud);
  const std::size_t c1 = quick ? 200 : 1000, c5 = quick ? 1000 : 5000, c10 = quick ? 2000 : 10000;
  for (std::size_t c : {c1, c5, c10}) write_control(dir, c);
  const auto rbf = [](const char* kernel, double radius) {
    return json{{"op", "rbf"}, {"kernel", kernel}, {"radius", radius}, {"k", 2}};
  };
  json rows = json::array();
  rows.push_back(scattered_row(ffdtool, dir, dir.file("small.ply"), small, rbf("gaussian_spline", 0.1), c1, 0));
  rows.push_back(scattered_row(ffdtool, dir, dir.file("small.ply"), small, rbf("thin_plate_spline", 0.5), c1, 0));
  const double target = quick ? 0 : 10, wendland_target = quick ? 0 : 5;  // the issue's, at full size
  rows.push_back(scattered_row(ffdtool, dir, dir.file("large.ply"), large, rbf("gaussian_spline", 0.06), c5, target));
  rows.push_back(scattered_row(ffdtool, dir, dir.file("large.ply"), large, rbf("thin_plate_spline", 0.5), c5, target));
  // About 50 control points within the radius: (4/3) pi r^3 c10 = 50.
  const double r50 = std::cbrt(50.0 / (4.0 / 3.0 * M_PI * static_cast<double>(c10)));
  rows.push_back(scattered_row(ffdtool, dir, dir.file("large.ply"), large, rbf("beckert_wendland_c2_basis", r50), c10,
                               wendland_target));
  rows.push_back(scattered_row(ffdtool, dir, dir.file("small.ply"), small, json{{"op", "idw"}, {"power", 2}}, c1, 0));
  return rows;
}

json cage_row(const std::string& ffdtool, const TempFolder& dir, const std::string& mesh, const std::string& cage,
              std::size_t triangles, double bspline_ms) {
  std::fprintf(stderr, "ffdbench: deformers: cage of %zu triangles\n", triangles);
  const json steps = {{{"op", "cage"}, {"name", "C"}, {"cage", dir.file(cage + ".obj")}},
                      {{"op", "move"}, {"lattice", "C"}, {"points", {{{"index", 0}, {"by", {0.01, 0, 0}}}}}},
                      {{"op", "move"}, {"lattice", "C"}, {"positions", {{"file", dir.file(cage + "_posed.txt")}}}}};
  const json r = run_steps(ffdtool, dir, mesh, steps);
  return {{"triangles", triangles},
          {"cage_vertices", r["created"]["cage_vertices"]},
          {"binding", r["created"]["binding"]},
          {"bind_ms", r["setup_ms"]},
          {"one_vertex_pose_ms", r["step1_ms"]},
          {"pose_ms", r["step2_ms"]},
          {"bspline_move_ms", bspline_ms},
          {"one_vertex_pose_vs_bspline_move", r["step1_ms"].get<double>() / bspline_ms},
          {"pose_vs_bspline_move", r["step2_ms"].get<double>() / bspline_ms},
          {"process_ms", r["process_ms"]},
          {"peak_bytes", r["peak_bytes"]},
          {"target", {{"bind_s", 2}, {"pose_ms", 30}, {"met", r["setup_ms"].get<double>() < 2000 && r["step2_ms"].get<double>() < 30}}}};
}

/// The cage rows on `mesh` (`what` says which), beside a B-spline move on it.
void cage_rows_on(const std::string& ffdtool, const TempFolder& dir, const std::string& mesh, const std::string& what,
                  bool quick, json& rows) {
  const json bspline = {{{"op", "lattice"}, {"name", "L"}, {"cells", {4, 4, 4}}},
                        {{"op", "move"}, {"lattice", "L"}, {"points", {{{"index", {2, 2, 2}}, {"by", {0.01, 0.02, 0.03}}}}}}};
  const double bspline_ms = run_steps(ffdtool, dir, mesh, bspline)["step1_ms"].get<double>();
  for (const auto& [name, slices, stacks] : {std::tuple{"cage200", 10, 11}, std::tuple{"cage2000", 40, 26}}) {
    if (quick && slices > 10) continue;
    json row = cage_row(ffdtool, dir, mesh, name, write_cage(dir, name, slices, stacks), bspline_ms);
    row["mesh"] = what;
    rows.push_back(row);
  }
}

/// Cages around a 100k-vertex sphere mesh (its normals need the Jacobian: gradients are
/// bound) and around the rbf rows' 100k-point cloud (no normals: coordinates only).
json cage_rows(const std::string& ffdtool, const TempFolder& dir, bool quick) {
  const std::string mesh = dir.file("sphere.ply");
  write_binary(mesh, quick ? uv_sphere(126, 80, Eigen::Vector3d::Constant(0.5), 0.4)
                           : uv_sphere(400, 251, Eigen::Vector3d::Constant(0.5), 0.4));
  json rows = json::array();
  cage_rows_on(ffdtool, dir, mesh, "sphere mesh with normals", quick, rows);
  cage_rows_on(ffdtool, dir, dir.file("small.ply"), "point cloud", quick, rows);
  return rows;
}

}  // namespace

void bench_deformers(Context& ctx) {
  const TempFolder dir("deformers");
  const std::string ffdtool = ffdtool_path(ctx.ffdtool);
  json scattered = rbf_rows(ffdtool, dir, ctx.quick);  // writes the point cloud the cage rows use too
  ctx.out["deformers"] = {{"scattered", std::move(scattered)}, {"cage", cage_rows(ffdtool, dir, ctx.quick)}};
}

}  // namespace ffd::bench
