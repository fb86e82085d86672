// Octree lattices (Ono et al.'s multiresolution lattices) through the ffdtool binary, on
// the shared real meshes (../shared/meshes): the lattice step's levels and box, moves and
// drags at a level, the control nets save writes, identity when nothing moves, locality,
// thread-count independence, global editing around a local lattice (enclose), input errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mesh/mesh_io.h"
#include "test_meshes.h"

namespace ffd {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using test::files_in;
using test::quoted;
using test::read_file;
using test::script;
using test::run_tool;
using test::temp_folder;
using test::without_measurements;
using test::write_file;
using test::expect_one_error_line;

// A mesh of the shared set beside the repository, or else the same file from Debian's
// libcgal-demo (../shared/meshes are byte-for-byte copies of its data/meshes/), extracted
// once; "" when neither is there.
std::string shared_mesh(const std::string& name) {
  const fs::path p = (fs::path(FFD_SOURCE_DIR) / ".." / "shared" / "meshes" / name).lexically_normal();
  if (fs::exists(p)) return p.string();
  return test::cgal_mesh(name);
}

#define SHARED_MESH_OR_SKIP(var, name)                                          \
  const std::string var = shared_mesh(name);                                    \
  if (var.empty()) GTEST_SKIP() << "../shared/meshes/" << name << " is missing, and libcgal-demo too"

const std::string kOctreeLattice =
    R"({"op": "lattice", "name": "auto", "basis": "octree", "box": {"fit": "obb", "padding": 0.02}, )"
    R"("levels": 4, "shrink": 0.002, "cc_steps": 2})";

struct ToolRun {
  int code = -1;
  std::string dir, err;
  json stats;
};

// Writes the script to a fresh folder `name` and runs it on `mesh`, output dir/`out`,
// stats dir/stats.json.
ToolRun run_octree_script(const std::string& name, const std::string& mesh, const std::vector<std::string>& steps,
                          const std::string& out = "out.off", const std::string& extra = "") {
  ToolRun r;
  r.dir = temp_folder("multires_" + name);
  write_file(r.dir + "/s.json", script(steps));
  r.code = run_tool("run " + quoted(mesh) + " " + quoted(r.dir + "/s.json") + " -o " + quoted(r.dir + "/" + out) +
                        " --stats " + quoted(r.dir + "/stats.json") + " --quiet " + extra,
                    nullptr, &r.err);
  const std::string text = read_file(r.dir + "/stats.json");
  if (!text.empty()) r.stats = json::parse(text);
  return r;
}

// A control net as save writes it: "v x y z" points, "l a b" edges (1-based), "#" comments.
struct Net {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<long, 2>> edges;
  std::vector<std::string> other_lines;
};

Net read_net(const std::string& path) {
  Net net;
  std::istringstream is(read_file(path));
  std::string line;
  while (std::getline(is, line)) {
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    if (tag == "#" || line.rfind("#", 0) == 0) continue;
    if (tag == "v") {
      Eigen::Vector3d p;
      if (ls >> p[0] >> p[1] >> p[2]) net.points.push_back(p);
      else net.other_lines.push_back(line);
    } else if (tag == "l") {
      std::array<long, 2> e{};
      std::string rest;
      if (ls >> e[0] >> e[1] && !(ls >> rest)) net.edges.push_back(e);
      else net.other_lines.push_back(line);
    } else {
      net.other_lines.push_back(line);
    }
  }
  return net;
}

// The net at `path` is well formed, with `points` points and `edges` edges (from the stats).
void check_net(const std::string& path, std::size_t points, std::size_t edges) {
  SCOPED_TRACE(path);
  const Net net = read_net(path);
  EXPECT_TRUE(net.other_lines.empty()) << "first stray line: " << net.other_lines.front();
  EXPECT_EQ(net.points.size(), points);
  EXPECT_EQ(net.edges.size(), edges);
  EXPECT_GT(net.edges.size(), net.points.size());
  for (const auto& e : net.edges) {
    EXPECT_TRUE(e[0] >= 1 && e[0] <= static_cast<long>(net.points.size()) && e[1] >= 1 &&
                e[1] <= static_cast<long>(net.points.size()) && e[0] != e[1])
        << "bad edge l " << e[0] << " " << e[1] << " (" << net.points.size() << " points)";
  }
}

// The lattice step's "levels": level 0 the box's one cell; every finer level's cells and
// cut cells are the 8 children of the level above's cells.
void check_levels(const json& step, int levels) {
  ASSERT_TRUE(step.contains("levels")) << step.dump();
  const json& ls = step["levels"];
  ASSERT_EQ(ls.size(), static_cast<std::size_t>(levels + 1)) << ls.dump();
  EXPECT_EQ(ls[0]["cells"], 1);
  EXPECT_EQ(ls[0]["points"], 8);
  EXPECT_EQ(ls[0]["cut_cells"], 0);
  for (int l = 0; l <= levels; ++l) {
    EXPECT_EQ(ls[l]["level"], l);
    EXPECT_GT(ls[l]["points"].get<long>(), 0) << "level " << l;
    if (l == 0) continue;
    EXPECT_EQ(ls[l]["cells"].get<long>() + ls[l]["cut_cells"].get<long>(), 8 * ls[l - 1]["cells"].get<long>())
        << "level " << l;
    EXPECT_GT(ls[l]["points"].get<long>(), ls[l - 1]["points"].get<long>()) << "level " << l;
  }
}

void check_box(const json& step) {
  ASSERT_TRUE(step.contains("box")) << step.dump();
  const json& box = step["box"];
  ASSERT_TRUE(box.contains("origin") && box.contains("axes")) << box.dump();
  EXPECT_EQ(box["origin"].size(), 3u);
  ASSERT_EQ(box["axes"].size(), 3u);
  for (const json& axis : box["axes"]) EXPECT_EQ(axis.size(), 3u);
}

void check_move(const json& step, int level) {
  SCOPED_TRACE(step.dump());
  EXPECT_EQ(step["op"], "move");
  EXPECT_EQ(step["level"], level);
  EXPECT_EQ(step["points_moved"], 1);
  EXPECT_GT(step["cells_subdivided"].get<long>(), 0);
  EXPECT_TRUE(step.contains("vertices_moved"));
  EXPECT_TRUE(step.contains("ms"));
}

// Vertices of `b` not bit-identical to `a`'s (same count required).
std::vector<std::uint32_t> changed_vertices(const Mesh& a, const Mesh& b) {
  std::vector<std::uint32_t> changed;
  EXPECT_EQ(a.num_vertices(), b.num_vertices());
  if (a.num_vertices() != b.num_vertices()) return changed;
  for (std::uint32_t v = 0; v < a.num_vertices(); ++v)
    if (!(a.positions().col(v) == b.positions().col(v))) changed.push_back(v);
  return changed;
}

// The steps' stats without times: without_measurements, and the remesh step's "ms_test",
// "ms_refine", "ms_decimate", which its "*_ms" rule does not catch.
json step_counts(const json& stats) {
  json steps = without_measurements(stats["steps"]);
  for (json& step : steps)
    for (const char* key : {"ms_test", "ms_refine", "ms_decimate"}) step.erase(key);
  return steps;
}

std::string vec(const Eigen::Vector3d& v) { return json::array({v[0], v[1], v[2]}).dump(); }

// Moves at levels 1 and 3, the nets of levels 2 and 3, a remesh and the mesh's save.
std::vector<std::string> end_to_end_steps() {
  return {kOctreeLattice,
          R"({"op": "move", "lattice": "auto", "level": 1, "select": {"near": [0.5, 0.5, 0]},
              "transform": {"translate": [0, 0.05, 0]}})",
          R"({"op": "move", "lattice": "auto", "level": 3, "points": [{"index": [4, 4, 4], "by": [0.02, 0, 0.01]}]})",
          R"({"op": "save", "path": "lat2.obj", "lattice": "auto", "level": 2})",
          R"({"op": "save", "path": "lat3.obj", "lattice": "auto", "level": 3})",
          R"({"op": "remesh", "theta_max_deg": 25.7, "theta_min_deg": 20.0})",
          R"({"op": "save", "path": "mesh.off"})"};
}

TEST(MultiresCli, EndToEndOnTheBunny) {
  SHARED_MESH_OR_SKIP(bunny, "bunny00.off");
  const ToolRun r = run_octree_script("e2e", bunny, end_to_end_steps());
  ASSERT_EQ(r.code, 0) << r.err;
  const json& steps = r.stats["steps"];
  ASSERT_EQ(steps.size(), 7u);
  const std::size_t n = r.stats["input"]["vertices"].get<std::size_t>();
  EXPECT_EQ(n, 37706u);

  EXPECT_EQ(steps[0]["basis"], "octree");
  check_levels(steps[0], 4);
  check_box(steps[0]);
  EXPECT_EQ(steps[0]["vertices_inside"], n);

  check_move(steps[1], 1);
  check_move(steps[2], 3);
  const std::size_t coarse = steps[1]["vertices_moved"].get<std::size_t>();
  const std::size_t fine = steps[2]["vertices_moved"].get<std::size_t>();
  EXPECT_LT(fine, n) << "a level-3 point should act on part of the mesh only";
  EXPECT_GT(coarse, fine) << "a level-1 point should act on more of the mesh than a level-3 one";

  for (int i : {3, 4}) {
    const json& save = steps[i];
    const int level = save["level"].get<int>();
    EXPECT_EQ(level, i - 1);
    EXPECT_EQ(save["points"], steps[0]["levels"][level]["points"]) << "level " << level;
    check_net(r.dir + "/" + save["path"].get<std::string>(), save["points"].get<std::size_t>(),
              save["edges"].get<std::size_t>());
  }

  EXPECT_EQ(steps[5]["op"], "remesh");
  const Mesh out = read_mesh(r.dir + "/out.off");
  EXPECT_EQ(out.num_vertices(), steps[5]["vertices"].get<std::size_t>());
  EXPECT_EQ(read_file(r.dir + "/mesh.off"), read_file(r.dir + "/out.off"));
}

TEST(MultiresCli, UnmovedOctreeLatticeWritesTheInputBack) {
  SHARED_MESH_OR_SKIP(bunny, "bunny00.off");
  const ToolRun r = run_octree_script(
      "identity", bunny,
      {kOctreeLattice, R"({"op": "move", "lattice": "auto", "level": 1, "points": [{"index": [1, 1, 1], "by": [0, 0, 0]}]})",
       R"({"op": "move", "lattice": "auto", "level": 3, "points": [{"index": [4, 4, 4], "by": [0, 0, 0]}]})"});
  ASSERT_EQ(r.code, 0) << r.err;
  std::string report;
  EXPECT_EQ(run_tool("compare " + quoted(bunny) + " " + quoted(r.dir + "/out.off") + " --tolerance 0", &report), 0)
      << report;
}

TEST(MultiresCli, OneAndTwoThreadsWriteTheSameBytes) {
  SHARED_MESH_OR_SKIP(bunny, "bunny00.off");
  const ToolRun one = run_octree_script("threads1", bunny, end_to_end_steps(), "out.off", "--threads 1");
  const ToolRun two = run_octree_script("threads2", bunny, end_to_end_steps(), "out.off", "--threads 2");
  ASSERT_EQ(one.code, 0) << one.err;
  ASSERT_EQ(two.code, 0) << two.err;
  for (const std::string file : {"out.off", "mesh.off", "lat2.obj", "lat3.obj"}) {
    const std::string a = read_file(one.dir + "/" + file);
    EXPECT_FALSE(a.empty()) << file;
    EXPECT_TRUE(a == read_file(two.dir + "/" + file)) << file << " differs between --threads 1 and 2";
  }
  EXPECT_EQ(step_counts(one.stats), step_counts(two.stats));
}

TEST(MultiresCli, ALevel4PointMovesOnlyVerticesNearIt) {
  SHARED_MESH_OR_SKIP(bunny, "bunny00.off");
  const Mesh input = read_mesh(bunny);
  const Eigen::Vector3d at = input.positions().col(100);
  const ToolRun r = run_octree_script("locality", bunny,
                                      {kOctreeLattice, R"({"op": "move", "lattice": "auto", "level": 4, "select": {"near": )" +
                                          vec(at) + R"(}, "transform": {"translate": [0, 0.03, 0]}})"});
  ASSERT_EQ(r.code, 0) << r.err;
  const json& move = r.stats["steps"][1];
  check_move(move, 4);
  const std::vector<std::uint32_t> changed = changed_vertices(input, read_mesh(r.dir + "/out.off"));
  EXPECT_GT(changed.size(), 200u);
  EXPECT_LT(changed.size(), 5000u);
  EXPECT_NE(std::find(changed.begin(), changed.end(), 100u), changed.end())
      << "the vertex at the moved point stayed";
  EXPECT_LE(changed.size(), move["vertices_moved"].get<std::size_t>())
      << "vertices_moved (re-evaluated) should bound the vertices that changed";
  EXPECT_LT(move["vertices_moved"].get<std::size_t>(), input.num_vertices() / 4);
}

// The box in the stats, as origin + axes columns.
bool inside_box(const json& box, const Eigen::Vector3d& p, double slack) {
  Eigen::Matrix3d axes;
  for (int a = 0; a < 3; ++a)
    for (int c = 0; c < 3; ++c) axes(c, a) = box["axes"][a][c].get<double>();
  const Eigen::Vector3d origin(box["origin"][0].get<double>(), box["origin"][1].get<double>(),
                               box["origin"][2].get<double>());
  const Eigen::Vector3d u = axes.inverse() * (p - origin);
  return (u.array() >= -slack).all() && (u.array() <= 1 + slack).all();
}

TEST(MultiresCli, EnclosingLatticeCarriesTheLocalOne) {
  SHARED_MESH_OR_SKIP(bunny, "bunny00.off");
  const ToolRun r = run_octree_script(
      "enclose", bunny,
      {kOctreeLattice, R"({"op": "move", "lattice": "auto", "level": 3, "points": [{"index": [4, 4, 4], "by": [0.02, 0, 0.01]}]})",
       R"({"op": "save", "path": "before.obj", "lattice": "auto", "level": 3})", R"({"op": "save", "path": "local.off"})",
       R"({"op": "lattice", "name": "global", "basis": "octree", "enclose": "auto", "levels": 1})",
       R"({"op": "save", "path": "mid.obj", "lattice": "auto", "level": 3})",
       R"({"op": "move", "lattice": "global", "level": 1, "points": [{"index": [1, 1, 1], "by": [0, 0.1, 0]}]})",
       R"({"op": "save", "path": "after.obj", "lattice": "auto", "level": 3})"});
  ASSERT_EQ(r.code, 0) << r.err;
  const json& global = r.stats["steps"][4];
  EXPECT_EQ(global["enclose"], "auto");
  check_levels(global, 1);
  const Net before = read_net(r.dir + "/before.obj"), mid = read_net(r.dir + "/mid.obj"),
            after = read_net(r.dir + "/after.obj");
  ASSERT_EQ(before.points.size(), r.stats["steps"][0]["levels"][3]["points"].get<std::size_t>());
  ASSERT_EQ(mid.points.size(), before.points.size());
  ASSERT_EQ(after.points.size(), before.points.size());
  EXPECT_EQ(after.edges, before.edges);
  std::size_t differ = 0, outside = 0;
  for (std::size_t p = 0; p < before.points.size(); ++p) {
    EXPECT_TRUE(mid.points[p] == before.points[p]) << "an unmoved enclosing lattice moved auto's point " << p;
    differ += !(after.points[p] == before.points[p]);
    EXPECT_LE((after.points[p] - before.points[p]).norm(), 0.1 + 1e-12) << "point " << p;
    outside += !inside_box(global["box"], before.points[p], 1e-9);
  }
  EXPECT_GT(differ, before.points.size() / 2) << "global's move should carry auto's net";
  EXPECT_EQ(outside, 0u) << "the enclosing box should hold auto's points";
  const std::vector<std::uint32_t> changed =
      changed_vertices(read_mesh(r.dir + "/local.off"), read_mesh(r.dir + "/out.off"));
  EXPECT_GT(changed.size(), 37706u / 2) << "global's level-1 move should move the mesh";
}

struct BadOctreeScript {
  std::string name;
  std::vector<std::string> steps;
  std::vector<std::string> parts;  // what the error line must mention
};

std::vector<BadOctreeScript> bad_scripts() {
  const std::string small = R"({"op": "lattice", "name": "auto", "basis": "octree", "levels": 3})";
  const std::string zero = R"(, "points": [{"index": [1, 1, 1], "by": [0, 0, 0]}]})";
  return {
      {"cells", {R"({"op": "lattice", "name": "auto", "basis": "octree", "cells": [4, 4, 4]})"}, {"/steps/0/cells"}},
      {"level_range", {small, R"({"op": "move", "lattice": "auto", "level": -1)" + zero}, {"/steps/1/level", "0"}},
      {"levels_range", {R"({"op": "lattice", "name": "auto", "basis": "octree", "levels": 7})"}, {"/steps/0/levels", "6"}},
      {"subdivide_local", {small, R"({"op": "subdivide", "lattice": "auto", "level": 1, "cells": {"indices": [[0, 0, 0]]}})",
                           R"({"op": "subdivide", "lattice": "auto", "level": 4, "cells": {"indices": [[0, 0, 0]]}})"},
       {"/steps/2/level", "cannot be subdivided again"}},
      {"subdivide_bspline", {R"({"op": "lattice", "name": "b", "cells": [4, 4, 4]})",
                             R"({"op": "subdivide", "lattice": "b", "cells": {"near": [0, 0, 0]}})"},
       {"/steps/1/lattice", "octree"}},
      {"level_above", {small, R"({"op": "move", "lattice": "auto", "level": 4)" + zero}, {"/steps/1/level", "auto"}},
      {"index", {small, R"({"op": "move", "lattice": "auto", "level": 2, "points": [{"index": [1, 5, 1], "by": [0, 0, 0]}]})"},
       {"/steps/1/points/0/index", "[1,5,1]"}},
      {"shrink", {R"({"op": "lattice", "name": "b", "cells": [4, 4, 4], "shrink": 0.01})"}, {"/steps/0/shrink"}},
      {"net_off", {small, R"({"op": "save", "path": "net.off", "lattice": "auto", "level": 2})"}, {"/steps/1/path", ".obj"}},
      {"enclose", {small, R"({"op": "lattice", "name": "g", "basis": "octree", "enclose": "nope", "levels": 1})"},
       {"/steps/1/enclose", "nope"}},
      // Found only when running: [8, 8, 8] of level 4 is inside the bunny, its cells cut.
      {"cut_point", {kOctreeLattice, R"({"op": "save", "path": "net.obj", "lattice": "auto"})",
                     R"({"op": "move", "lattice": "auto", "level": 4, "points": [{"index": [8, 8, 8], "by": [0, 0, 0.1]}]})"},
       {"/steps/2/points/0/index", "[8,8,8]"}},
  };
}

TEST(MultiresCli, BadOctreeScriptsAreInputErrorsThatWriteNothing) {
  SHARED_MESH_OR_SKIP(bunny, "bunny00.off");
  for (const BadOctreeScript& bad : bad_scripts()) {
    SCOPED_TRACE(bad.name);
    const std::string dir = temp_folder("multires_bad_" + bad.name);
    write_file(dir + "/s.json", script(bad.steps));
    std::string err;
    EXPECT_EQ(run_tool("run " + quoted(bunny) + " " + quoted(dir + "/s.json") + " -o " + quoted(dir + "/out.off") + " --quiet",
                       nullptr, &err),
              2);
    expect_one_error_line(err, bad.parts);
    EXPECT_EQ(files_in(dir), std::set<std::string>{"s.json"});
  }
}

TEST(MultiresCli, DragAtALevelReachesItsTarget) {
  SHARED_MESH_OR_SKIP(bunny, "bunny00.off");
  const Mesh input = read_mesh(bunny);
  const Eigen::Vector3d target = input.positions().col(100) + Eigen::Vector3d(0.01, 0.02, -0.01);
  const ToolRun r = run_octree_script(
      "drag", bunny,
      {kOctreeLattice, R"({"op": "drag", "lattice": "auto", "level": 3, "points": [{"vertex": 100, "to": )" + vec(target) + "}]}"});
  ASSERT_EQ(r.code, 0) << r.err;
  const json& drag = r.stats["steps"][1];
  EXPECT_EQ(drag["level"], 3);
  EXPECT_EQ(drag["unreachable"], 0);
  EXPECT_GT(drag["points_changed"].get<long>(), 0);
  EXPECT_LT(drag["residual_max"].get<double>(), 1e-9);
  const Mesh out = read_mesh(r.dir + "/out.off");
  ASSERT_EQ(out.num_vertices(), input.num_vertices());
  EXPECT_LT((out.positions().col(100) - target).norm(), 1e-6)
      << "vertex 100 at " << out.positions().col(100).transpose() << ", target " << target.transpose();
  EXPECT_LT(changed_vertices(input, out).size(), input.num_vertices()) << "a level-3 drag moved every vertex";
}

TEST(MultiresCli, FiveLevelsOnOtherMeshesCutCells) {
  for (const std::string name : {"armadillo.off", "refined_elephant.off"}) {
    SCOPED_TRACE(name);
    SHARED_MESH_OR_SKIP(mesh, name);
    const ToolRun r = run_octree_script(
        "levels5_" + name, mesh,
        {R"({"op": "lattice", "name": "auto", "basis": "octree", "box": {"fit": "obb", "padding": 0.02}, "levels": 5,
             "shrink": 0.002})",
         R"({"op": "move", "lattice": "auto", "level": 5, "select": {"near": [0, 0, 0]},
             "transform": {"translate": [0, 0.01, 0]}})"});
    ASSERT_EQ(r.code, 0) << r.err;
    const json& lattice = r.stats["steps"][0];
    check_levels(lattice, 5);
    EXPECT_GT(lattice["levels"][5]["cut_cells"].get<long>(), 0);
    EXPECT_EQ(lattice["vertices_inside"], r.stats["input"]["vertices"]);
    const json& move = r.stats["steps"][1];
    check_move(move, 5);
    EXPECT_LT(move["vertices_moved"].get<std::size_t>(), r.stats["input"]["vertices"].get<std::size_t>());
  }
}

// CGAL's elephant (libcgal-demo, installed by scripts/setup.sh, so this runs on CI too):
// local subdivision of a level through the CLI, the new level moved, its net saved.
TEST(MultiresCli, LocalSubdivisionOfCgalsElephant) {
  const std::string mesh = test::cgal_mesh("elephant.off");
  if (mesh.empty()) GTEST_SKIP() << "libcgal-demo is not installed";
  const Mesh input = read_mesh(mesh);
  const std::string lattice =
      R"({"op": "lattice", "name": "auto", "basis": "octree", "box": {"fit": "obb", "padding": 0.02}, "levels": 3})";
  const std::string subdivide = R"({"op": "subdivide", "lattice": "auto", "level": 2, "cells": {"indices": [[1, 1, 1], [2, 1, 1]]}})";
  // Subdividing moves nothing, even after the coarser level moved: the new level starts
  // from the level as shown.
  const ToolRun still = run_octree_script("subdivide_still", mesh,
                                          {lattice, R"({"op": "move", "lattice": "auto", "level": 4, "points": [{"index": [4, 4, 4], "by": [0, 0, 0]}]})", subdivide},
                                   "out.off");
  ASSERT_NE(still.code, 0) << "level 4 does not exist before the subdivide step";
  const ToolRun zero = run_octree_script("subdivide_zero", mesh,
                                         {lattice, subdivide, R"({"op": "move", "lattice": "auto", "level": 4, "points": [{"index": [4, 4, 4], "by": [0, 0, 0]}]})"});
  ASSERT_EQ(zero.code, 0) << zero.err;
  EXPECT_TRUE(changed_vertices(input, read_mesh(zero.dir + "/out.off")).empty());
  const ToolRun r = run_octree_script(
      "subdivide_elephant", mesh,
      {lattice, subdivide,
       R"({"op": "move", "lattice": "auto", "level": 4, "points": [{"index": [4, 3, 3], "by": [0.0, 0.03, 0.0]}]})",
       R"({"op": "save", "path": "net.obj", "lattice": "auto", "level": 4})",
       R"({"op": "remesh", "theta_max_deg": 25.7, "theta_min_deg": 20.0})"});
  ASSERT_EQ(r.code, 0) << r.err;
  const json& step = r.stats["steps"][1];
  EXPECT_EQ(step["new_level"], 4);
  EXPECT_EQ(step["cells_subdivided"], 2);
  EXPECT_EQ(step["cell_ids"], json::parse("[[1, 1, 1], [2, 1, 1]]"));
  const json& cells = r.stats["steps"][0]["levels"][2]["cells"];
  EXPECT_EQ(step["cells"].get<long>(), cells.get<long>() - 2 + 16);
  const std::string net = read_file(r.dir + "/net.obj");
  long v_lines = 0;
  std::istringstream lines(net);
  for (std::string line; std::getline(lines, line);) v_lines += line.rfind("v ", 0) == 0;
  EXPECT_EQ(v_lines, step["points"].get<long>());
  EXPECT_GT(r.stats["steps"][2]["vertices_moved"].get<long>(), 0);
}

}  // namespace
}  // namespace ffd
