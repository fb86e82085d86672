// The Deformer seam through the ffdtool binary: the outputs each lattice kind gave before
// the seam (test_data/expected/seam, written by the code before the refactor), move to
// positions from a file (a saved net loaded back is the identity), the sensitivity save,
// and their input errors.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "test_meshes.h"

namespace ffd {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using test::expect_one_error_line;
using test::quoted;
using test::read_file;
using test::script;
using test::run_tool;
using test::temp_folder;
using test::write_file;

std::string seam_mesh(const std::string& name) {
  return name == "bunny" ? test::data("bunny.obj") : test::cgal_mesh(name + ".off");
}

struct SeamRun {
  int code = -1;
  std::string dir, err;
  json stats;
};

SeamRun run_seam_script(const std::string& dir, const std::string& mesh, const std::string& script,
                        const std::string& out = "out.off", const std::string& extra = "") {
  SeamRun r;
  r.dir = dir;
  r.code = run_tool("run " + quoted(mesh) + " " + quoted(script) + " -o " + quoted(dir + "/" + out) + " --stats " +
                        quoted(dir + "/stats.json") + " --quiet " + extra,
                    nullptr, &r.err);
  const std::string text = read_file(dir + "/stats.json");
  if (!text.empty()) r.stats = json::parse(text);
  return r;
}

/// `ffdtool compare --tolerance T` says the meshes (or control nets) are the same.
void expect_same_mesh(const std::string& a, const std::string& b, const std::string& tolerance = "0") {
  std::string out;
  EXPECT_EQ(run_tool("compare " + quoted(a) + " " + quoted(b) + " --tolerance " + tolerance, &out), 0)
      << a << " vs " << b << "\n"
      << out;
}

// The goldens are the bytes of a Release build for x86-64-v3 (AVX2 and FMA: one binary
// whatever CPU built it, cmake/arch.cmake); that build must reproduce them byte for byte
// on any CPU. The default build (FFD_ARCH=native) rounds differently in the last bits on
// some CPU models (Eigen's AVX-512 packets sum in another order; GCC's tuning contracts
// other products into FMAs): it is held to 1e-12 of the bunny's and the elephant's units
// (about 1e3 ulps of their coordinates; measured differences are below 1e-15). The
// sanitizers' -O1 portable build has no FMA contraction at all: 1e-9.
bool golden_build() { return std::string(FFD_BUILD_FLAGS) == "Release x86-64-v3"; }
std::string golden_tolerance() {
  if (golden_build()) return "0";
  return std::string(FFD_BUILD_FLAGS).find("native") != std::string::npos ? "1e-12" : "1e-9";
}

class SeamGolden : public ::testing::TestWithParam<std::tuple<std::string, std::string>> {};

// Move, drag and the saved nets of each kind as before the seam: byte for byte on the
// x86-64-v3 build (golden_build()), to golden_tolerance() elsewhere; on one thread and on
// two, which agree byte for byte on every build.
TEST_P(SeamGolden, OutputsMatchTheGoldensWrittenBeforeTheSeam) {
  const auto& [mesh_name, kind] = GetParam();
  const std::string mesh = seam_mesh(mesh_name);
  if (mesh.empty()) GTEST_SKIP() << "CGAL's " << mesh_name << " is missing (libcgal-demo)";
  const std::string name = mesh_name + "_" + kind;
  std::string one_thread;  // the folder of the one-thread run
  for (const char* threads : {"1", "2"}) {
    const std::string dir = temp_folder("seam_" + name + "_" + threads);
    if (one_thread.empty()) one_thread = dir;
    const SeamRun r = run_seam_script(dir, mesh, test::data("seam/" + name + ".json"), "drag.off", std::string("--threads ") + threads);
    ASSERT_EQ(r.code, 0) << r.err;
    for (const std::string out : {"move.off", "drag.off", "net.obj", "net0.obj"}) {
      const std::string stem = out.substr(0, out.find('.'));
      const std::string expected = test::data("expected/seam/" + name + "_" + stem + out.substr(out.find('.')));
      if (!fs::exists(expected)) continue;
      SCOPED_TRACE(expected);
      expect_same_mesh(dir + "/" + out, expected, golden_tolerance());
      // Braces: in a unity batch (tests/CMakeLists.txt) GCC 12 takes the else inside
      // EXPECT_TRUE for a dangling one here, though not when the file is compiled alone.
      if (golden_build()) {
        EXPECT_TRUE(read_file(dir + "/" + out) == read_file(expected)) << out << " differs in its bytes";
      }
      if (dir != one_thread) {  // on any build, the thread count changes no byte
        EXPECT_TRUE(read_file(dir + "/" + out) == read_file(one_thread + "/" + out)) << out << ": threads 1 and 2 differ";
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(EveryKind, SeamGolden,
                         ::testing::Combine(::testing::Values("bunny", "elephant"),
                                            ::testing::Values("bspline", "bernstein", "octree")),
                         [](const auto& info) { return std::get<0>(info.param) + "_" + std::get<1>(info.param); });

const std::string kBSpline =
    R"({"op": "lattice", "name": "L", "basis": "bspline", "box": {"fit": "aabb", "padding": 0.05}, "cells": [6, 6, 6]})";
const std::string kOctree =
    R"({"op": "lattice", "name": "L", "basis": "octree", "box": {"fit": "obb", "padding": 0.02}, "levels": 3})";
const std::string kBSplineMoves =
    R"({"op": "move", "lattice": "L", "select": {"sphere": {"center": [0, 6, 0], "radius": 4}},
        "transform": {"rotate": {"axis": [0, 0, 1], "degrees": 12}, "translate": [0.3, 0.4, 0]}})";
const std::string kOctreeMoves =
    R"({"op": "move", "lattice": "L", "level": 1, "points": [{"index": [1, 1, 1], "by": [0.3, 0.5, -0.2]}]},
       {"op": "move", "lattice": "L", "level": 2, "select": {"near": [0, 8, 0]}, "transform": {"translate": [0, 0.6, 0]}})";

// A net saved by ffdtool and loaded back with move positions changes nothing, for a
// B-spline lattice (border points included) and an octree level.
TEST(MovePositions, ASavedNetLoadedBackIsTheIdentity) {
  for (const auto& [lattice, moves, level] :
       {std::tuple<std::string, std::string, std::string>{kBSpline, kBSplineMoves, ""},
        {kOctree, kOctreeMoves, R"(, "level": 2)"}}) {
    const std::string dir = temp_folder("positions_identity");
    write_file(dir + "/a.json", script({lattice, moves, R"({"op": "save", "path": "net.obj", "lattice": "L")" + level + "}"}));
    const SeamRun a = run_seam_script(dir, test::data("bunny.obj"), dir + "/a.json", "a.off");
    ASSERT_EQ(a.code, 0) << a.err;
    write_file(dir + "/b.json", script({lattice, moves, R"({"op": "move", "lattice": "L", "positions": {"file": "net.obj"})" + level + "}"}));
    fs::copy_file(dir + "/net.obj", dir + "/net_in.obj");
    const SeamRun b = run_seam_script(dir, test::data("bunny.obj"), dir + "/b.json", "b.off");
    ASSERT_EQ(b.code, 0) << b.err;
    expect_same_mesh(dir + "/a.off", dir + "/b.off");
    EXPECT_EQ(b.stats["steps"].back()["points_moved"], 0);
    EXPECT_EQ(b.stats["steps"].back()["vertices_moved"], 0);
  }
}

// An edited net moves the points whose lines changed, and only them: the same mesh as
// moving that point `to` the new position.
TEST(MovePositions, AnEditedNetMovesTheEditedPoints) {
  const std::string dir = temp_folder("positions_edit");
  write_file(dir + "/a.json", script({kBSpline, R"({"op": "save", "path": "net.obj", "lattice": "L"})"}));
  ASSERT_EQ(run_seam_script(dir, test::data("bunny.obj"), dir + "/a.json", "a.off").code, 0);
  std::string net = read_file(dir + "/net.obj");
  write_file(dir + "/b.json", script({kBSpline, R"({"op": "move", "lattice": "L", "points": [{"index": [3, 3, 3], "to": [1.5, 7.25, -0.5]}]})",
                                      R"({"op": "save", "path": "net_moved.obj", "lattice": "L"})"}));
  const SeamRun b = run_seam_script(dir, test::data("bunny.obj"), dir + "/b.json", "b.off");
  ASSERT_EQ(b.code, 0) << b.err;
  write_file(dir + "/c.json", script({kBSpline, R"({"op": "move", "lattice": "L", "positions": {"file": "net_moved.obj"}})"}));
  const SeamRun c = run_seam_script(dir, test::data("bunny.obj"), dir + "/c.json", "c.off");
  ASSERT_EQ(c.code, 0) << c.err;
  expect_same_mesh(dir + "/b.off", dir + "/c.off");
  EXPECT_EQ(c.stats["steps"].back()["points_moved"], 1);
  EXPECT_NE(net, read_file(dir + "/net_moved.obj"));
}

TEST(MovePositions, PlainTextPositionsAndFixedPointsThatDifferWarn) {
  const std::string dir = temp_folder("positions_text");
  write_file(dir + "/a.json", script({kBSpline, R"({"op": "save", "path": "net.obj", "lattice": "L"})"}));
  ASSERT_EQ(run_seam_script(dir, test::data("bunny.obj"), dir + "/a.json", "a.off").code, 0);
  // The same points as "x y z" lines, the first (a fixed border point) nudged.
  std::string text, line;
  std::istringstream is(read_file(dir + "/net.obj"));
  bool first = true;
  while (std::getline(is, line))
    if (line.rfind("v ", 0) == 0) {
      text += (first ? "100 100 100" : line.substr(2)) + "\n";
      first = false;
    }
  write_file(dir + "/points.txt", "# x y z\n" + text);
  write_file(dir + "/b.json", script({kBSpline, R"({"op": "move", "lattice": "L", "positions": {"file": "points.txt"}})"}));
  const SeamRun b = run_seam_script(dir, test::data("bunny.obj"), dir + "/b.json", "b.off");
  ASSERT_EQ(b.code, 0) << b.err;
  expect_same_mesh(dir + "/a.off", dir + "/b.off");
  ASSERT_EQ(b.stats["warnings"].size(), 1u) << b.stats.dump();
  const std::string warning = b.stats["warnings"][0].get<std::string>();
  EXPECT_NE(warning.find("1 fixed points of lattice 'L' differ"), std::string::npos) << warning;
  EXPECT_NE(warning.find("points.txt"), std::string::npos) << warning;
}

TEST(MovePositions, ACountThatDiffersIsAnInputErrorNamingBothCounts) {
  const std::string dir = temp_folder("positions_count");
  write_file(dir + "/points.txt", "0 0 0\n1 1 1\n");
  write_file(dir + "/s.json", script({kBSpline, R"({"op": "move", "lattice": "L", "positions": {"file": "points.txt"}})"}));
  const SeamRun r = run_seam_script(dir, test::data("bunny.obj"), dir + "/s.json");
  EXPECT_EQ(r.code, 2);
  expect_one_error_line(r.err, {dir + "/s.json: /steps/1/positions", "has 2 points", "has 729"});
  EXPECT_FALSE(fs::exists(dir + "/out.off"));
  write_file(dir + "/bad.txt", "0 0 0\n1 1 x\n");
  write_file(dir + "/t.json", script({kBSpline, R"({"op": "move", "lattice": "L", "positions": {"file": "bad.txt"}})"}));
  const SeamRun t = run_seam_script(dir, test::data("bunny.obj"), dir + "/t.json");
  EXPECT_EQ(t.code, 2);
  expect_one_error_line(t.err, {"bad.txt:2"});
}

TEST(Sensitivity, SaveWritesAMatrixMarketFileWithItsCounts) {
  const std::string dir = temp_folder("sensitivity_save");
  write_file(dir + "/s.json", script({kOctree, kOctreeMoves,
                                      R"({"op": "save", "path": "dxdp.mtx", "sensitivity": {"lattice": "L", "level": 2}})"}));
  const SeamRun r = run_seam_script(dir, test::data("bunny.obj"), dir + "/s.json");
  ASSERT_EQ(r.code, 0) << r.err;
  const json& step = r.stats["steps"].back();
  EXPECT_EQ(step["rows"], 3 * 1839);
  EXPECT_EQ(step["level"], 2);
  const std::string text = read_file(dir + "/dxdp.mtx");
  EXPECT_EQ(text.rfind("%%MatrixMarket matrix coordinate real general\n", 0), 0u);
  const std::string size_line = std::to_string(3 * 1839) + " " + std::to_string(step["columns"].get<std::size_t>()) +
                                " " + std::to_string(step["entries"].get<std::size_t>()) + "\n";
  EXPECT_NE(text.find("\n" + size_line), std::string::npos) << size_line;
  EXPECT_NE(text.find("\n% point 0 index "), std::string::npos);
  std::size_t lines = 0;
  for (char c : text) lines += c == '\n';
  EXPECT_EQ(lines, 2 + step["movable_points"].get<std::size_t>() + 1 + step["entries"].get<std::size_t>());
}

TEST(Sensitivity, UnknownOrFrozenLatticeIsAnInputErrorAtItsKey) {
  const std::string dir = temp_folder("sensitivity_errors");
  write_file(dir + "/s.json", script({kBSpline, R"({"op": "save", "path": "d.mtx", "sensitivity": {"lattice": "M"}})"}));
  SeamRun r = run_seam_script(dir, test::data("bunny.obj"), dir + "/s.json");
  EXPECT_EQ(r.code, 2);
  expect_one_error_line(r.err, {dir + "/s.json: /steps/1/sensitivity/lattice", "no lattice named 'M'"});
  write_file(dir + "/t.json", script({kBSpline, R"({"op": "save", "path": "d.obj", "sensitivity": {"lattice": "L"}})"}));
  r = run_seam_script(dir, test::data("bunny.obj"), dir + "/t.json");
  EXPECT_EQ(r.code, 2);
  expect_one_error_line(r.err, {dir + "/t.json: /steps/1/path", ".mtx"});
  write_file(dir + "/u.json", script({kBSpline, R"({"op": "save", "path": "d.mtx", "sensitivity": {"lattice": "L", "level": 1}})"}));
  r = run_seam_script(dir, test::data("bunny.obj"), dir + "/u.json");
  EXPECT_EQ(r.code, 2);
  expect_one_error_line(r.err, {dir + "/u.json: /steps/1/sensitivity/level"});
  // A surface edit freezes the lattices before it into the mesh: no sensitivity to give.
  write_file(dir + "/v.json",
             script({kBSpline, R"({"op": "bcm", "name": "back", "support": {"sphere": {"center": [1.24, 6.29, 1.05], "radius": 3.0}},
                       "handles": [{"name": "hump", "select": {"sphere": {"center": [1.24, 6.29, 1.05], "radius": 0.7}}}]})",
                     R"({"op": "save", "path": "d.mtx", "sensitivity": {"lattice": "L"}})"}));
  r = run_seam_script(dir, test::data("bunny.obj"), dir + "/v.json");
  EXPECT_EQ(r.code, 2);
  expect_one_error_line(r.err, {dir + "/v.json: /steps/2/sensitivity/lattice", "frozen into the mesh"});
  EXPECT_TRUE(test::files_in(dir).count("d.mtx") == 0);
}

}  // namespace
}  // namespace ffd
