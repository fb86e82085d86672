// Gain & Dodgson's figure 7 end to end: an extruding deformation with adaptive
// refinement, then a flattening one with refinement and decimation, on a plane grid and
// on the bunny; the outputs are compared with checked-in meshes by `ffdtool compare`.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "test_meshes.h"

namespace ffd {
namespace {

using test::data;
using test::read_file;
using test::run_tool;
using test::temp_folder;

struct Figure7 {
  std::string mesh, script, name;
};

// Names the case in test listings instead of gtest's byte dump.
void PrintTo(const Figure7& f, std::ostream* os) { *os << f.name; }

class Figure7Test : public ::testing::TestWithParam<Figure7> {};

// The checked-in meshes come from the optimized build; every build must match them vertex
// for vertex, the sanitizers' portable -O1 build (no FMA) included: the remesher's
// longest-first order treats lengths equal but for their last bits as ties.
TEST_P(Figure7Test, MatchesTheCheckedInMeshesAndDecimatesWhatExtrusionRefined) {
  const Figure7& f = GetParam();
  const std::string dir = temp_folder("fig7_" + f.name);
  std::string err;
  ASSERT_EQ(run_tool("run " + data(f.mesh) + " " + data(f.script) + " -o " + dir + "/" + f.name + ".obj --stats " +
                         dir + "/stats.json --quiet",
                     nullptr, &err),
            0)
      << err;
  for (const std::string& out : {f.name + "_extruded.obj", f.name + ".obj"}) {
    std::string report;
    EXPECT_EQ(run_tool("compare " + dir + "/" + out + " " + data("expected/" + out) + " --tolerance 1e-9", &report),
              0)
        << out << ": " << report;
  }
  const nlohmann::json stats = nlohmann::json::parse(read_file(dir + "/stats.json"));
  std::vector<nlohmann::json> remesh;
  for (const auto& step : stats["steps"])
    if (step["op"] == "remesh") remesh.push_back(step);
  ASSERT_EQ(remesh.size(), 2u);
  EXPECT_GT(remesh[0]["refinements"].get<int>(), 10);
  EXPECT_EQ(remesh[0]["decimations"].get<int>(), 0);
  // The flattening step removes refinements the extrusion made.
  EXPECT_GT(remesh[1]["decimations"].get<int>(), remesh[0]["refinements"].get<int>() / 3);
  EXPECT_LT(remesh[1]["faces_after"].get<int>(), remesh[0]["faces_after"].get<int>());
}

INSTANTIATE_TEST_SUITE_P(Remesh, Figure7Test,
                         ::testing::Values(Figure7{"grid.obj", "fig7_grid.json", "fig7_grid"},
                                           Figure7{"bunny.obj", "fig7_bunny.json", "fig7_bunny"}),
                         [](const auto& info) { return info.param.name; });

TEST(RemeshCli, LevelColoursAreWritten) {
  const std::string dir = temp_folder("fig7_levels");
  ASSERT_EQ(run_tool("run " + data("grid.obj") + " " + data("fig7_grid.json") + " -o " + dir + "/out.obj --quiet"), 0);
  const std::string ply = read_file(dir + "/fig7_grid_extruded_levels.ply");
  EXPECT_NE(ply.find("property uchar red"), std::string::npos);
  EXPECT_NE(ply.find(" 191 191 191"), std::string::npos);  // level 0: light grey
}

// The remesh step says what it did with each attribute: the grid as a PLY with UVs,
// colours and a custom property; UVs and colours are interpolated, the custom property
// cannot follow the new connectivity, and the stats name it, as the output's warning does.
TEST(RemeshCli, TheStatsSayWhatEachAttributeBecame) {
  const std::string dir = temp_folder("remesh_attributes");
  std::string ply = "ply\nformat ascii 1.0\nelement vertex 441\nproperty double x\nproperty double y\nproperty double z\n"
                    "property float u\nproperty float v\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
                    "property float confidence\nelement face 800\nproperty list uchar int vertex_indices\nend_header\n";
  std::istringstream obj(read_file(data("grid.obj")));
  std::string line;
  int v = 0;
  while (std::getline(obj, line)) {
    std::istringstream in(line.substr(line.find(' ') + 1));
    double x, y, z;
    int a, b, c;
    if (line.rfind("v ", 0) == 0 && in >> x >> y >> z)
      ply += std::to_string(x) + " " + std::to_string(y) + " " + std::to_string(z) + " 0.5 0.25 200 100 50 " +
             std::to_string(v++ % 7) + "\n";
    else if (line.rfind("f ", 0) == 0 && std::sscanf(line.c_str(), "f %d/%*d %d/%*d %d/%*d", &a, &b, &c) == 3)
      ply += "3 " + std::to_string(a - 1) + " " + std::to_string(b - 1) + " " + std::to_string(c - 1) + "\n";
  }
  test::write_file(dir + "/grid.ply", ply);
  std::string err;
  ASSERT_EQ(run_tool("run " + dir + "/grid.ply " + data("fig7_grid.json") + " -o " + dir + "/out.ply --stats " + dir +
                         "/stats.json",
                     nullptr, &err),
            0)
      << err;
  const nlohmann::json stats = nlohmann::json::parse(read_file(dir + "/stats.json"));
  bool seen = false;
  for (const auto& step : stats["steps"]) {
    if (step["op"] != "remesh") continue;
    seen = true;
    const std::string interpolated = step["attributes"]["interpolated"].dump();
    EXPECT_NE(interpolated.find("uv"), std::string::npos) << interpolated;
    EXPECT_NE(interpolated.find("vertex colors"), std::string::npos) << interpolated;
    EXPECT_NE(step["attributes"]["dropped"].get<std::string>().find("confidence"), std::string::npos);
  }
  EXPECT_TRUE(seen);
  EXPECT_NE(err.find("confidence"), std::string::npos) << err;  // and the write warns
}

TEST(RemeshCli, BadRemeshOptionsAreInputErrors) {
  const std::string dir = temp_folder("remesh_bad");
  const std::string script = dir + "/s.json";
  test::write_file(script, R"({"version": 1, "steps": [
    {"op": "lattice", "name": "l", "cells": [6, 6, 6]},
    {"op": "remesh", "theta_max_deg": 10, "theta_min_deg": 20}]})");
  std::string err;
  EXPECT_EQ(run_tool("run " + data("bunny.obj") + " " + script + " -o " + dir + "/out.obj", nullptr, &err), 2);
  EXPECT_NE(err.find("/steps/1/theta_min_deg"), std::string::npos) << err;
  test::write_file(script, R"({"version": 1, "steps": [{"op": "remesh"}]})");
  EXPECT_EQ(run_tool("run " + data("bunny.obj") + " " + script + " -o " + dir + "/out.obj", nullptr, &err), 2);
  EXPECT_NE(err.find("/steps/0/l_max"), std::string::npos) << err;
  EXPECT_FALSE(std::ifstream(dir + "/out.obj").good());
}

}  // namespace
}  // namespace ffd
