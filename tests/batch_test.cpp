// `ffdtool batch` and `ffdtool report` end to end, on real meshes from CGAL's data
// (Debian's libcgal-demo, installed by scripts/setup.sh) and the bundled ones: outputs
// byte-identical to single runs whatever --jobs, shards that add up to the whole, resume,
// and failures (a broken file, a crash, a timeout) that stop nothing else.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "test_meshes.h"

namespace ffd {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using test::data;
using test::quoted;
using test::read_file;
using test::run_tool;
using test::temp_folder;
using test::write_file;
using test::xpath;

const char* kScript = R"({"version": 1, "steps": [
  {"op": "lattice", "name": "b", "cells": [4, 4, 4]},
  {"op": "move", "lattice": "b", "points": [{"index": [2, 2, 2], "by": [0, 0.05, 0.1]}]},
  {"op": "save", "path": "mid/stretched.obj"},
  {"op": "move", "lattice": "b", "points": [{"index": [2, 2, 2], "by": [0.1, 0, 0]}]}]})";

// A folder of real meshes in the four formats, plus one broken file (`broken` true).
std::string mesh_folder(const std::string& name, bool broken) {
  const std::string dir = temp_folder(name);
  const std::string in = dir + "/in";
  fs::create_directories(in);
  EXPECT_FALSE(test::cgal_meshes().empty()) << "CGAL's data set is missing: scripts/setup.sh installs libcgal-demo";
  for (const char* name : {"pig.stl", "sphere.ply", "cube.off", "octahedron.off", "elephant.off", "b9.ply"})
    fs::copy(test::cgal_mesh(name), in);
  fs::copy(data("bunny.obj"), in);
  fs::copy(data("grid.obj"), in);
  if (broken) write_file(in + "/broken.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n");
  write_file(dir + "/s.json", kScript);
  return dir;
}

// Every file under `root`, relative path -> bytes; results logs left out (they hold times).
std::map<std::string, std::string> files_under(const std::string& root) {
  std::map<std::string, std::string> out;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    if (!entry.is_regular_file()) continue;
    const std::string rel = fs::relative(entry.path(), root).string();
    if (rel.rfind("results", 0) == 0) continue;
    out[rel] = read_file(entry.path().string());
  }
  return out;
}

std::vector<json> results(const std::string& file) {
  std::vector<json> out;
  std::istringstream lines(read_file(file));
  for (std::string line; std::getline(lines, line);) out.push_back(json::parse(line));
  return out;
}

int batch(const std::string& args, std::string* err = nullptr) { return run_tool("batch " + args, nullptr, err); }

TEST(Batch, RealMeshesAndABrokenOneGiveSingleRunsBytesAndOneLineEach) {
  const std::string dir = mesh_folder("batch_real", true);
  std::string err;
  EXPECT_EQ(batch(quoted(dir + "/s.json") + " " + quoted(dir + "/in") + " -o " + quoted(dir + "/out"), &err), 2) << err;
  const std::vector<json> lines = results(dir + "/out/results.jsonl");
  EXPECT_EQ(lines.size(), 9u);
  std::set<std::string> formats;
  for (const json& line : lines) {
    const std::string input = line["input"], name = fs::path(input).stem().string();
    if (name == "broken") {
      EXPECT_EQ(line["status"], "error");
      EXPECT_EQ(line["exit"], 2);
      EXPECT_NE(line["error"].get<std::string>().find("broken.off:2"), std::string::npos) << line.dump();
      EXPECT_FALSE(fs::exists(dir + "/out/broken.off"));
      EXPECT_FALSE(fs::exists(dir + "/out/broken")) << "a failed item left its save folder";
      continue;
    }
    EXPECT_EQ(line["status"], "ok") << line.dump();
    formats.insert(fs::path(input).extension().string());
    // The single run of the same mesh, and its bytes.
    const std::string single = dir + "/single/" + name;
    fs::create_directories(single + "/mid");
    const std::string out = single + "/" + fs::path(input).filename().string();
    ASSERT_EQ(run_tool("run " + quoted(input) + " " + quoted(dir + "/s.json") + " -o " + quoted(out) + " --quiet"), 0);
    EXPECT_EQ(read_file(dir + "/out/" + fs::path(input).filename().string()), read_file(out)) << name;
    EXPECT_EQ(read_file(dir + "/out/" + name + "/mid/stretched.obj"), read_file(single + "/mid/stretched.obj")) << name;
    EXPECT_EQ(line["sha256"]["output"].get<std::string>().size(), 64u);
    EXPECT_TRUE(line["stats"].is_array());
  }
  EXPECT_EQ(formats, (std::set<std::string>{".obj", ".off", ".ply", ".stl"}));
  std::string report;
  ASSERT_EQ(run_tool("report " + quoted(dir + "/out") + " --json", &report), 0);
  const json r = json::parse(report);
  EXPECT_EQ(r["counts"]["ok"], 8);
  EXPECT_EQ(r["counts"]["failed"], 1);
  EXPECT_EQ(r["failures"][0]["input"].get<std::string>(), dir + "/in/broken.off");
  EXPECT_EQ(r["slowest"].size(), 5u);
}

TEST(Batch, OneJobOrTwoGiveTheSameBytes) {
  const std::string dir = mesh_folder("batch_jobs", false);
  const std::string args = quoted(dir + "/s.json") + " " + quoted(dir + "/in") + " -o ";
  ASSERT_EQ(batch(args + quoted(dir + "/one") + " --jobs 1"), 0);
  ASSERT_EQ(batch(args + quoted(dir + "/two") + " --jobs 2"), 0);
  const auto one = files_under(dir + "/one");
  EXPECT_EQ(one.size(), 16u);  // 8 meshes and their saves
  EXPECT_EQ(one, files_under(dir + "/two"));
}

TEST(Batch, ThreeShardsMakeTheWholeBatch) {
  const std::string dir = mesh_folder("batch_shards", false);
  const std::string args = quoted(dir + "/s.json") + " " + quoted(dir + "/in") + " -o ";
  ASSERT_EQ(batch(args + quoted(dir + "/all")), 0);
  for (int i = 0; i < 3; ++i) ASSERT_EQ(batch(args + quoted(dir + "/shards") + " --shard " + std::to_string(i) + "/3"), 0);
  EXPECT_EQ(files_under(dir + "/shards"), files_under(dir + "/all"));
  std::set<std::string> inputs;
  for (int i = 0; i < 3; ++i)
    for (const json& line : results(dir + "/shards/results-" + std::to_string(i) + "-of-3.jsonl"))
      EXPECT_TRUE(inputs.insert(line["input"].get<std::string>()).second) << "in two shards: " << line["input"];
  EXPECT_EQ(inputs.size(), 8u);
  // A Slurm array task finds its shard in the environment and says so.
  std::string err;
  EXPECT_EQ(run_tool("batch " + args + quoted(dir + "/slurm"), nullptr, &err), 0);
  EXPECT_EQ(std::system(("SLURM_ARRAY_TASK_ID=1 SLURM_ARRAY_TASK_COUNT=3 " FFD_TOOL " batch " + args +
                         quoted(dir + "/env") + " 2>" + quoted(dir + "/env.err")).c_str()), 0);
  EXPECT_NE(read_file(dir + "/env.err").find("shard 1/3 (SLURM_ARRAY_TASK_ID)"), std::string::npos);
  EXPECT_EQ(results(dir + "/env/results-1-of-3.jsonl").size(), 3u);  // items 1, 4, 7
}

TEST(Batch, ResumeRerunsNothingUntilTheScriptChanges) {
  const std::string dir = mesh_folder("batch_resume", false);
  const std::string args = quoted(dir + "/s.json") + " " + quoted(dir + "/in") + " -o " + quoted(dir + "/out");
  ASSERT_EQ(batch(args), 0);
  struct stat before {};
  ASSERT_EQ(::stat((dir + "/out/bunny.obj").c_str(), &before), 0);
  const auto bytes = files_under(dir + "/out");
  ASSERT_EQ(batch(args + " --resume"), 0);
  for (const json& line : results(dir + "/out/results.jsonl")) EXPECT_EQ(line["status"], "skipped") << line.dump();
  struct stat after {};
  ASSERT_EQ(::stat((dir + "/out/bunny.obj").c_str(), &after), 0);
  EXPECT_EQ(before.st_ino, after.st_ino) << "the output was rewritten";
  EXPECT_EQ(before.st_mtim.tv_nsec, after.st_mtim.tv_nsec);
  EXPECT_EQ(files_under(dir + "/out"), bytes);
  write_file(dir + "/s.json", std::string(kScript).replace(std::string(kScript).find("0.05"), 4, "0.07"));
  ASSERT_EQ(batch(args + " --resume"), 0);
  for (const json& line : results(dir + "/out/results.jsonl")) EXPECT_EQ(line["status"], "ok") << line.dump();
  EXPECT_NE(files_under(dir + "/out"), bytes);
}

// "ffdtool batch: 8 ok, 1 failed, 0 skipped in ..." in a batch's stderr: {ok, failed, skipped}.
std::array<int, 3> summary_counts(const std::string& err) {
  std::array<int, 3> n{-1, -1, -1};
  const std::size_t at = err.rfind("ffdtool batch: ");  // the last line: the summary
  if (at != std::string::npos) std::sscanf(err.c_str() + at, "ffdtool batch: %d ok, %d failed, %d skipped", &n[0], &n[1], &n[2]);
  return n;
}

// A JUnit file without what two reports of the same results may differ in: the time,
// timestamp and hostname of <testsuites> and <testsuite>.
std::string junit_content(const std::string& path) {
  std::istringstream lines(read_file(path));
  std::string out;
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("<testsuites ", 0) == 0 || line.rfind("  <testsuite ", 0) == 0)
      line = std::regex_replace(line, std::regex(R"( (time|timestamp|hostname)="[^"]*")"), "");
    out += line + "\n";
  }
  return out;
}

// Expects the JUnit file at `path` to validate and to count what `report --json` of the
// batch's folder `out` counts; returns that report.
json expect_junit_counts(const std::string& path, const std::string& out) {
  std::string why;
  EXPECT_TRUE(test::junit_valid(path, &why)) << why;
  std::string text;
  EXPECT_EQ(run_tool("report " + quoted(out) + " --json", &text), 0);
  const json counts = json::parse(text)["counts"];
  const int ok = counts["ok"], failed = counts["failed"], skipped = counts["skipped"];
  for (const std::string& element : std::vector<std::string>{"/testsuites", "/testsuites/testsuite"}) {
    EXPECT_EQ(xpath(path, "string(" + element + "/@tests)"), std::to_string(ok + failed + skipped)) << element;
    EXPECT_EQ(xpath(path, "string(" + element + "/@failures)"), std::to_string(failed)) << element;
    EXPECT_EQ(xpath(path, "string(" + element + "/@skipped)"), std::to_string(skipped)) << element;
    EXPECT_EQ(xpath(path, "string(" + element + "/@errors)"), "0") << element;
  }
  EXPECT_EQ(xpath(path, "count(//testcase)"), std::to_string(ok + failed + skipped));
  EXPECT_EQ(xpath(path, "count(//testcase/failure)"), std::to_string(failed));
  EXPECT_EQ(xpath(path, "count(//testcase/skipped)"), std::to_string(skipped));
  return counts;
}

TEST(Batch, JUnitReportHasACasePerMeshAndTheBatchsCounts) {
  const std::string dir = mesh_folder("batch_junit", true);
  const std::string args = quoted(dir + "/s.json") + " " + quoted(dir + "/in") + " -o " + quoted(dir + "/out");
  std::string err;
  EXPECT_EQ(batch(args + " --jobs 2 --junit " + quoted(dir + "/first.xml"), &err), 2) << err;
  const json counts = expect_junit_counts(dir + "/first.xml", dir + "/out");
  EXPECT_EQ(counts, json({{"ok", 8}, {"failed", 1}, {"skipped", 0}}));
  EXPECT_EQ(summary_counts(err), (std::array<int, 3>{8, 1, 0})) << err;
  // A case per results line: its input, its time, and a failed mesh's error line.
  for (const json& line : results(dir + "/out/results.jsonl")) {
    const std::string input = line["input"], testcase = "//testcase[@name=\"" + input + "\"]";
    char seconds[32];
    std::snprintf(seconds, sizeof seconds, "%.3f", line["ms"].get<double>() / 1000);
    EXPECT_EQ(xpath(dir + "/first.xml", "string(" + testcase + "/@time)"), seconds) << input;
    EXPECT_EQ(xpath(dir + "/first.xml", "string(" + testcase + "/@classname)"), "ffdtool.batch") << input;
    if (line["status"] == "error") {
      EXPECT_EQ(xpath(dir + "/first.xml", "string(" + testcase + "/failure/@message)"), line["error"].get<std::string>());
    }
  }
  EXPECT_NE(xpath(dir + "/first.xml", "string(//testcase[@name=\"" + dir + "/in/broken.off\"]/failure/@message)").find("broken.off:2"),
            std::string::npos);
  EXPECT_NE(xpath(dir + "/first.xml", "string(//testsuite/@timestamp)"), "");
  // `report --junit` gives the same cases and counts from the log.
  ASSERT_EQ(run_tool("report " + quoted(dir + "/out") + " --junit " + quoted(dir + "/first-report.xml")), 0);
  EXPECT_TRUE(test::junit_valid(dir + "/first-report.xml"));
  EXPECT_EQ(junit_content(dir + "/first-report.xml"), junit_content(dir + "/first.xml"));
  EXPECT_NE(junit_content(dir + "/first.xml").find("<testcase"), std::string::npos);

  // Resumed: the 8 done meshes are skipped cases, the broken one fails again.
  EXPECT_EQ(batch(args + " --resume --junit " + quoted(dir + "/second.xml"), &err), 2) << err;
  EXPECT_EQ(expect_junit_counts(dir + "/second.xml", dir + "/out"), json({{"ok", 0}, {"failed", 1}, {"skipped", 8}}));
  EXPECT_EQ(summary_counts(err), (std::array<int, 3>{0, 1, 8})) << err;
  EXPECT_EQ(xpath(dir + "/second.xml", "string(//testcase[@name=\"" + dir + "/in/bunny.obj\"]/skipped/@message)"),
            "done before with the same input and script (--resume)");
  ASSERT_EQ(run_tool("report " + quoted(dir + "/out") + " --json --junit " + quoted(dir + "/second-report.xml")), 0);
  EXPECT_EQ(junit_content(dir + "/second-report.xml"), junit_content(dir + "/second.xml"));
  EXPECT_NE(junit_content(dir + "/second.xml"), junit_content(dir + "/first.xml"));
}

TEST(Batch, AJUnitFileThatCannotBeWrittenIsRefusedBeforeAnyWork) {
  const std::string dir = mesh_folder("batch_junit_bad", false);
  std::string err;
  EXPECT_EQ(batch(quoted(dir + "/s.json") + " " + quoted(dir + "/in") + " -o " + quoted(dir + "/out") + " --junit " +
                      quoted(dir + "/missing/junit.xml"), &err), 2);
  test::expect_one_error_line(err, {"missing/junit.xml", "--junit"});
  EXPECT_FALSE(fs::exists(dir + "/out/results.jsonl"));
  EXPECT_EQ(batch(quoted(dir + "/s.json") + " " + quoted(dir + "/in") + " -o " + quoted(dir + "/out") + " --junit " +
                      quoted(dir + "/s.json"), &err), 2);
  test::expect_one_error_line(err, {"would overwrite the script"});
  EXPECT_FALSE(fs::exists(dir + "/out/results.jsonl"));
  EXPECT_EQ(read_file(dir + "/s.json"), kScript);
}

// pig.off and pig.stl side by side (two different real meshes): each is named by its file
// name, pig_off and pig_stl, and gives what a single run gives; --resume skips both.
// With --format obj their outputs take the names too.
TEST(Batch, InputsThatShareAStemAreNamedByTheirFileNames) {
  const std::string dir = mesh_folder("batch_stem", false);
  fs::create_directories(dir + "/pair");
  fs::copy(dir + "/in/pig.stl", dir + "/pair/pig.stl");
  fs::copy(dir + "/in/elephant.off", dir + "/pair/pig.off");
  fs::copy(dir + "/in/bunny.obj", dir + "/pair/bunny.obj");  // a stem of its own keeps its name
  const std::string args = quoted(dir + "/s.json") + " " + quoted(dir + "/pair") + " -o " + quoted(dir + "/out") + " --format obj";
  std::string err;
  ASSERT_EQ(batch(args, &err), 0) << err;
  EXPECT_EQ(test::files_in(dir + "/out"),
            (std::set<std::string>{"bunny.obj", "bunny", "pig_off.obj", "pig_off", "pig_stl.obj", "pig_stl", "results.jsonl"}));
  for (const std::string& name : std::vector<std::string>{"pig_off", "pig_stl", "bunny"}) {
    const std::string input = dir + "/pair/" + (name == "bunny" ? "bunny.obj" : name == "pig_off" ? "pig.off" : "pig.stl");
    const std::string single = dir + "/single/" + name;
    fs::create_directories(single + "/mid");
    ASSERT_EQ(run_tool("run " + quoted(input) + " " + quoted(dir + "/s.json") + " -o " + quoted(single + "/" + name + ".obj") +
                       " --quiet"), 0);
    EXPECT_EQ(read_file(dir + "/out/" + name + ".obj"), read_file(single + "/" + name + ".obj")) << name;
    EXPECT_EQ(read_file(dir + "/out/" + name + "/mid/stretched.obj"), read_file(single + "/mid/stretched.obj")) << name;
  }
  EXPECT_NE(read_file(dir + "/out/pig_off.obj"), read_file(dir + "/out/pig_stl.obj"));
  std::map<std::string, std::string> outputs;
  for (const json& line : results(dir + "/out/results.jsonl")) outputs[line["input"]] = line["output"];
  EXPECT_EQ(outputs[dir + "/pair/pig.off"], dir + "/out/pig_off.obj");
  EXPECT_EQ(outputs[dir + "/pair/pig.stl"], dir + "/out/pig_stl.obj");
  const auto bytes = files_under(dir + "/out");
  ASSERT_EQ(batch(args + " --resume", &err), 0) << err;
  const std::vector<json> lines = results(dir + "/out/results.jsonl");
  EXPECT_EQ(lines.size(), 3u);
  for (const json& line : lines) EXPECT_EQ(line["status"], "skipped") << line.dump();
  EXPECT_EQ(files_under(dir + "/out"), bytes);
  // Without --format an output keeps its input's file name (their extensions keep them
  // apart), so that `compare IN OUT` pairs them; the save folders are the names.
  ASSERT_EQ(batch(quoted(dir + "/s.json") + " " + quoted(dir + "/pair") + " -o " + quoted(dir + "/kept"), &err), 0) << err;
  EXPECT_EQ(test::files_in(dir + "/kept"),
            (std::set<std::string>{"bunny.obj", "bunny", "pig.off", "pig_off", "pig.stl", "pig_stl", "results.jsonl"}));
  EXPECT_TRUE(fs::exists(dir + "/kept/pig_off/mid/stretched.obj"));
}

// Names that still collide are refused before any work, naming both files.
TEST(Batch, NamesThatStillCollideAreRefused) {
  const std::string dir = mesh_folder("batch_collide", false);
  fs::create_directories(dir + "/deep/a");
  fs::create_directories(dir + "/deep/b");
  fs::copy(dir + "/in/cube.off", dir + "/deep/a/pig.off");
  fs::copy(dir + "/in/octahedron.off", dir + "/deep/b/pig.off");
  std::string err;
  EXPECT_EQ(batch(quoted(dir + "/s.json") + " " + quoted(dir + "/deep") + " --recursive -o " + quoted(dir + "/out"), &err), 2);
  test::expect_one_error_line(err, {dir + "/deep/a/pig.off", dir + "/deep/b/pig.off", "'pig_off'", "share a stem"});
  EXPECT_FALSE(fs::exists(dir + "/out/results.jsonl"));
  fs::create_directories(dir + "/three");
  fs::copy(dir + "/in/pig.stl", dir + "/three/pig.stl");
  fs::copy(dir + "/in/cube.off", dir + "/three/pig.off");
  fs::copy(dir + "/in/bunny.obj", dir + "/three/pig_off.obj");
  EXPECT_EQ(batch(quoted(dir + "/s.json") + " " + quoted(dir + "/three") + " -o " + quoted(dir + "/out"), &err), 2);
  test::expect_one_error_line(err, {dir + "/three/pig.off", dir + "/three/pig_off.obj", "'pig_off'"});
  EXPECT_FALSE(fs::exists(dir + "/out/results.jsonl"));
}

// The item process for one mesh crashes (a stand-in for the real one that kills itself),
// another one runs past its time: both fail alone.
TEST(Batch, ACrashAndATimeoutStopNothingElse) {
  const std::string dir = mesh_folder("batch_crash", false);
  write_file(dir + "/runner.sh",
             "#!/bin/sh\ncase \"$2\" in\n  *cube.off) kill -SEGV $$ ;;\n  *octahedron.off) sleep 5 ;;\nesac\nexec " FFD_TOOL " \"$@\"\n");
  fs::permissions(dir + "/runner.sh", fs::perms::owner_all);
  const std::string command = "FFD_BATCH_RUNNER=" + quoted(dir + "/runner.sh") + " " FFD_TOOL " batch " +
                              quoted(dir + "/s.json") + " " + quoted(dir + "/in") + " -o " + quoted(dir + "/out") +
                              " --timeout 1.5 2>" + quoted(dir + "/err");
  const int status = std::system(command.c_str());
  EXPECT_EQ(WEXITSTATUS(status), 3) << read_file(dir + "/err");
  std::map<std::string, json> by_name;
  for (const json& line : results(dir + "/out/results.jsonl"))
    by_name[fs::path(line["input"].get<std::string>()).stem().string()] = line;
  ASSERT_EQ(by_name.size(), 8u);
  EXPECT_EQ(by_name["cube"]["status"], "error");
  EXPECT_NE(by_name["cube"]["error"].get<std::string>().find("killed by signal 11"), std::string::npos);
  EXPECT_EQ(by_name["octahedron"]["status"], "error");
  EXPECT_NE(by_name["octahedron"]["error"].get<std::string>().find("timed out after 1.5 s"), std::string::npos);
  std::size_t ok = 0;
  for (const auto& [name, line] : by_name) ok += line["status"] == "ok";
  EXPECT_EQ(ok, 6u);
}

// --max-memory: a mesh too large for the limit fails as out of memory, a small one runs.
TEST(Batch, AMeshPastTheMemoryLimitFailsAlone) {
#ifdef FFD_SANITIZE
  GTEST_SKIP() << "an ASan build cannot start under --max-memory's RLIMIT_AS: its shadow memory is address space";
#endif
  const std::string dir = temp_folder("batch_memory");
  fs::create_directories(dir + "/in");
  fs::copy(data("bunny.obj"), dir + "/in/bunny.obj");
  write_file(dir + "/in/big.obj", test::grid_obj(800));  // 641,601 vertices, about 170 MB to run
  write_file(dir + "/s.json", kScript);
  std::string err;
  EXPECT_EQ(batch(quoted(dir + "/s.json") + " " + quoted(dir + "/in") + " -o " + quoted(dir + "/out") +
                      " --max-memory 100M --jobs 1", &err), 3) << err;
  std::map<std::string, json> by_name;
  for (const json& line : results(dir + "/out/results.jsonl"))
    by_name[fs::path(line["input"].get<std::string>()).stem().string()] = line;
  EXPECT_EQ(by_name["bunny"]["status"], "ok");
  EXPECT_EQ(by_name["big"]["status"], "error");
  EXPECT_EQ(by_name["big"]["exit"], 3);
  EXPECT_NE(by_name["big"]["error"].get<std::string>().find("out of memory"), std::string::npos) << by_name["big"].dump();
  EXPECT_FALSE(fs::exists(dir + "/out/big.obj"));
}

// An output folder inside the input folder: a second (recursive) batch does not take the
// first one's outputs for inputs.
TEST(Batch, ItsOwnOutputsAreNotInputs) {
  const std::string dir = mesh_folder("batch_inside", false);
  const std::string args = quoted(dir + "/s.json") + " " + quoted(dir + "/in") + " -o " + quoted(dir + "/in/out") + " --recursive";
  ASSERT_EQ(batch(args), 0);
  ASSERT_EQ(batch(args), 0);
  EXPECT_EQ(results(dir + "/in/out/results.jsonl").size(), 8u);
  EXPECT_FALSE(fs::exists(dir + "/in/out/out"));
}

// A script that no mesh could run (an octree move selecting points by plain numbers) is
// refused with the script, before any mesh runs: one line, exit 2, nothing written.
TEST(Batch, AScriptThatCannotRunOnAnyMeshRunsOnNone) {
  const std::string dir = mesh_folder("batch_bad_indices", false);
  write_file(dir + "/octree.json", R"({"version":1,"steps":[
 {"op":"lattice","name":"o","basis":"octree","levels":2},
 {"op":"move","lattice":"o","select":{"indices":[3,4]},"transform":{"translate":[0.1,0,0]}}]})");
  std::string out, err;
  EXPECT_EQ(run_tool("validate " + quoted(dir + "/octree.json"), &out, &err), 2);
  test::expect_one_error_line(err, {dir + "/octree.json: /steps/1/select/indices/0: expected a lattice index [i, j, k]"});
  EXPECT_EQ(batch(quoted(dir + "/octree.json") + " " + quoted(dir + "/in") + " -o " + quoted(dir + "/out") + " --junit " +
                      quoted(dir + "/junit.xml"), &err), 2);
  test::expect_one_error_line(err, {dir + "/octree.json: /steps/1/select/indices/0: expected a lattice index [i, j, k]"});
  EXPECT_TRUE(!fs::exists(dir + "/out") || fs::is_empty(dir + "/out")) << "a mesh ran or a log was started";
  EXPECT_FALSE(fs::exists(dir + "/junit.xml"));
}

TEST(Batch, BadInputsAreRefusedBeforeAnyWork) {
  const std::string dir = mesh_folder("batch_bad", false);
  fs::create_directories(dir + "/other");
  fs::copy(data("bunny.obj"), dir + "/other/bunny.obj");
  std::string err;
  EXPECT_EQ(batch(quoted(dir + "/s.json") + " " + quoted(dir + "/in") + " " + quoted(dir + "/other") + " -o " +
                      quoted(dir + "/out"), &err), 2);
  EXPECT_NE(err.find("same name"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(dir + "/out/results.jsonl"));
  write_file(dir + "/bad.json", R"({"version": 1, "steps": [{"op": "twist"}]})");
  EXPECT_EQ(batch(quoted(dir + "/bad.json") + " " + quoted(dir + "/in") + " -o " + quoted(dir + "/out2"), &err), 2);
  EXPECT_NE(err.find("/steps/0/op"), std::string::npos) << err;
  EXPECT_EQ(batch(quoted(dir + "/s.json") + " " + quoted(dir + "/in") + " -o " + quoted(dir + "/out3") + " --shard 3/3", &err), 2);
  EXPECT_NE(err.find("--shard"), std::string::npos) << err;
}

}  // namespace
}  // namespace ffd
