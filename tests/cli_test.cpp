// The ffdtool binary end to end: run, compare, info, validate, schema; exit codes, one-line
// errors, outputs written whole or not at all, determinism.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mesh/build_mesh.h"
#include "mesh/mesh_io.h"
#include "script/schema.h"
#include "test_meshes.h"

namespace ffd {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using test::data;
using test::files_in;
using test::without_measurements;
using test::quoted;
using test::read_file;
using test::run_tool;
using test::script_with;
using test::temp_folder;
using test::write_file;
using test::expect_one_error_line;

// ---------------------------------------------------------------------------------------
// An independent evaluation of the demo script (test_data/demo.json) on the bunny: the
// box fitted as docs/script-reference.md says, the lattice points it selects and moves, and the cubic
// B-spline displacement summed directly from the cardinal basis.

double cubic_bspline(double s) {
  s = std::abs(s);
  if (s < 1) return (4 - 6 * s * s + 3 * s * s * s) / 6;
  if (s < 2) return (2 - s) * (2 - s) * (2 - s) / 6;
  return 0;
}

struct DemoModel {
  Eigen::Vector3d origin, size;
  static constexpr int kCells = 6;
  std::map<std::array<int, 3>, Eigen::Vector3d> displacement;  // moved points only

  Eigen::Vector3d rest_point(const std::array<int, 3>& ijk) const {
    return origin + size.cwiseProduct(Eigen::Vector3d(ijk[0], ijk[1], ijk[2]) / kCells);
  }
  Eigen::Vector3d point(const std::array<int, 3>& ijk) const {
    auto it = displacement.find(ijk);
    return rest_point(ijk) + (it == displacement.end() ? Eigen::Vector3d::Zero() : it->second);
  }
  // The movable points (cubic, 6 cells: 2..4 on every axis) whose current position is in
  // the demo's selection box [-10, 6, -10] .. [10, 20, 10].
  std::vector<std::array<int, 3>> select() const {
    std::vector<std::array<int, 3>> picked;
    for (int k = 2; k <= 4; ++k)
      for (int j = 2; j <= 4; ++j)
        for (int i = 2; i <= 4; ++i) {
          const Eigen::Vector3d p = point({i, j, k});
          if ((p.array() >= Eigen::Array3d(-10, 6, -10)).all() && (p.array() <= Eigen::Array3d(10, 20, 10)).all())
            picked.push_back({i, j, k});
        }
    return picked;
  }
  // p -> c + L (p - c) + t over the picked points, c their centroid.
  void transform(const Eigen::Matrix3d& L, const Eigen::Vector3d& t) {
    const auto picked = select();
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const auto& ijk : picked) c += point(ijk);
    c /= static_cast<double>(picked.size());
    for (const auto& ijk : picked) displacement[ijk] = c + L * (point(ijk) - c) + t - rest_point(ijk);
  }
  Eigen::Vector3d warp(const Eigen::Vector3d& x) const {
    const Eigen::Vector3d u = (x - origin).cwiseQuotient(size) * kCells;
    Eigen::Vector3d out = x;
    for (const auto& [ijk, d] : displacement)
      out += cubic_bspline(u[0] - ijk[0]) * cubic_bspline(u[1] - ijk[1]) * cubic_bspline(u[2] - ijk[2]) * d;
    return out;
  }
};

// The demo's lattice after its first `steps` steps that move points (1 or 2).
DemoModel demo_model(const Mesh& input, int moves) {
  DemoModel m;
  const Eigen::Vector3d lo = input.positions().rowwise().minCoeff(), hi = input.positions().rowwise().maxCoeff();
  const double pad = 0.05 * (hi - lo).maxCoeff();
  m.origin = lo - Eigen::Vector3d::Constant(pad);
  m.size = hi - lo + Eigen::Vector3d::Constant(2 * pad);
  m.transform(Eigen::Vector3d(1, 1.1, 1).asDiagonal(), Eigen::Vector3d(0, 1.2, 0));
  if (moves >= 2) {
    const double a = 20 * M_PI / 180;
    Eigen::Matrix3d R;
    R << std::cos(a), 0, std::sin(a), 0, 1, 0, -std::sin(a), 0, std::cos(a);
    m.transform(R, Eigen::Vector3d::Zero());
  }
  return m;
}

// Checks a mesh file against the independent evaluation of the demo's first `moves`
// moves; returns the number of vertices it says moved.
std::size_t check_demo_output(const std::string& path, int moves) {
  SCOPED_TRACE(path);
  const Mesh input = test::bunny();
  const Mesh output = read_mesh(path);
  EXPECT_EQ(output.num_vertices(), input.num_vertices());
  EXPECT_EQ(output.faces(), input.faces()) << "a plain FFD keeps the connectivity";
  if (output.num_vertices() != input.num_vertices()) return 0;
  const DemoModel model = demo_model(input, moves);
  EXPECT_EQ(model.displacement.size(), 9u) << "the demo moves the 9 movable points of the layer j = 4";
  for (const auto& entry : model.displacement) EXPECT_EQ(entry.first[1], 4);
  // Point j = 4 influences cells j = 2..5: below u_y = 2/6 nothing may change, bit for bit.
  std::size_t in_band = 0, unchanged = 0;
  double worst = 0;
  for (std::size_t v = 0; v < input.num_vertices(); ++v) {
    const Eigen::Vector3d x = input.positions().col(v), y = output.positions().col(v);
    const double uy = (x.y() - model.origin.y()) / model.size.y();
    if (uy < 2.0 / 6 - 1e-9) {
      EXPECT_TRUE(x == y) << "vertex " << v << " is outside the moved points' cells but changed";
      ++unchanged;
    } else {
      ++in_band;
      worst = std::max(worst, (model.warp(x) - y).norm());
    }
  }
  EXPECT_GT(unchanged, 500u);
  EXPECT_GT(in_band, 500u);
  EXPECT_LT(worst, 1e-11) << "the output differs from the directly summed B-spline FFD";
  return in_band;
}

std::string demo_run_args(const std::string& dir, const std::string& extra = "") {
  return "run " + quoted(data("bunny.obj")) + " " + quoted(data("demo.json")) + " -o " + quoted(dir + "/out.obj") + " --stats " +
         quoted(dir + "/stats.json") + (extra.empty() ? "" : " " + extra);
}

TEST(CliRun, DemoOnTheBunnyMatchesTheExpectedMesh) {
  const std::string dir = temp_folder("cli_demo");
  std::string out, err;
  ASSERT_EQ(run_tool(demo_run_args(dir), &out, &err), 0) << err;
  EXPECT_EQ(files_in(dir), (std::set<std::string>{"out.obj", "stats.json", "bunny_stretched.obj"}));
  // One summary line per step on stderr, and nothing on stdout.
  EXPECT_NE(err.find("[3] move 'body'"), std::string::npos) << err;
  EXPECT_TRUE(out.empty()) << out;

  // Against the checked-in expected mesh, through `ffdtool compare`.
  std::string cmp_out, cmp_err;
  EXPECT_EQ(run_tool("compare " + quoted(dir + "/out.obj") + " " + quoted(data("expected/bunny_demo.obj")) + " --tolerance 1e-9",
                     &cmp_out, &cmp_err),
            0)
      << cmp_out << cmp_err;
  EXPECT_NE(cmp_out.find("same"), std::string::npos) << cmp_out;

  // The output, the expected mesh and the mid-script save against an independent evaluation.
  const std::size_t in_band = check_demo_output(dir + "/out.obj", 2);
  check_demo_output(data("expected/bunny_demo.obj"), 2);
  check_demo_output(dir + "/bunny_stretched.obj", 1);

  // stats.json has what docs/architecture.md ("Stats") lists.
  const json stats = json::parse(read_file(dir + "/stats.json"));
  for (const char* key : {"tool", "version", "input", "steps", "totals", "peak_memory_bytes", "output", "warnings"})
    EXPECT_TRUE(stats.contains(key)) << key;
  EXPECT_EQ(stats["tool"], "ffdtool");
  EXPECT_EQ(stats["input"]["mesh"], data("bunny.obj"));
  EXPECT_EQ(stats["input"]["vertices"], 1839);
  EXPECT_EQ(stats["input"]["faces"], 3674);
  ASSERT_EQ(stats["steps"].size(), 4u);
  const std::vector<std::string> ops = {"lattice", "move", "save", "move"};
  for (std::size_t i = 0; i < 4; ++i) {
    const json& step = stats["steps"][i];
    EXPECT_EQ(step["op"], ops[i]);
    EXPECT_TRUE(step["ms"].is_number() && step["ms"].get<double>() >= 0) << step.dump();
    EXPECT_EQ(step["vertices"], 1839);
    EXPECT_EQ(step["faces"], 3674);
  }
  EXPECT_EQ(stats["steps"][0]["movable_points"], 27);
  EXPECT_EQ(stats["steps"][0]["vertices_inside"], 1839);
  EXPECT_EQ(stats["steps"][1]["points_moved"], 9);
  EXPECT_EQ(stats["steps"][1]["vertices_moved"], in_band);
  EXPECT_EQ(stats["steps"][3]["vertices_moved"], in_band);
  EXPECT_EQ(stats["steps"][1]["inverted_jacobians"], 0);
  EXPECT_EQ(stats["steps"][2]["path"], "bunny_stretched.obj");
  EXPECT_EQ(stats["output"]["vertices"], 1839);
  EXPECT_TRUE(stats["totals"]["ms"].is_number());
  EXPECT_GE(stats["totals"]["ms"].get<double>(), stats["totals"]["steps_ms"].get<double>());
  EXPECT_GT(stats["peak_memory_bytes"].get<double>(), 0);
}

TEST(CliRun, IsDeterministicWhateverTheThreadCount) {
  const std::string dir = temp_folder("cli_determinism");
  ASSERT_EQ(run_tool(demo_run_args(dir, "--quiet")), 0);
  const std::string mesh1 = read_file(dir + "/out.obj"), save1 = read_file(dir + "/bunny_stretched.obj");
  const json stats1 = json::parse(read_file(dir + "/stats.json"));
  ASSERT_EQ(run_tool(demo_run_args(dir, "--quiet")), 0);
  EXPECT_EQ(read_file(dir + "/out.obj"), mesh1);
  EXPECT_EQ(read_file(dir + "/bunny_stretched.obj"), save1);
  const json stats2 = json::parse(read_file(dir + "/stats.json"));
  EXPECT_EQ(without_measurements(stats1), without_measurements(stats2));
  EXPECT_NE(without_measurements(stats1).dump().find("vertices_moved"), std::string::npos);

  for (const char* threads : {"1", "2"}) {
    const std::string tdir = temp_folder(std::string("cli_threads_") + threads);
    ASSERT_EQ(run_tool(demo_run_args(tdir, std::string("--quiet --threads ") + threads)), 0);
    EXPECT_EQ(read_file(tdir + "/out.obj"), mesh1) << "--threads " << threads;
    EXPECT_EQ(read_file(tdir + "/bunny_stretched.obj"), save1) << "--threads " << threads;
    EXPECT_EQ(json::parse(read_file(tdir + "/stats.json"))["threads"], std::stoi(threads));
  }
}

// ---------------------------------------------------------------------------------------
// Bad input: exit 2, one line naming the file and the place, nothing written.

struct BadRun {
  const char* name;
  std::function<std::string(const std::string& in, const std::string& out)> setup;  // returns the arguments
  std::vector<std::string> mentions;  // parts of the message ("{in}" is replaced by the input folder)
};

const char* kGoodScript = R"({"version": 1, "steps": [
  {"op": "lattice", "name": "body", "cells": [4, 4, 4]},
  {"op": "move", "lattice": "body", "points": [{"index": [2, 2, 2], "by": [0, 0.1, 0]}]}]})";

std::string run_stats_args(const std::string& mesh, const std::string& script, const std::string& output,
                           const std::string& stats) {
  return "run " + quoted(mesh) + " " + quoted(script) + " -o " + quoted(output) + " --stats " + quoted(stats);
}

TEST(CliRun, BadInputExitsTwoWithOneLineAndWritesNothing) {
  const std::string triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  const std::string lattice = R"({"op": "lattice", "name": "body", "cells": [6, 6, 6]})";
  // Each setup writes its inputs into `in` and returns the arguments; outputs go to `out`.
  const auto standard = [&](const std::string& mesh_name, const std::string& mesh_text, const std::string& script) {
    return [=](const std::string& in, const std::string& out) {
      if (!mesh_text.empty()) write_file(in + "/" + mesh_name, mesh_text);
      write_file(in + "/script.json", script);
      return run_stats_args(in + "/" + mesh_name, in + "/script.json", out + "/out.obj", out + "/stats.json");
    };
  };
  const std::vector<BadRun> cases = {
      {"missing mesh file", standard("missing.obj", "", kGoodScript), {"{in}/missing.obj", "no such file"}},
      {"malformed OBJ line", standard("bad.obj", "v 0 0 0\nv 1 0 0\nv 1 2\nf 1 2 3\n", kGoodScript),
       {"{in}/bad.obj:3:", "v x y z"}},
      {"NaN coordinate", standard("nan.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n", kGoodScript),
       {"{in}/nan.obj:2:", "'nan'"}},
      {"inf coordinate", standard("inf.obj", "v 0 0 0\nv 1 0 0\nv 0 1 -inf\nf 1 2 3\n", kGoodScript),
       {"{in}/inf.obj:3:", "'-inf'"}},
      {"face index out of range", standard("face.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n", kGoodScript),
       {"{in}/face.obj:4:", "out of range"}},
      {"malformed OFF line", standard("bad.off", "OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n", kGoodScript),
       {"{in}/bad.off:4:", "vertex 1"}},
      {"OFF face index out of range", standard("face.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", kGoodScript),
       {"{in}/face.off:6:", "out of range"}},
      {"invalid JSON", standard("mesh.obj", triangle, "{\"version\": 1,\n \"steps\": [}\n"),
       {"{in}/script.json: invalid JSON", "line 2", "column"}},
      {"unknown op", standard("mesh.obj", triangle, script_with(R"({"op": "twist"})")),
       {"{in}/script.json: /steps/0/op:", "unknown op \"twist\""}},
      {"unknown key", standard("mesh.obj", triangle, script_with(R"({"op": "lattice", "name": "b", "cells": [4, 4, 4], "colour": 1})")),
       {"{in}/script.json: /steps/0/colour:", "unknown key 'colour'"}},
      {"lattice index out of range",
       standard("mesh.obj", triangle,
                script_with(lattice + R"(, {"op": "move", "lattice": "body", "points": [{"index": [7, 3, 3], "by": [0, 1, 0]}]})")),
       {"{in}/script.json: /steps/1/points/0/index:", "[7,3,3]", "i in [2, 4]"}},
      {"index not movable",
       standard("mesh.obj", triangle,
                script_with(lattice + R"(, {"op": "move", "lattice": "body", "points": [{"index": [3, 3, 1], "by": [0, 1, 0]}]})")),
       {"{in}/script.json: /steps/1/points/0/index:", "not movable", "k in [2, 4]"}},
      {"output folder missing",
       [&](const std::string& in, const std::string& out) {
         write_file(in + "/mesh.obj", triangle);
         write_file(in + "/script.json", kGoodScript);
         return run_stats_args(in + "/mesh.obj", in + "/script.json", out + "/missing/out.obj", out + "/stats.json");
       },
       {"missing/out.obj", "does not exist"}},
      {"unknown output extension",
       [&](const std::string& in, const std::string& out) {
         write_file(in + "/mesh.obj", triangle);
         write_file(in + "/script.json", kGoodScript);
         return run_stats_args(in + "/mesh.obj", in + "/script.json", out + "/out.xyz", out + "/stats.json");
       },
       {"out.xyz", "unknown mesh format"}},
      {"selection picks nothing (found at run time, after a save)",
       [&](const std::string& in, const std::string& out) {
         write_file(in + "/mesh.obj", read_file(data("bunny.obj")));
         write_file(in + "/script.json",
                    script_with(lattice + R"(,
              {"op": "move", "lattice": "body", "points": [{"index": [3, 3, 3], "by": [0, 1, 0]}]},
              {"op": "save", "path": "early.obj"},
              {"op": "move", "lattice": "body", "select": {"box": {"min": [100, 100, 100], "max": [101, 101, 101]}},
               "transform": {"scale": 2}}
              )"));
         return run_stats_args(in + "/mesh.obj", in + "/script.json", out + "/out.obj", out + "/stats.json") + " --quiet";
       },
       {"{in}/script.json: /steps/3/select:", "picks no movable lattice point"}},
  };
  for (const BadRun& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string in = temp_folder("bad_in"), out = temp_folder("bad_out");
    const std::string args = c.setup(in, out);
    std::string stdout_text, err;
    EXPECT_EQ(run_tool(args, &stdout_text, &err), 2) << err;
    std::vector<std::string> mentions;
    for (std::string m : c.mentions) {
      const auto at = m.find("{in}");
      if (at != std::string::npos) m.replace(at, 4, in);
      mentions.push_back(m);
    }
    expect_one_error_line(err, mentions);
    EXPECT_TRUE(files_in(out).empty()) << "files were written: " << [&] {
      std::string s;
      for (const auto& f : files_in(out)) s += f + " ";
      return s;
    }();
    EXPECT_FALSE(fs::exists(out + "/missing"));
  }
}

TEST(CliRun, ASaveThatWouldOverwriteTheInputIsRefused) {
  const std::string dir = temp_folder("cli_overwrite");
  const std::string mesh = read_file(data("bunny.obj"));
  write_file(dir + "/in.obj", mesh);
  write_file(dir + "/script.json", script_with(R"({"op": "lattice", "name": "body", "cells": [4, 4, 4]},
      {"op": "move", "lattice": "body", "points": [{"index": [2, 2, 2], "by": [0, 1, 0]}]},
      {"op": "save", "path": "in.obj"})"));
  std::string err;
  EXPECT_EQ(run_tool(run_stats_args(dir + "/in.obj", dir + "/script.json", dir + "/out.obj", dir + "/stats.json"), nullptr, &err), 2);
  expect_one_error_line(err, {dir + "/script.json: /steps/2", "in.obj", "overwrite"});
  EXPECT_EQ(files_in(dir), (std::set<std::string>{"in.obj", "script.json"}));
  EXPECT_EQ(read_file(dir + "/in.obj"), mesh);

  // The stats file may not overwrite an input either.
  EXPECT_EQ(run_tool(run_stats_args(dir + "/in.obj", dir + "/script.json", dir + "/out.obj", dir + "/in.obj"), nullptr, &err), 2);
  EXPECT_EQ(read_file(dir + "/in.obj"), mesh);
  EXPECT_EQ(files_in(dir), (std::set<std::string>{"in.obj", "script.json"}));
}

// ---------------------------------------------------------------------------------------
// compare

// Each triangle split into four at its edge midpoints: the same surface, more vertices.
Mesh midpoint_refined(const Mesh& mesh) {
  PolygonSoup soup;
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) soup.positions.push_back(mesh.positions().col(v));
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
  const auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
    const auto key = std::minmax(a, b);
    auto it = mid.find(key);
    if (it != mid.end()) return it->second;
    soup.positions.push_back(0.5 * (soup.positions[a] + soup.positions[b]));
    return mid[key] = static_cast<std::uint32_t>(soup.positions.size() - 1);
  };
  for (const auto& f : mesh.faces()) {
    const std::uint32_t ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
    for (const std::vector<std::uint32_t>& t : {std::vector<std::uint32_t>{f[0], ab, ca}, {f[1], bc, ab},
                                                {f[2], ca, bc}, {ab, bc, ca}}) {
      test::SoupFace face;
      face.vertices = t;
      test::add_face(soup, face.vertices, face.uvs, face.normals, face.group);
    }
  }
  return build_mesh(soup, "refined");
}

TEST(CliCompare, ExitCodesAndMetrics) {
  const std::string dir = temp_folder("cli_compare");
  const std::string bunny = data("bunny.obj");
  std::string out, err;
  EXPECT_EQ(run_tool("compare " + quoted(bunny) + " " + quoted(bunny), &out, &err), 0) << out << err;
  EXPECT_NE(out.find("max 0"), std::string::npos) << out;

  // One vertex moved by 1e-6.
  Mesh moved = test::bunny();
  moved.positions()(0, 100) += 1e-6;
  write_mesh(dir + "/moved.obj", moved);
  EXPECT_EQ(run_tool("compare " + quoted(bunny) + " " + quoted(dir + "/moved.obj") + " --tolerance 1e-9", &out, &err), 1) << err;
  EXPECT_NE(out.find("different"), std::string::npos) << out;
  EXPECT_NE(out.find("vertex 100"), std::string::npos) << out;
  EXPECT_EQ(run_tool("compare " + quoted(bunny) + " " + quoted(dir + "/moved.obj") + " --tolerance 1e-5", &out, &err), 0) << out;
  ASSERT_EQ(run_tool("compare " + quoted(bunny) + " " + quoted(dir + "/moved.obj") + " --json", &out, &err), 1) << err;
  const json j = json::parse(out);
  EXPECT_EQ(j["metric"], "vertex");
  EXPECT_EQ(j["within_tolerance"], false);
  EXPECT_EQ(j["worst_vertex"], 100);
  EXPECT_NEAR(j["max"].get<double>(), 1e-6, 1e-12);
  EXPECT_NEAR(j["mean"].get<double>(), 1e-6 / 1839, 1e-12);
  EXPECT_EQ(j["same_connectivity"], true);

  // Different vertex counts: the vertex metric cannot compare them and says what to use.
  const Mesh refined = midpoint_refined(test::bunny());
  write_mesh(dir + "/refined.obj", refined);
  EXPECT_EQ(run_tool("compare " + quoted(bunny) + " " + quoted(dir + "/refined.obj") + " --metric vertex", &out, &err), 1);
  EXPECT_NE(out.find("hausdorff"), std::string::npos) << out;
  EXPECT_NE(out.find("1839"), std::string::npos) << out;

  // Hausdorff: the refined copy has the same surface...
  ASSERT_EQ(run_tool("compare " + quoted(bunny) + " " + quoted(dir + "/refined.obj") + " --metric hausdorff --tolerance 1e-6 --json",
                     &out, &err),
            0)
      << out << err;
  const json h = json::parse(out);
  EXPECT_EQ(h["metric"], "hausdorff");
  EXPECT_EQ(h["within_tolerance"], true);
  EXPECT_LT(h["max"].get<double>(), 1e-6);
  // ...and a copy scaled by 1.01 about the centre is 0.01 away (unit icosphere).
  const Mesh sphere = test::sphere_mesh(3);
  Mesh bigger = test::sphere_mesh(3);
  bigger.positions() *= 1.01;
  write_mesh(dir + "/sphere.off", sphere);
  write_mesh(dir + "/bigger.obj", bigger);
  write_mesh(dir + "/sphere_refined.ply", midpoint_refined(sphere));
  ASSERT_EQ(run_tool("compare " + quoted(dir + "/sphere.off") + " " + quoted(dir + "/bigger.obj") +
                         " --metric hausdorff --tolerance 1e-3 --json",
                     &out, &err),
            1)
      << err;
  const json s = json::parse(out);
  EXPECT_NEAR(s["max"].get<double>(), 0.01, 1e-4);
  ASSERT_EQ(run_tool("compare " + quoted(dir + "/sphere.off") + " " + quoted(dir + "/sphere_refined.ply") +
                         " --metric hausdorff --tolerance 1e-9",
                     &out, &err),
            0)
      << out << err;
}

TEST(CliCompare, BadArgumentsExitTwo) {
  std::string err;
  EXPECT_EQ(run_tool("compare " + quoted(data("bunny.obj")) + " " + quoted(data("nope.obj")), nullptr, &err), 2);
  expect_one_error_line(err, {"nope.obj", "no such file"});
  EXPECT_EQ(run_tool("compare " + quoted(data("bunny.obj")) + " " + quoted(data("bunny.obj")) + " --metric chamfer", nullptr, &err), 2);
  expect_one_error_line(err, {"chamfer"});
  EXPECT_EQ(run_tool("compare " + quoted(data("bunny.obj")), nullptr, &err), 2);
  expect_one_error_line(err, {});
}

// ---------------------------------------------------------------------------------------
// info, validate, schema, version, usage

TEST(CliInfo, PrintsTheBunnysCounts) {
  std::string out, err;
  ASSERT_EQ(run_tool("info " + quoted(data("bunny.obj")), &out, &err), 0) << err;
  EXPECT_NE(out.find("vertices   1,839 (0 isolated)"), std::string::npos) << out;
  EXPECT_NE(out.find("faces      3,674 (3,674 with 3 sides)"), std::string::npos) << out;
  EXPECT_NE(out.find("closed"), std::string::npos) << out;
  EXPECT_NE(out.find("Euler characteristic 2"), std::string::npos) << out;
  ASSERT_EQ(run_tool("info --json " + quoted(data("bunny.obj")), &out, &err), 0) << err;
  const json j = json::parse(out);
  EXPECT_EQ(j["vertices"], 1839);
  EXPECT_EQ(j["faces"], 3674);
  EXPECT_EQ(j["boundary_edges"], 0);
  EXPECT_EQ(j["edges"], 5511);
}

TEST(CliValidate, ValidResolvedAndInvalid) {
  std::string out, err;
  ASSERT_EQ(run_tool("validate " + quoted(data("demo.json")), &out, &err), 0) << err;
  EXPECT_NE(out.find("valid"), std::string::npos) << out;
  EXPECT_NE(out.find("4 steps"), std::string::npos) << out;

  const std::string dir = temp_folder("cli_validate");
  write_file(dir + "/s.json", script_with(R"({"op": "lattice", "name": "b", "cells": [4, 4, 4]},
      {"op": "move", "lattice": "b", "select": {"near": [0, 0, 0]}, "transform": {"rotate": {"axis": [0, 0, 1], "degrees": 5}}})"));
  ASSERT_EQ(run_tool("validate --resolved " + quoted(dir + "/s.json"), &out, &err), 0) << err;
  const json r = json::parse(out);
  EXPECT_EQ(r["steps"][0]["basis"], "bspline");
  EXPECT_EQ(r["steps"][0]["degree"], 3);
  EXPECT_EQ(r["steps"][0]["box"], json::parse(R"({"fit": "aabb", "padding": 0.05})"));
  EXPECT_EQ(r["steps"][1]["transform"]["scale"], 1);
  EXPECT_EQ(r["steps"][1]["transform"]["translate"], json::array({0, 0, 0}));

  write_file(dir + "/bad.json", script_with(R"({"op": "lattice", "name": "b", "cells": [4, 4]})"));
  EXPECT_EQ(run_tool("validate " + quoted(dir + "/bad.json"), &out, &err), 2);
  expect_one_error_line(err, {dir + "/bad.json: /steps/0/cells:", "expected an array of 3 integers"});
  EXPECT_TRUE(out.empty()) << out;
}

TEST(CliSchema, PrintsTheSchemaAsJson) {
  std::string out, err;
  ASSERT_EQ(run_tool("schema", &out, &err), 0) << err;
  const json schema = json::parse(out);
  EXPECT_EQ(schema, script_schema());
  EXPECT_TRUE(schema.contains("$defs"));
}

TEST(CliUsage, VersionHelpAndUsageErrors) {
  std::string out, err;
  EXPECT_EQ(run_tool("--version", &out, &err), 0);
  EXPECT_NE(out.find("ffdtool " FFD_VERSION), std::string::npos) << out;
  EXPECT_EQ(run_tool("--help", &out, &err), 0);
  for (const char* sub : {"run", "compare", "info", "validate", "schema"}) EXPECT_NE(out.find(sub), std::string::npos) << sub;

  EXPECT_EQ(run_tool("frobnicate", &out, &err), 2);
  expect_one_error_line(err, {});
  EXPECT_EQ(run_tool("", &out, &err), 2);
  expect_one_error_line(err, {});
  EXPECT_EQ(run_tool("run " + quoted(data("bunny.obj")), &out, &err), 2);
  expect_one_error_line(err, {"required"});
  EXPECT_EQ(run_tool("run " + quoted(data("bunny.obj")) + " " + quoted(data("demo.json")), &out, &err), 2);
  expect_one_error_line(err, {"--output"});
  EXPECT_EQ(run_tool("info", &out, &err), 2);
  expect_one_error_line(err, {"mesh"});
  EXPECT_EQ(run_tool("validate", &out, &err), 2);
  expect_one_error_line(err, {"script"});
  EXPECT_EQ(run_tool("info " + quoted(data("bunny.obj")) + " --frob", &out, &err), 2);
  expect_one_error_line(err, {"--frob"});
}

}  // namespace
}  // namespace ffd
