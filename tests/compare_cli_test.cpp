// `ffdtool compare DIR_A DIR_B` end to end on real meshes (the bundled ones and CGAL's):
// identical folders, a changed, a missing and an extra file, the same bytes whatever
// --jobs, heat maps of the differing pairs, and JUnit reports that validate and count
// what the summary counts.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "test_meshes.h"

namespace ffd {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using test::quoted;
using test::run_tool;

// A/ and B/ holding the same five meshes (one in a subfolder), and a lattice script.
std::string twin_folders(const std::string& name) {
  const std::string dir = test::temp_folder(name);
  for (const char* side : {"/A", "/B"}) {
    fs::create_directories(dir + side + "/sub");
    fs::copy(test::data("bunny.obj"), dir + side);
    fs::copy(test::data("grid.obj"), dir + side + "/sub");
    for (const char* mesh : {"elephant.off", "pig.off", "sphere.ply"}) {
      const std::string path = test::cgal_mesh(mesh);
      EXPECT_FALSE(path.empty()) << mesh << " is missing: scripts/setup.sh installs libcgal-demo";
      fs::copy(path, dir + side);
    }
  }
  test::write_file(dir + "/notes.txt", "not a mesh");
  fs::copy(dir + "/notes.txt", dir + "/A");  // files without a mesh extension are no pair
  test::write_file(dir + "/ffd.json", test::script({R"({"op": "lattice", "name": "b", "cells": [4, 4, 4]})",
                                                    R"({"op": "move", "lattice": "b", "points": [{"index": [2, 2, 2], "by": [0.02, 0.01, 0]}]})"}));
  return dir;
}

// B/PATH becomes A/PATH after the lattice script.
void deform_in_b(const std::string& dir, const std::string& path) {
  ASSERT_EQ(run_tool("run " + quoted(dir + "/A/" + path) + " " + quoted(dir + "/ffd.json") + " -o " + quoted(dir + "/B/" + path) +
                     " --quiet"),
            0);
}

int compare(const std::string& dir, const std::string& options, std::string* out, std::string* err = nullptr) {
  return run_tool("compare " + quoted(dir + "/A") + " " + quoted(dir + "/B") + " " + options, out, err);
}

TEST(CompareFolders, IdenticalFoldersAreTheSame) {
  const std::string dir = twin_folders("compare_same");
  std::string out, err;
  EXPECT_EQ(compare(dir, "--metric hausdorff --tolerance 1e-9", &out, &err), 0) << out << err;
  EXPECT_NE(out.find("compare: 4 pairs: 4 same, 0 different, 0 missing, 0 errors"), std::string::npos) << out;
  EXPECT_EQ(compare(dir, "--recursive", &out, &err), 0) << out << err;  // the vertex metric, and sub/grid.obj
  EXPECT_NE(out.find("compare: 5 pairs: 5 same"), std::string::npos) << out;
}

TEST(CompareFolders, AChangedAMissingAndAnExtraFileAreNamedAndCounted) {
  const std::string dir = twin_folders("compare_diff");
  deform_in_b(dir, "elephant.off");
  fs::remove(dir + "/B/pig.off");
  fs::copy(test::data("bunny.obj"), dir + "/B/extra.obj");
  std::string out, err;
  ASSERT_EQ(compare(dir, "--metric hausdorff --tolerance 1e-4 --recursive", &out, &err), 1) << out << err;
  EXPECT_NE(out.find("different elephant.off: hausdorff distance "), std::string::npos) << out;
  EXPECT_NE(out.find("> tolerance 0.0001"), std::string::npos) << out;
  EXPECT_NE(out.find("missing   pig.off: only in " + dir + "/A"), std::string::npos) << out;
  EXPECT_NE(out.find("missing   extra.obj: only in " + dir + "/B"), std::string::npos) << out;
  EXPECT_NE(out.find("compare: 6 pairs: 3 same, 1 different, 2 missing, 0 errors; worst hausdorff distance"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("(elephant.off)"), std::string::npos) << out;
  EXPECT_EQ(out.find("bunny.obj:"), std::string::npos) << "a same pair has no line: " << out;

  // --json says the same, pair by pair.
  ASSERT_EQ(compare(dir, "--metric hausdorff --tolerance 1e-4 --recursive --json", &out, &err), 1) << err;
  const json j = json::parse(out);
  EXPECT_EQ(j["pairs"], 6);
  EXPECT_EQ(j["different"], 1);
  EXPECT_EQ(j["only_in_a"], 1);
  EXPECT_EQ(j["only_in_b"], 1);
  EXPECT_EQ(j["worst"]["path"], "elephant.off");
  for (const json& r : j["results"])
    if (r["path"] == "elephant.off") {
      EXPECT_EQ(r["status"], "different");
      EXPECT_GT(r["difference"]["max"].get<double>(), 1e-4);
      EXPECT_LE(r["difference"]["max_upper"].get<double>() - r["difference"]["max"].get<double>(), 1e-5);
    }
}

TEST(CompareFolders, JobsChangeNoByteOfTheOutput) {
  const std::string dir = twin_folders("compare_jobs");
  deform_in_b(dir, "pig.off");
  for (const char* format : {"", "--json"}) {
    std::string one, two;
    EXPECT_EQ(compare(dir, std::string("--metric hausdorff --tolerance 1e-5 --recursive --jobs 1 ") + format, &one), 1);
    EXPECT_EQ(compare(dir, std::string("--metric hausdorff --tolerance 1e-5 --recursive --jobs 2 ") + format, &two), 1);
    EXPECT_EQ(one, two) << format;
    EXPECT_FALSE(one.empty());
  }
}

TEST(CompareFolders, HeatMapsOfTheDifferingPairsOnly) {
  const std::string dir = twin_folders("compare_heat");
  deform_in_b(dir, "sub/grid.obj");
  std::string out, err;
  ASSERT_EQ(compare(dir, "--recursive --tolerance 1e-6 --heatmap-dir " + quoted(dir + "/maps") + " --size 160x120", &out, &err),
            1)
      << out << err;
  EXPECT_EQ(test::files_in(dir + "/maps"), std::set<std::string>{"sub"});
  EXPECT_EQ(test::files_in(dir + "/maps/sub"), std::set<std::string>{"grid.obj.png"});
  EXPECT_EQ(test::read_file(dir + "/maps/sub/grid.obj.png").substr(1, 3), "PNG");
}

// The JUnit file's counts: tests, failures, errors.
std::array<std::string, 3> junit_counts(const std::string& path) {
  return {test::xpath(path, "string(//testsuite/@tests)"), test::xpath(path, "string(//testsuite/@failures)"),
          test::xpath(path, "string(//testsuite/@errors)")};
}

TEST(CompareFolders, JUnitReportsValidateAndCountWhatTheSummaryCounts) {
  const std::string dir = twin_folders("compare_junit");
  deform_in_b(dir, "bunny.obj");
  fs::remove(dir + "/B/sphere.ply");
  test::write_file(dir + "/A/broken.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n");
  test::write_file(dir + "/B/broken.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n");
  std::string out, err, why;
  // A mesh that cannot be read is a bad input: exit 2, after every other pair.
  ASSERT_EQ(compare(dir, "--json --junit " + quoted(dir + "/report.xml"), &out, &err), 2) << err;
  EXPECT_TRUE(test::junit_valid(dir + "/report.xml", &why)) << why;
  const json j = json::parse(out);
  EXPECT_EQ(j["errors"], 1);
  const std::array<std::string, 3> expected = {std::to_string(j["pairs"].get<int>()),
                                               std::to_string(j["different"].get<int>() + j["missing"].get<int>()),
                                               std::to_string(j["errors"].get<int>())};
  EXPECT_EQ(junit_counts(dir + "/report.xml"), expected);
  EXPECT_EQ(expected, (std::array<std::string, 3>{"5", "2", "1"}));
  EXPECT_NE(test::xpath(dir + "/report.xml", R"(string(//testcase[@name="bunny.obj"]/failure/@message))").find("vertex distance"),
            std::string::npos);
  EXPECT_NE(test::xpath(dir + "/report.xml", R"(string(//testcase[@name="broken.off"]/error/@message))").find("broken.off"),
            std::string::npos);

  // Two files: one test case.
  EXPECT_EQ(run_tool("compare " + quoted(dir + "/A/pig.off") + " " + quoted(dir + "/B/pig.off") + " --junit " +
                     quoted(dir + "/pair.xml")),
            0);
  EXPECT_TRUE(test::junit_valid(dir + "/pair.xml", &why)) << why;
  EXPECT_EQ(junit_counts(dir + "/pair.xml"), (std::array<std::string, 3>{"1", "0", "0"}));
}

TEST(CompareFolders, AFolderAgainstAFileIsABadInput) {
  const std::string dir = twin_folders("compare_bad");
  std::string err;
  EXPECT_EQ(run_tool("compare " + quoted(dir + "/A") + " " + quoted(dir + "/B/bunny.obj"), nullptr, &err), 2);
  test::expect_one_error_line(err, {dir + "/B/bunny.obj", "is a file", "compare two meshes or two folders"});
  EXPECT_EQ(run_tool("compare " + quoted(dir + "/A") + " " + quoted(dir + "/nowhere"), nullptr, &err), 2);
  test::expect_one_error_line(err, {dir + "/nowhere", "no such file or folder"});
  EXPECT_EQ(run_tool("compare " + quoted(dir + "/A/bunny.obj") + " " + quoted(dir + "/B/bunny.obj") + " --jobs 2", nullptr, &err), 2);
  test::expect_one_error_line(err, {"--jobs is for comparing two folders"});
  EXPECT_EQ(compare(dir, "--heatmap " + quoted(dir + "/one.png"), nullptr, &err), 2);
  test::expect_one_error_line(err, {"--heatmap-dir"});
  EXPECT_FALSE(fs::exists(dir + "/one.png"));
}

}  // namespace
}  // namespace ffd
