// The bcm and transform ops end to end through ffdtool: the bundled bunny against a
// checked-in expected mesh, frames saved as an animation, determinism, and bad input
// (exit 2, one line naming the script and the JSON pointer, nothing written).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "common/errors.h"
#include "mesh/mesh_io.h"
#include "mesh/vertex_normals.h"
#include "script/runner.h"
#include "script/script.h"
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

std::string run_args(const std::string& mesh, const std::string& script, const std::string& dir, const std::string& extra = "") {
  return "run " + quoted(mesh) + " " + quoted(script) + " -o " + quoted(dir + "/out.obj") + " --stats " + quoted(dir + "/stats.json") +
         (extra.empty() ? "" : " " + extra);
}

const Eigen::Vector3d kBack(1.24, 6.29, 1.05), kEar(0.0, 9.65, -1.36);

Eigen::Matrix3Xd vertex_normals_of(const Mesh& mesh) { return vertex_normals(mesh, mesh.positions()); }

TEST(BcmCli, BunnyEditMatchesTheExpectedMesh) {
  const std::string dir = temp_folder("bcm_cli_bunny");
  std::string out, err;
  ASSERT_EQ(run_tool(run_args(data("bunny.obj"), data("bcm_bunny.json"), dir), &out, &err), 0) << err;
  EXPECT_EQ(files_in(dir), (std::set<std::string>{"out.obj", "stats.json"}));
  EXPECT_NE(err.find("[0] bcm 'back': k=3 cotan with detail, 220 free / 14 handle / 269 fixed vertices"), std::string::npos)
      << err;
  EXPECT_NE(err.find("[1] transform 'back' handle 'hump': 1 frame"), std::string::npos) << err;

  std::string cmp;
  EXPECT_EQ(run_tool("compare " + quoted(dir + "/out.obj") + " " + quoted(data("expected/bcm_bunny.obj")) + " --tolerance 1e-8", &cmp), 0)
      << cmp;

  // A valid mesh: same vertices and faces, finite; only the two supports moved, and they
  // moved for real.
  const Mesh input = test::bunny(), output = read_mesh(dir + "/out.obj");
  ASSERT_EQ(output.num_vertices(), input.num_vertices());
  ASSERT_EQ(output.faces(), input.faces());
  EXPECT_TRUE(output.positions().allFinite());
  double back_moved = 0, ear_moved = 0;
  for (Eigen::Index v = 0; v < input.positions().cols(); ++v) {
    const Eigen::Vector3d p = input.positions().col(v);
    const double moved = (output.positions().col(v) - p).norm();
    if ((p - kBack).norm() > 3.0 && (p - kEar).norm() > 2.2) {
      EXPECT_EQ(moved, 0.0) << "vertex " << v << " lies outside both supports";
    }
    if ((p - kBack).norm() <= 0.7) back_moved = std::max(back_moved, moved);
    if ((p - kEar).norm() <= 0.5) ear_moved = std::max(ear_moved, moved);
  }
  EXPECT_GT(back_moved, 0.7);
  EXPECT_GT(ear_moved, 0.5);

  const json stats = json::parse(read_file(dir + "/stats.json"));
  ASSERT_EQ(stats["steps"].size(), 4u);
  const json& bcm = stats["steps"][0];
  EXPECT_EQ(bcm["op"], "bcm");
  EXPECT_EQ(bcm["free_vertices"], 220);
  EXPECT_EQ(bcm["handle_vertices"], 14);
  EXPECT_EQ(bcm["fixed_vertices"], 269);
  EXPECT_EQ(bcm["solver"], "supernodal Cholesky");
  for (const char* key : {"factorization_ms", "basis_ms", "laplacian_ms", "system_ms"}) EXPECT_TRUE(bcm[key].is_number()) << key;
  const json& transform = stats["steps"][1];
  EXPECT_EQ(transform["frames"], 1);
  EXPECT_EQ(transform["vertices_moved"], 234);
  EXPECT_TRUE(transform["frame_ms"].is_number());
  EXPECT_EQ(stats["steps"][2]["continuity"], (json{{"outer", 1.0}, {"inner", 0.0}}));
}

TEST(BcmCli, IsDeterministicWhateverTheThreadCount) {
  std::string first_mesh;
  json first_stats;
  for (const char* threads : {"1", "2", "2"}) {
    const std::string dir = temp_folder(std::string("bcm_cli_threads_") + threads);
    ASSERT_EQ(run_tool(run_args(data("bunny.obj"), data("bcm_bunny.json"), dir, std::string("--quiet --threads ") + threads)), 0);
    const std::string mesh = read_file(dir + "/out.obj");
    json stats = without_measurements(json::parse(read_file(dir + "/stats.json")));
    stats.erase("threads");
    stats["output"].erase("mesh");  // the folder differs
    if (first_mesh.empty()) {
      first_mesh = mesh;
      first_stats = stats;
    } else {
      EXPECT_EQ(mesh, first_mesh) << "--threads " << threads;
      EXPECT_EQ(stats, first_stats);
    }
  }
}

// Frames are poses relative to setup, each saved; the last one is the output; any frame
// equals a single transform to the same pose.
TEST(BcmCli, FramesSaveAnAnimation) {
  const std::string setup = R"({"op": "bcm", "name": "back", "support": {"sphere": {"center": [1.24, 6.29, 1.05], "radius": 3.0}},
      "handles": [{"name": "hump", "select": {"sphere": {"center": [1.24, 6.29, 1.05], "radius": 0.7}}}], "k": 2})";
  const std::string dir = temp_folder("bcm_cli_frames");
  write_file(dir + "/frames.json", script_with(setup + R"(, {"op": "transform", "editor": "back",
      "frames": [{"translate": [0, 0.2, 0]}, {"translate": [0, 0.4, 0], "scale": 1.1}, {"translate": [0, 0.6, 0]}],
      "save": "frame_{i}.obj"})"));
  std::string err;
  ASSERT_EQ(run_tool(run_args(data("bunny.obj"), dir + "/frames.json", dir), nullptr, &err), 0) << err;
  for (const char* name : {"frame_0.obj", "frame_1.obj", "frame_2.obj"}) EXPECT_TRUE(fs::exists(dir + "/" + name)) << name;
  EXPECT_EQ(read_file(dir + "/frame_2.obj"), read_file(dir + "/out.obj"));
  EXPECT_NE(read_file(dir + "/frame_0.obj"), read_file(dir + "/frame_1.obj"));
  const json stats = json::parse(read_file(dir + "/stats.json"));
  EXPECT_EQ(stats["steps"][1]["frames"], 3);
  EXPECT_EQ(stats["steps"][1]["saved"], (json{"frame_0.obj", "frame_1.obj", "frame_2.obj"}));

  const std::string one = temp_folder("bcm_cli_one_frame");
  write_file(one + "/one.json", script_with(setup + R"(, {"op": "transform", "editor": "back",
      "transform": {"translate": [0, 0.4, 0], "scale": 1.1}})"));
  ASSERT_EQ(run_tool(run_args(data("bunny.obj"), one + "/one.json", one)), 0);
  std::string cmp;
  EXPECT_EQ(run_tool("compare " + quoted(one + "/out.obj") + " " + quoted(dir + "/frame_1.obj") + " --tolerance 1e-12", &cmp), 0) << cmp;
}

// ---------------------------------------------------------------------------------------
// Bad input.

struct BadScript {
  const char* name;
  std::string mesh;    // file name in test_data, or OBJ text written to the input folder
  std::string script;
  std::vector<std::string> mentions;
};

// A 4 × 4 grid of unit squares (triangles) and, far away, a separate triangle.
std::string two_pieces() {
  std::string s;
  for (int j = 0; j <= 4; ++j)
    for (int i = 0; i <= 4; ++i) s += "v " + std::to_string(i) + " " + std::to_string(j) + " 0\n";
  s += "v 10 10 0\nv 11 10 0\nv 10 11 0\n";
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) {
      const int a = j * 5 + i + 1, b = a + 1, c = a + 6, d = a + 5;
      s += "f " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(c) + "\n";
      s += "f " + std::to_string(a) + " " + std::to_string(c) + " " + std::to_string(d) + "\n";
    }
  return s + "f 26 27 28\n";
}


const char* kBackEditor = R"({"op": "bcm", "name": "back", "support": {"sphere": {"center": [1.24, 6.29, 1.05], "radius": 3.0}},
    "handles": [{"name": "hump", "select": {"sphere": {"center": [1.24, 6.29, 1.05], "radius": 0.7}}}]})";
const char* kTwoHandles = R"({"op": "bcm", "name": "back", "support": {"sphere": {"center": [1.24, 6.29, 1.05], "radius": 3.0}},
    "handles": [{"name": "a", "select": {"near": [1.24, 6.29, 1.05]}}, {"name": "b", "select": {"near": [1.24, 4.0, 2.0]}}]})";

TEST(BcmCli, BadInputExitsTwoWithOneLineNamingThePlaceAndWritesNothing) {
  const std::string back = kBackEditor;
  const std::vector<BadScript> cases = {
      {"handle outside the support", "bunny.obj",
       script_with(R"({"op": "bcm", "name": "e", "support": {"sphere": {"center": [1.24, 6.29, 1.05], "radius": 1.0}},
          "handles": [{"name": "h", "select": {"sphere": {"center": [0, 9.65, -1.36], "radius": 0.5}}}]})"),
       {"/steps/0/handles/0/select:", "outside the support"}},
      {"empty support", "bunny.obj",
       script_with(R"({"op": "bcm", "name": "e", "support": {"sphere": {"center": [100, 0, 0], "radius": 1.0}},
          "handles": [{"name": "h", "select": {"near": [0, 0, 0]}}]})"),
       {"/steps/0/support:", "picks no mesh vertex"}},
      {"empty handle", "bunny.obj",
       script_with(R"({"op": "bcm", "name": "e", "support": {"sphere": {"center": [1.24, 6.29, 1.05], "radius": 1.0}},
          "handles": [{"name": "h", "select": {"box": {"min": [50, 50, 50], "max": [51, 51, 51]}}}]})"),
       {"/steps/0/handles/0/select:", "picks no mesh vertex"}},
      {"overlapping handles", "bunny.obj",
       script_with(R"({"op": "bcm", "name": "e", "support": {"sphere": {"center": [1.24, 6.29, 1.05], "radius": 2.0}},
          "handles": [{"name": "a", "select": {"near": [1.24, 6.29, 1.05]}}, {"name": "b", "select": {"near": [1.24, 6.29, 1.05]}}]})"),
       {"/steps/0/handles/1/select:", "overlap"}},
      {"handles cover the support", "bunny.obj",
       script_with(R"({"op": "bcm", "name": "e", "support": {"near": [1.24, 6.29, 1.05]},
          "handles": [{"name": "a", "select": {"near": [1.24, 6.29, 1.05]}}]})"),
       {"/steps/0/support:", "no vertex is left free"}},
      {"a part of the support touches nothing", two_pieces(),
       script_with(R"({"op": "bcm", "name": "e", "support": [{"box": {"min": [0, 0, -1], "max": [2, 2, 1]}},
          {"box": {"min": [9, 9, -1], "max": [12, 12, 1]}}], "handles": [{"name": "h", "select": {"near": [1, 1, 0]}}]})"),
       {"/steps/0/support:", "touches no fixed or handle vertex", "3 free vertices"}},
      {"quads in the support", test::grid_obj(8, true),
       script_with(R"({"op": "bcm", "name": "e", "support": {"box": {"min": [2, 2, -1], "max": [6, 6, 1]}},
          "handles": [{"name": "h", "select": {"near": [4, 4, 0]}}]})"),
       {"/steps/0/support:", "4 sides", "triangles"}},
      {"anisotropic on an annulus", test::grid_obj(12),
       script_with(R"({"op": "bcm", "name": "e", "laplacian": "anisotropic", "k": 1,
          "support": [{"box": {"min": [1, 1, -1], "max": [11, 3, 1]}}, {"box": {"min": [1, 9, -1], "max": [11, 11, 1]}},
                      {"box": {"min": [1, 1, -1], "max": [3, 11, 1]}}, {"box": {"min": [9, 1, -1], "max": [11, 11, 1]}}],
          "handles": [{"name": "h", "select": {"near": [2, 6, 0]}}]})"),
       {"/steps/0/laplacian:", "topological disk", "2 boundary loops"}},
      {"continuity above k - 1", "bunny.obj",
       script_with(R"({"op": "bcm", "name": "e", "k": 2, "continuity": {"outer": 1.5},
          "support": {"near": [0, 0, 0]}, "handles": [{"name": "h", "select": {"near": [0, 0, 0]}}]})"),
       {"/steps/0/continuity/outer:", "at most k - 1 = 1"}},
      {"negative continuity", "bunny.obj",
       script_with(R"({"op": "bcm", "name": "e", "continuity": {"inner": -1},
          "support": {"near": [0, 0, 0]}, "handles": [{"name": "h", "select": {"near": [0, 0, 0]}}]})"),
       {"/steps/0/continuity/inner:", "at least 0"}},
      {"k out of range", "bunny.obj",
       script_with(R"({"op": "bcm", "name": "e", "k": 4, "support": {"near": [0, 0, 0]}, "handles": [{"name": "h", "select": {"near": [0, 0, 0]}}]})"),
       {"/steps/0/k:", "at most 3"}},
      {"duplicate handle names", "bunny.obj",
       script_with(R"({"op": "bcm", "name": "e", "support": {"near": [0, 0, 0]},
          "handles": [{"name": "h", "select": {"near": [0, 0, 0]}}, {"name": "h", "select": {"near": [1, 0, 0]}}]})"),
       {"/steps/0/handles/1/name:", "already has a handle named 'h'"}},
      {"unknown editor", "bunny.obj", script_with(R"({"op": "transform", "editor": "nope", "transform": {"translate": [0, 1, 0]}})"),
       {"/steps/0/editor:", "no bcm editor named 'nope'"}},
      {"unknown handle", "bunny.obj",
       script_with(back + R"(, {"op": "transform", "editor": "back", "handle": "tail", "transform": {"translate": [0, 1, 0]}})"),
       {"/steps/1/handle:", "no handle named 'tail'", "'hump'"}},
      {"handle left out with two handles", "bunny.obj",
       script_with(std::string(kTwoHandles) + R"(, {"op": "transform", "editor": "back", "transform": {"translate": [0, 1, 0]}})"),
       {"/steps/1:", "missing key 'handle'", "'a', 'b'"}},
      {"transform and frames both", "bunny.obj",
       script_with(back + R"(, {"op": "transform", "editor": "back", "transform": {}, "frames": [{}]})"),
       {"/steps/1:", "give only one of 'transform', or 'frames'"}},
      {"save pattern without {i}", "bunny.obj",
       script_with(back + R"(, {"op": "transform", "editor": "back", "frames": [{}, {"translate": [0, 1, 0]}], "save": "frame.obj"})"),
       {"/steps/1/save:", "has no '{i}'"}},
      {"save pattern without a mesh extension", "bunny.obj",
       script_with(back + R"(, {"op": "transform", "editor": "back", "frames": [{}], "save": "frame_{i}.txt"})"),
       {"/steps/1/save:", "no mesh extension"}},
      {"zero rotation axis in a frame", "bunny.obj",
       script_with(back + R"(, {"op": "transform", "editor": "back",
          "frames": [{}, {"rotate": {"axis": [0, 0, 0], "degrees": 10}}]})"),
       {"/steps/1/frames/1/rotate/axis:", "zero"}},
      {"the editor's surface moved by a lattice after setup (found at run time, after a frame save)", "bunny.obj",
       script_with(back + R"(, {"op": "transform", "editor": "back", "frames": [{"translate": [0, 0.2, 0]}], "save": "early_{i}.obj"},
          {"op": "lattice", "name": "body", "cells": [4, 4, 4]},
          {"op": "move", "lattice": "body", "points": [{"index": [2, 2, 2], "by": [0, 1, 0]}]},
          {"op": "transform", "editor": "back", "transform": {"translate": [0, 0.5, 0]}})"),
       {"/steps/4/editor:", "moved by a step after the editor was set up", "set the editor up again"}},
  };
  for (const BadScript& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string in = temp_folder("bcm_bad_in"), out = temp_folder("bcm_bad_out");
    std::string mesh = c.mesh;
    if (mesh.find('\n') != std::string::npos) {
      write_file(in + "/mesh.obj", mesh);
      mesh = in + "/mesh.obj";
    } else {
      mesh = test::data(mesh);
    }
    write_file(in + "/script.json", c.script);
    std::string stdout_text, err;
    EXPECT_EQ(run_tool(run_args(mesh, in + "/script.json", out, "--quiet"), &stdout_text, &err), 2) << err;
    EXPECT_EQ(err.rfind("ffdtool: error: " + in + "/script.json: ", 0), 0u) << err;
    EXPECT_EQ(err.find('\n'), err.size() - 1) << "not one line:\n" << err;
    for (const std::string& part : c.mentions) EXPECT_NE(err.find(part), std::string::npos) << "no '" << part << "' in: " << err;
    EXPECT_TRUE(files_in(out).empty()) << "files were written";
  }
}

TEST(BcmCli, AFramePathThatNamesTheInputMeshIsRefusedBeforeAnyWork) {
  const std::string dir = temp_folder("bcm_frame_input");
  const std::string bunny = read_file(data("bunny.obj"));
  write_file(dir + "/frame_1.obj", bunny);
  write_file(dir + "/script.json",
             script_with(std::string(kBackEditor) + R"(, {"op": "transform", "editor": "back",
                 "frames": [{}, {"translate": [0, 0.5, 0]}], "save": "frame_{i}.obj"})"));
  std::string err;
  EXPECT_EQ(run_tool(run_args(dir + "/frame_1.obj", dir + "/script.json", dir, "--quiet"), nullptr, &err), 2);
  EXPECT_NE(err.find("/steps/1: '" + dir + "/frame_1.obj' would overwrite an input file"), std::string::npos) << err;
  EXPECT_EQ(files_in(dir), (std::set<std::string>{"frame_1.obj", "script.json"}));
  EXPECT_EQ(read_file(dir + "/frame_1.obj"), bunny);
}

// A remesh (or any step that changes connectivity) between setup and a transform: the
// editor's vertex sets no longer apply.
TEST(BcmCli, TransformAfterAConnectivityChangeIsAnInputError) {
  Scene scene;
  scene.mesh = test::bunny();
  scene.output_folder = temp_folder("bcm_topology");
  const Script script = parse_script(script_with(std::string(kBackEditor) +
                                                 R"(, {"op": "transform", "editor": "back", "transform": {"translate": [0, 1, 0]}})"),
                                     "s.json");
  StepContext setup;
  setup.pointer = "/steps/0";
  run_step(script, *script.steps[0], scene, setup);
  EXPECT_EQ(setup.stats["free_vertices"], 220);
  scene.mesh.mark_topology_changed();
  StepContext transform;
  transform.pointer = "/steps/1";
  try {
    run_step(script, *script.steps[1], scene, transform);
    FAIL() << "a stale editor moved a handle";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("s.json: /steps/1/editor: ", 0), 0u) << what;
    EXPECT_NE(what.find("connectivity"), std::string::npos) << what;
    EXPECT_NE(what.find("set the editor up again"), std::string::npos) << what;
  }
}

// Figure 1 from scripts: C^2 at both boundaries, C^0 at the handle, C^0 at the support's
// edge (k = 3 on a plane grid, the handle lifted). Hinging a boundary makes the surface
// leave it at a slope; clamping makes it leave flat.
TEST(BcmCli, FigureOneConfigurationsFromScripts) {
  constexpr int n = 30;
  const std::string dir = temp_folder("bcm_figure1");
  write_file(dir + "/grid.obj", test::grid_obj(n));
  struct Shape {
    double outer_slope = 0, inner_drop = 0;
  };
  const auto run = [&](int outer, int inner) {
    const std::string name = "c" + std::to_string(outer) + std::to_string(inner);
    write_file(dir + "/" + name + ".json",
               script_with(R"({"op": "bcm", "name": "e", "k": 3, "detail": false,
                  "continuity": {"outer": )" + std::to_string(outer) + R"(, "inner": )" + std::to_string(inner) + R"(},
                  "support": {"sphere": {"center": [15, 15, 0], "radius": 11}},
                  "handles": [{"name": "h", "select": {"sphere": {"center": [15, 15, 0], "radius": 3}}}]},
                  {"op": "transform", "editor": "e", "transform": {"translate": [0, 0, 4]}})"));
    std::string err;
    EXPECT_EQ(run_tool("run " + quoted(dir + "/grid.obj") + " " + quoted(dir + "/" + name + ".json") + " -o " + quoted(dir + "/" + name + ".obj") +
                           " --quiet",
                       nullptr, &err),
              0)
        << err;
    const Mesh mesh = read_mesh(dir + "/" + name + ".obj");
    Shape shape;
    int outer_count = 0, inner_count = 0;
    for (int j = 1; j < n; ++j)
      for (int i = 1; i < n; ++i) {
        const double r = std::hypot(i - 15.0, j - 15.0);
        const double z = mesh.positions()(2, j * (n + 1) + i);
        if (r <= 11 && r > 10) {  // free, next to the fixed surface
          shape.outer_slope += z;
          ++outer_count;
        }
        if (r > 3 && r <= 4) {  // free, next to the handle
          shape.inner_drop += 4 - z;
          ++inner_count;
        }
      }
    shape.outer_slope /= outer_count;
    shape.inner_drop /= inner_count;
    return shape;
  };
  const Shape both = run(2, 2), hinged_handle = run(2, 0), hinged_edge = run(0, 2);
  EXPECT_GT(hinged_handle.inner_drop, 2 * both.inner_drop);
  EXPECT_GT(hinged_edge.outer_slope, 2 * both.outer_slope);
  EXPECT_GT(both.inner_drop, 0);
  EXPECT_GT(both.outer_slope, 0);
}

// A mesh's own normals (OBJ vn) turn with the edited surface: each corner's normal at a
// vertex whose faces moved is turned like the vertex normal, elsewhere it stays.
TEST(BcmCli, FileNormalsFollowTheEdit) {
  constexpr int n = 16;
  const std::string dir = temp_folder("bcm_file_normals");
  std::string obj = "vn 0 0 1\n";
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) obj += "v " + std::to_string(i) + " " + std::to_string(j) + " 0\n";
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i + 1, b = a + 1, c = a + n + 2, d = a + n + 1;
      obj += "f " + std::to_string(a) + "//1 " + std::to_string(b) + "//1 " + std::to_string(c) + "//1\n";
      obj += "f " + std::to_string(a) + "//1 " + std::to_string(c) + "//1 " + std::to_string(d) + "//1\n";
    }
  write_file(dir + "/grid.obj", obj);
  write_file(dir + "/s.json", script_with(R"({"op": "bcm", "name": "e", "k": 2,
      "support": {"sphere": {"center": [8, 8, 0], "radius": 5}},
      "handles": [{"name": "h", "select": {"sphere": {"center": [8, 8, 0], "radius": 1.5}}}]},
      {"op": "transform", "editor": "e", "transform": {"translate": [0, 0, 3], "rotate": {"axis": [1, 0, 0], "degrees": 20}}})"));
  std::string err;
  ASSERT_EQ(run_tool("run " + quoted(dir + "/grid.obj") + " " + quoted(dir + "/s.json") + " -o " + quoted(dir + "/out.obj") + " --quiet", nullptr, &err), 0)
      << err;
  // Parse the output: vertex positions, the normal table, each corner's (vertex, normal).
  std::vector<Eigen::Vector3d> normals;
  std::vector<std::pair<int, int>> corners;
  std::istringstream lines(read_file(dir + "/out.obj"));
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream tokens(line);
    std::string kind;
    tokens >> kind;
    if (kind == "vn") {
      Eigen::Vector3d v;
      tokens >> v.x() >> v.y() >> v.z();
      normals.push_back(v);
    } else if (kind == "f") {
      std::string corner;
      while (tokens >> corner)
        corners.emplace_back(std::stoi(corner.substr(0, corner.find('/'))) - 1, std::stoi(corner.substr(corner.rfind('/') + 1)) - 1);
    }
  }
  const Mesh out = read_mesh(dir + "/out.obj");
  const Eigen::Matrix3Xd vertex_normals = vertex_normals_of(out);
  int turned = 0;
  for (const auto& [v, k] : corners) {
    const Eigen::Vector3d file = normals.at(static_cast<std::size_t>(k));
    const Eigen::Vector3d q = out.positions().col(v);
    if (std::hypot(q.x() - 8, q.y() - 8) > 7) {
      EXPECT_LT((file - Eigen::Vector3d::UnitZ()).norm(), 1e-6) << "vertex " << v;  // far from the edit
    } else {
      EXPECT_LT((file - vertex_normals.col(v)).norm(), 1e-5) << "vertex " << v;  // turned with the surface
      turned += file.z() < 0.99;
    }
  }
  EXPECT_GT(turned, 50);
}

TEST(BcmCli, ValidateFillsTheDefaults) {
  const std::string dir = temp_folder("bcm_validate");
  write_file(dir + "/s.json", script_with(std::string(kBackEditor) + R"(, {"op": "transform", "editor": "back", "transform": {}})"));
  std::string out, err;
  ASSERT_EQ(run_tool("validate --resolved " + quoted(dir + "/s.json"), &out, &err), 0) << err;
  const json resolved = json::parse(out);
  const json& bcm = resolved["steps"][0];
  EXPECT_EQ(bcm["k"], 3);
  EXPECT_EQ(bcm["laplacian"], "cotan");
  EXPECT_EQ(bcm["detail"], true);
  std::string schema;
  ASSERT_EQ(run_tool("schema", &schema), 0);
  const json s = json::parse(schema);
  EXPECT_TRUE(s["$defs"].contains("bcm"));
  EXPECT_TRUE(s["$defs"].contains("transform_step"));
}

}  // namespace
}  // namespace ffd
