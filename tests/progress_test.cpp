// The progress reporter (lib/common/progress.h): NDJSON events that parse, in order, with
// monotone fractions; string escaping; the terminal line (shown late, cleared); the batch
// calls from several threads; nothing at all in mode None. The algorithms' progress
// callbacks (remesh, bcm setup) report fractions in [0, 1] and change nothing. And
// `ffdtool run --progress`: events for every step, the same bytes out, nothing extra by
// default when stderr is not a terminal.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "bcm/bcm_editor.h"
#include "bcm_test_util.h"
#include "common/progress.h"
#include "remesh/adaptive_remesher.h"
#include "test_meshes.h"
#include "warp/bspline_lattice.h"
#include "warp/warp_stack.h"

namespace ffd {
namespace {

using json = nlohmann::json;

// A temporary file to report into, and what was written to it.
class Capture {
public:
  Capture() : file_(std::tmpfile()) {}
  ~Capture() { std::fclose(file_); }
  std::FILE* file() const { return file_; }
  std::string text() const {
    std::fflush(file_);
    const long end = std::ftell(file_);
    std::string out(static_cast<std::size_t>(end), '\0');
    std::rewind(file_);
    const std::size_t got = std::fread(out.data(), 1, out.size(), file_);
    std::fseek(file_, 0, SEEK_END);
    out.resize(got);
    return out;
  }

private:
  std::FILE* file_;
};

// Each line of `text` parsed as JSON (a line that does not parse fails the test).
std::vector<json> events(const std::string& text) {
  std::vector<json> out;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t end = text.find('\n', start);
    EXPECT_NE(end, std::string::npos) << "the last event has no newline";
    const std::string line = text.substr(start, end - start);
    try {
      out.push_back(json::parse(line));
    } catch (const json::exception& e) {
      ADD_FAILURE() << "not JSON: " << line << " (" << e.what() << ")";
    }
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return out;
}

TEST(JsonQuote, EscapesQuotesBackslashesAndControlCharacters) {
  EXPECT_EQ(json_quote(""), R"("")");
  EXPECT_EQ(json_quote("plain/path.obj"), R"("plain/path.obj")");
  EXPECT_EQ(json_quote("say \"hi\""), R"("say \"hi\"")");
  EXPECT_EQ(json_quote("C:\\meshes\\a.obj"), R"("C:\\meshes\\a.obj")");
  EXPECT_EQ(json_quote("a\nb\tc\rd\be\ff"), R"("a\nb\tc\rd\be\ff")");
  EXPECT_EQ(json_quote(std::string("\x01\x1f\0x", 4)), R"("\u0001\u001f\u0000x")");
  EXPECT_EQ(json_quote("\x7f"), "\"\x7f\"");  // DEL needs no escape
  // Whatever goes in comes back out of a JSON parser.
  for (const std::string& s : {std::string("\"\\\"\\\\"), std::string("tab\there\nnew \"line\"\\"),
                              std::string("\x1b[31mred\x1b[0m"), std::string("\0\x01\x02", 3)})
    EXPECT_EQ(json::parse(json_quote(s)).get<std::string>(), s);
}

TEST(JsonQuote, KeepsUtf8AndReplacesInvalidBytes) {
  const std::string utf8 = "h\xc3\xa9llo \xe2\x82\xac \xf0\x9f\x98\x80";  // é, €, an emoji
  EXPECT_EQ(json_quote(utf8), "\"" + utf8 + "\"");
  const std::string replacement = "\xef\xbf\xbd";  // U+FFFD
  // A stray byte, a truncated sequence, an overlong form, a surrogate, past U+10FFFF.
  EXPECT_EQ(json::parse(json_quote("a\xff" "b")).get<std::string>(), "a" + replacement + "b");
  EXPECT_EQ(json::parse(json_quote("a\xc3")).get<std::string>(), "a" + replacement);
  EXPECT_EQ(json::parse(json_quote("\xc0\xaf")).get<std::string>(), replacement + replacement);
  EXPECT_EQ(json::parse(json_quote("\xed\xa0\x80")).get<std::string>(), replacement + replacement + replacement);
  EXPECT_EQ(json::parse(json_quote("\xf4\x90\x80\x80")).get<std::string>(),
            replacement + replacement + replacement + replacement);
}

TEST(JsonEvent, WritesFieldsInOrderWithJsonNumbers) {
  const std::string line = JsonEvent("item_end")
                               .text("input", "in/\"odd\".obj")
                               .integer("exit", -2)
                               .number("ms", 12.34567, 2)
                               .number("nan", std::nan(""))
                               .number("zero", -0.0)
                               .boolean("ok", false)
                               .str();
  EXPECT_EQ(line, R"({"event":"item_end","input":"in/\"odd\".obj","exit":-2,"ms":12.35,"nan":null,"zero":0,"ok":false})");
  EXPECT_TRUE(json::parse(line).is_object());
}

// A step's reports, out of order and out of range on purpose.
void report_a_step(Progress& progress, std::size_t index, std::size_t total) {
  progress.step_start(index, total, "remesh");
  for (double f : {0.0, 0.005, 0.3, 0.2, std::nan(""), -1.0, 0.3, 0.305, 0.32, 0.9, 2.0, 0.5})
    progress.step_progress(f);
  for (int i = 0; i <= 1000; ++i) progress.step_progress(i / 1000.0);
  progress.step_end(12.5);
}

TEST(ProgressJson, StepEventsParseAndComeInOrderWithMonotoneFractions) {
  Capture out;
  {
    Progress progress(ProgressMode::Json, out.file());
    ASSERT_EQ(progress.mode(), ProgressMode::Json);
    ASSERT_TRUE(progress.step_callback());
    report_a_step(progress, 0, 2);
    progress.step_start(1, 2, "save");
    progress.step_end(1.25, false);
  }
  const std::vector<json> ev = events(out.text());
  ASSERT_GE(ev.size(), 5u);
  EXPECT_EQ(ev.front(), json::parse(R"({"event":"step_start","index":0,"total":2,"op":"remesh"})"));
  double last = -1;
  std::size_t progress_events = 0;
  for (std::size_t i = 1; i + 3 < ev.size(); ++i) {
    EXPECT_EQ(ev[i]["event"], "step_progress") << ev[i];
    EXPECT_EQ(ev[i]["index"], 0);
    const double f = ev[i]["fraction"].get<double>();
    EXPECT_GE(f, 0.0);
    EXPECT_LE(f, 1.0);
    EXPECT_GT(f, last) << "fractions only grow";
    last = f;
    ++progress_events;
  }
  EXPECT_EQ(last, 1.0);  // 2.0 is clamped to 1
  EXPECT_LE(progress_events, 101u) << "one event per 1% at most";
  EXPECT_EQ(ev[ev.size() - 3], json::parse(R"({"event":"step_end","index":0,"ms":12.5,"status":"ok"})"));
  EXPECT_EQ(ev[ev.size() - 2], json::parse(R"({"event":"step_start","index":1,"total":2,"op":"save"})"));
  EXPECT_EQ(ev.back(), json::parse(R"({"event":"step_end","index":1,"ms":1.25,"status":"error"})"));
}

TEST(ProgressJson, TheSameReportsGiveTheSameEvents) {
  Capture a, b;
  {
    Progress pa(ProgressMode::Json, a.file()), pb(ProgressMode::Json, b.file());
    report_a_step(pa, 3, 6);
    report_a_step(pb, 3, 6);
  }
  EXPECT_EQ(a.text(), b.text());
}

TEST(ProgressJson, BatchEventsFromManyThreadsAreWholeLines) {
  Capture out;
  const int threads = 4, per_thread = 50;
  {
    Progress progress(ProgressMode::Json, out.file());
    progress.begin(threads * per_thread);
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t)
      pool.emplace_back([&progress, t] {
        for (int i = 0; i < per_thread; ++i) {
          const std::string input = "in/mesh \"" + std::to_string(t) + "\"\\" + std::to_string(i) + ".obj";
          progress.item_start(input);
          const bool bad = i % 10 == 0;
          progress.item_end(input, bad ? "error" : (i % 10 == 1 ? "skipped" : "ok"), 1.5,
                            bad ? "line 3: \"v\" needs 3 numbers\n" : "");
        }
      });
    for (std::thread& t : pool) t.join();
    progress.event(JsonEvent("shard").integer("index", 1).integer("count", 3));
    progress.finish();
  }
  const std::vector<json> ev = events(out.text());
  ASSERT_EQ(ev.size(), 2u + 2u * threads * per_thread + 1u);
  EXPECT_EQ(ev.front(), json::parse(R"({"event":"batch_start","total":200})"));
  std::size_t starts = 0, ends = 0, errors = 0;
  for (const json& e : ev) {
    starts += e["event"] == "item_start";
    ends += e["event"] == "item_end";
    if (e["event"] == "item_end" && e["status"] == "error") {
      ++errors;
      EXPECT_EQ(e["error"], "line 3: \"v\" needs 3 numbers\n");
    }
  }
  EXPECT_EQ(starts, 200u);
  EXPECT_EQ(ends, 200u);
  EXPECT_EQ(errors, 20u);
  EXPECT_EQ(ev[ev.size() - 2], json::parse(R"({"event":"shard","index":1,"count":3})"));
  const json& end = ev.back();
  EXPECT_EQ(end["event"], "batch_end");
  EXPECT_EQ(end["total"], 200);
  EXPECT_EQ(end["done"], 200);
  EXPECT_EQ(end["failures"], 20);
  EXPECT_GE(end["ms"].get<double>(), 0.0);
}

TEST(ProgressNone, WritesNothingAndHasNoCallback) {
  Capture out;
  {
    Progress progress(ProgressMode::None, out.file());
    EXPECT_FALSE(progress.step_callback());
    report_a_step(progress, 0, 1);
    progress.begin(3);
    progress.item_start("a.obj");
    progress.item_end("a.obj", "ok", 1);
    progress.event(JsonEvent("shard"));
    progress.finish();
  }
  EXPECT_EQ(out.text(), "");
}

TEST(ProgressModes, AutoIsNoneWhenTheStreamIsNotATerminal) {
  Capture out;
  EXPECT_EQ(resolve_progress_mode(ProgressMode::Auto, out.file()), ProgressMode::None);
  EXPECT_EQ(resolve_progress_mode(ProgressMode::Json, out.file()), ProgressMode::Json);
  EXPECT_EQ(Progress(ProgressMode::Auto, out.file()).mode(), ProgressMode::None);
  EXPECT_EQ(progress_mode_names().at("json"), ProgressMode::Json);
  EXPECT_EQ(progress_mode_names().size(), 3u);
}

// What a terminal would show at the end: the text after the last carriage return.
std::string last_segment(const std::string& text) {
  const std::size_t cr = text.rfind('\r');
  return cr == std::string::npos ? text : text.substr(cr + 1);
}

TEST(ProgressTerminal, ShowsALongStepWithItsFractionAndClearsIt) {
  Capture out;
  {
    Progress progress(ProgressMode::Terminal, out.file(), 0.0);  // show at once
    progress.step_start(2, 5, "remesh");
    progress.step_progress(0.42);
    std::this_thread::sleep_for(std::chrono::milliseconds(350));
    progress.step_end(350);
  }
  const std::string text = out.text();
  EXPECT_NE(text.find("\r  [2] remesh, step 3 of 5: 42%"), std::string::npos) << text;
  EXPECT_EQ(text.find('\n'), std::string::npos) << "a live line never scrolls";
  EXPECT_EQ(text.back(), '\r');
  EXPECT_EQ(last_segment(text.substr(0, text.size() - 1)).find_first_not_of(' '), std::string::npos)
      << "cleared at the end";
}

TEST(ProgressTerminal, ShowsNothingForAStepShorterThanASecond) {
  Capture out;
  {
    Progress progress(ProgressMode::Terminal, out.file());
    progress.step_start(0, 1, "bcm");
    progress.step_progress(0.5);
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
    progress.step_end(250);
  }
  EXPECT_EQ(out.text(), "");
}

TEST(ProgressTerminal, BatchLineCountsItemsAndMessagesGoAboveIt) {
  Capture out;
  {
    Progress progress(ProgressMode::Terminal, out.file());
    progress.begin(4);
    progress.item_end("a.obj", "ok", 10);
    progress.item_end("b.obj", "error", 10, "bad");
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
    progress.message("ffdtool: b.obj: bad");
    progress.finish();
  }
  const std::string text = out.text();
  EXPECT_NE(text.find("\r2/4 done, 1 failed, "), std::string::npos) << text;
  EXPECT_NE(text.find(" meshes/s, ETA "), std::string::npos) << text;
  // The message starts on a cleared line and ends with a newline.
  const std::size_t message = text.find("ffdtool: b.obj: bad\n");
  ASSERT_NE(message, std::string::npos) << text;
  ASSERT_GT(message, 0u);
  EXPECT_EQ(text[message - 1], '\r');
  EXPECT_EQ(last_segment(text.substr(0, text.size() - 1)).find_first_not_of(' '), std::string::npos) << text;
}

// What a remesh up (two lattice points moved) and back down (moved back) leaves, with or
// without a progress callback recording its fractions.
struct RemeshRun {
  std::vector<std::vector<std::uint32_t>> faces_up, faces_down;
  Eigen::Matrix3Xd positions_up, normals_up, positions_down;
  RemeshStats up, down;
};

RemeshRun remesh_up_and_down(std::vector<double>* fractions) {
  Mesh mesh = test::grid_mesh(40, [](double x, double y) { return 0.05 * std::sin(3 * x) * std::cos(2 * y); });
  WarpStack stack;
  const Parallelepiped box =
      Parallelepiped::from_min_max(Eigen::Vector3d(-0.01, -0.01, -0.5), Eigen::Vector3d(1.01, 1.01, 0.5));
  auto owned = std::make_unique<BSplineLattice>(box, Index3{6, 6, 4}, 3);
  BSplineLattice* lattice = owned.get();
  stack.push(mesh, "l", std::move(owned));
  const auto move = [&](const Index3& ijk, const Eigen::Vector3d& to) {
    lattice->move_point(ijk, to);
    stack.update(mesh, "l");
  };
  std::function<void(double)> callback;
  if (fractions) callback = [fractions](double f) { fractions->push_back(f); };
  RemeshOptions options;
  options.theta_max_deg = 4;
  options.theta_min_deg = 3;
  RemeshRun run;
  move({3, 2, 2}, lattice->point({3, 2, 2}) + Eigen::Vector3d(0.1, 0, 0.4));
  move({3, 4, 2}, lattice->point({3, 4, 2}) + Eigen::Vector3d(-0.1, 0.05, -0.3));
  HalfedgeCache cache;
  run.up = adaptive_remesh(mesh, cache, stack, options, callback);
  run.faces_up = mesh.faces();
  run.positions_up = mesh.positions();
  run.normals_up = mesh.normals();
  for (const Index3& p : {Index3{3, 2, 2}, Index3{3, 4, 2}}) move(p, lattice->rest_point(p));
  run.down = adaptive_remesh(mesh, cache, stack, options, callback);
  run.faces_down = mesh.faces();
  run.positions_down = mesh.positions();
  return run;
}

TEST(RemeshProgress, ReportsFractionsInRangeAndChangesNothing) {
  std::vector<double> fractions;
  const RemeshRun plain = remesh_up_and_down(nullptr), reported = remesh_up_and_down(&fractions);
  ASSERT_GT(plain.up.refinements, 2000u) << "enough to report during refinement";
  ASSERT_GT(plain.down.decimations, 2000u) << "and during decimation";
  EXPECT_EQ(reported.faces_up, plain.faces_up);
  EXPECT_EQ(reported.positions_up, plain.positions_up);
  EXPECT_EQ(reported.normals_up, plain.normals_up);
  EXPECT_EQ(reported.faces_down, plain.faces_down);
  EXPECT_EQ(reported.positions_down, plain.positions_down);
  for (const auto& [a, b] : {std::pair{reported.up, plain.up}, std::pair{reported.down, plain.down}}) {
    EXPECT_EQ(a.edges_tested, b.edges_tested);
    EXPECT_EQ(a.refinements, b.refinements);
    EXPECT_EQ(a.decimations, b.decimations);
    EXPECT_EQ(a.max_level_hits, b.max_level_hits);
    EXPECT_EQ(a.faces_after, b.faces_after);
    EXPECT_EQ(a.highest_level, b.highest_level);
  }
  // Reports during the scan, the refinement and the decimation, each run ending at 1.
  ASSERT_GT(fractions.size(), 6u);
  for (double f : fractions) {
    EXPECT_GE(f, 0.0);
    EXPECT_LE(f, 1.0);
  }
  EXPECT_EQ(std::count(fractions.begin(), fractions.end(), 1.0), 2);
  EXPECT_EQ(fractions.back(), 1.0);
}

TEST(BcmProgress, ReportsEachPhaseInOrderAndChangesNothing) {
  const Mesh mesh = test::sphere_mesh(3);
  const std::vector<std::uint32_t> support = test::pick(mesh, [](const Eigen::Vector3d& p) { return p.z() > -0.3; });
  const std::vector<BcmHandle> handles = {{"top", test::pick(mesh, [](const Eigen::Vector3d& p) { return p.z() > 0.8; })}};
  for (bool detail : {false, true}) {
    SCOPED_TRACE(detail ? "with detail" : "without detail");
    BcmOptions options;
    options.detail = detail;
    std::vector<double> fractions;
    BcmData plain = bcm_precompute(mesh, support, handles, options);
    BcmData reported = bcm_precompute(mesh, support, handles, options, [&](double f) { fractions.push_back(f); });
    EXPECT_EQ(reported.constant, plain.constant);
    EXPECT_EQ(reported.basis, plain.basis);
    const Eigen::Matrix3d linear = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()).toRotationMatrix();
    Eigen::Matrix3Xd a = mesh.positions(), b = mesh.positions();
    bcm_set_pose(plain, 0, linear, Eigen::Vector3d(0, 0.1, 0.2));
    bcm_set_pose(reported, 0, linear, Eigen::Vector3d(0, 0.1, 0.2));
    bcm_pose(plain, a);
    bcm_pose(reported, b);
    EXPECT_EQ(a, b);
    // One report per phase: regions, operator, system, factorization, basis (, detail).
    ASSERT_EQ(fractions.size(), detail ? 6u : 5u);
    for (std::size_t i = 1; i < fractions.size(); ++i) EXPECT_GT(fractions[i], fractions[i - 1]);
    EXPECT_GT(fractions.front(), 0.0);
    EXPECT_EQ(fractions.back(), 1.0);
  }
}

// A remesh, a bcm setup and a transform with saved frames on the bundled bunny.
const char* const kStagesScript = R"({"version": 1, "steps": [
  {"op": "lattice", "name": "body", "cells": [6, 6, 6], "box": {"fit": "aabb", "padding": 0.05}},
  {"op": "move", "lattice": "body", "select": {"box": {"min": [-10, 3, 1], "max": [10, 20, 20]}},
   "transform": {"translate": [0, 0, 1.2]}},
  {"op": "remesh"},
  {"op": "bcm", "name": "ear", "support": {"sphere": {"center": [0.0, 9.65, -1.36], "radius": 2.2}},
   "handles": [{"name": "tip", "select": {"sphere": {"center": [0.0, 9.65, -1.36], "radius": 0.5}}}], "k": 2},
  {"op": "transform", "editor": "ear", "frames": [{"translate": [0, 0.2, 0]}, {"translate": [0, 0.4, 0]},
   {"translate": [0, 0.6, 0]}], "save": "frame_{i}.obj"}]})";
const std::vector<std::string> kOps = {"lattice", "move", "remesh", "bcm", "transform"};
const std::vector<std::string> kOutputs = {"out.obj", "frame_0.obj", "frame_1.obj", "frame_2.obj"};

// `ffdtool run` of kStagesScript on the bunny into a fresh folder `name`; returns the exit code.
int run_script_in(const std::string& name, const std::string& extra, std::string& dir, std::string& err) {
  dir = test::temp_folder(name);
  test::write_file(dir + "/script.json", kStagesScript);
  return test::run_tool("run " + test::quoted(test::data("bunny.obj")) + " " + test::quoted(dir + "/script.json") +
                            " -o " + test::quoted(dir + "/out.obj") + " --stats " + test::quoted(dir + "/stats.json") +
                            (extra.empty() ? "" : " " + extra),
                        nullptr, &err);
}

// The lines of `text` that are events (start with '{'), parsed; the others are the
// run's own lines.
std::vector<json> event_lines(const std::string& text) {
  std::vector<json> out;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);)
    if (!line.empty() && line[0] == '{') out.push_back(json::parse(line));
  return out;
}

// Checks that `ev` is, for each step in order, its start, its progress (monotone, in
// [0, 1]) and its end. Returns the number of progress events per step.
std::vector<std::size_t> expect_step_sequence(const std::vector<json>& ev, const std::vector<std::string>& ops) {
  std::vector<std::size_t> progress(ops.size(), 0);
  std::size_t k = 0;
  for (std::size_t i = 0; i < ops.size(); ++i) {
    SCOPED_TRACE("step " + std::to_string(i));
    if (k >= ev.size()) {
      ADD_FAILURE() << "no events for step " << i;
      break;
    }
    EXPECT_EQ(ev[k++], (json{{"event", "step_start"}, {"index", i}, {"total", ops.size()}, {"op", ops[i]}}));
    double last = -1;
    for (; k < ev.size() && ev[k]["event"] == "step_progress"; ++k, ++progress[i]) {
      EXPECT_EQ(ev[k]["index"], i);
      const double f = ev[k]["fraction"].get<double>();
      EXPECT_TRUE(f > last && f >= 0 && f <= 1) << ev[k];
      last = f;
    }
    if (k >= ev.size()) break;
    EXPECT_EQ(ev[k]["event"], "step_end");
    EXPECT_EQ(ev[k]["index"], i);
    EXPECT_EQ(ev[k]["status"], "ok");
    EXPECT_GE(ev[k]["ms"].get<double>(), 0.0);
    ++k;
  }
  EXPECT_EQ(k, ev.size()) << "events after the last step";
  return progress;
}

TEST(ProgressCli, JsonGivesEveryStepsStartAndEndAndTheBcmSetupsProgress) {
  std::string dir, err;
  ASSERT_EQ(run_script_in("progress_json", "--progress json", dir, err), 0) << err;
  const std::vector<std::size_t> progress = expect_step_sequence(event_lines(err), kOps);
  EXPECT_GE(progress[3], 1u) << "the bcm setup reports its phases\n" << err;
  EXPECT_GE(progress[2], 1u) << "the remesh reports\n" << err;
  EXPECT_EQ(progress[4], 3u) << "frame i of 3\n" << err;
  // The per-step lines stay, each after its step's end event.
  EXPECT_NE(err.find("\"step_end\",\"index\":3,"), std::string::npos);
  EXPECT_LT(err.find("\"step_end\",\"index\":3,"), err.find("  [3] bcm 'ear'")) << err;
  // With --quiet, stderr holds the events alone.
  ASSERT_EQ(run_script_in("progress_json_quiet", "--progress json --quiet", dir, err), 0) << err;
  expect_step_sequence(events(err), kOps);
}

// The stats file in `dir` without times (remesh's "ms_*" too) and the run's own paths.
json counts_of(const std::string& dir) {
  json stats = test::without_measurements(json::parse(test::read_file(dir + "/stats.json")));
  stats["input"].erase("script");
  stats["output"].erase("mesh");
  for (json& step : stats["steps"])
    for (const char* key : {"ms_test", "ms_refine", "ms_decimate"}) step.erase(key);
  return stats;
}

TEST(ProgressCli, OutputsAreByteIdenticalWithAndWithoutProgress) {
  std::string with, without, err;
  ASSERT_EQ(run_script_in("progress_bytes_json", "--progress json", with, err), 0) << err;
  ASSERT_EQ(run_script_in("progress_bytes_none", "--progress none", without, err), 0) << err;
  for (const std::string& file : kOutputs) {
    const std::string a = test::read_file(with + "/" + file), b = test::read_file(without + "/" + file);
    EXPECT_FALSE(a.empty()) << file;
    EXPECT_TRUE(a == b) << file << " differs";
  }
  EXPECT_EQ(counts_of(with), counts_of(without));
}

// stderr with its times ("12.3 ms") blanked, to compare runs.
std::string without_times(const std::string& text) {
  return std::regex_replace(text, std::regex("[0-9][0-9.,]* ms"), "_ ms");
}

TEST(ProgressCli, ByDefaultNothingExtraGoesToAStderrThatIsNotATerminal) {
  std::string dir, by_default, none;
  ASSERT_EQ(run_script_in("progress_default", "", dir, by_default), 0) << by_default;
  ASSERT_EQ(run_script_in("progress_none", "--progress none", dir, none), 0) << none;
  EXPECT_EQ(by_default.find('\r'), std::string::npos);
  EXPECT_EQ(by_default.find('{'), std::string::npos);
  // The folders differ, and so do the paths in the first and last lines.
  const auto same_paths = [](std::string text) {
    return std::regex_replace(without_times(text), std::regex("progress_(default|none)"), "_");
  };
  EXPECT_EQ(same_paths(by_default), same_paths(none));
  EXPECT_NE(by_default.find("  [3] bcm 'ear'"), std::string::npos) << by_default;
}

TEST(ProgressCli, OnATerminalStepsShorterThanASecondShowNothing) {
  if (std::system("command -v script >/dev/null 2>&1") != 0) GTEST_SKIP() << "no script(1) to make a terminal";
  std::string dir, none;
  ASSERT_EQ(run_script_in("progress_tty_none", "--progress none", dir, none), 0) << none;
  // The same run with stderr on a pseudo-terminal (util-linux script) and the default.
  const std::string tty_dir = test::temp_folder("progress_tty_auto");
  test::write_file(tty_dir + "/script.json", kStagesScript);
  const std::string command = std::string(FFD_TOOL) + " run " + test::quoted(test::data("bunny.obj")) + " " +
                              test::quoted(tty_dir + "/script.json") + " -o " + test::quoted(tty_dir + "/out.obj") +
                              " --stats " + test::quoted(tty_dir + "/stats.json");
  const std::string typescript = tty_dir + "/typescript";
  ASSERT_EQ(std::system(("script -q -e -c \"" + command + "\" /dev/null </dev/null >" + typescript).c_str()), 0);
  std::string shown = test::read_file(typescript);
  shown = std::regex_replace(shown, std::regex("\r\n"), "\n");  // the terminal's line ends
  EXPECT_EQ(shown.find('\r'), std::string::npos) << shown;
  const auto same_paths = [](std::string text) {
    return std::regex_replace(without_times(text), std::regex("progress_tty_(auto|none)"), "_");
  };
  EXPECT_EQ(same_paths(shown), same_paths(none));
}

TEST(ProgressCli, AFailingStepEndsWithAnErrorEvent) {
  const std::string dir = test::temp_folder("progress_fail");
  test::write_file(dir + "/script.json", R"({"version": 1, "steps": [
    {"op": "lattice", "name": "body", "cells": [6, 6, 6]},
    {"op": "bcm", "name": "far", "support": {"sphere": {"center": [100, 100, 100], "radius": 1}},
     "handles": [{"name": "h", "select": {"sphere": {"center": [100, 100, 100], "radius": 0.5}}}]}]})");
  std::string err;
  EXPECT_EQ(test::run_tool("run " + test::quoted(test::data("bunny.obj")) + " " + test::quoted(dir + "/script.json") +
                               " -o " + test::quoted(dir + "/out.obj") + " --progress json --quiet",
                           nullptr, &err),
            2);
  const std::vector<json> ev = event_lines(err);
  ASSERT_EQ(ev.size(), 4u) << err;
  EXPECT_EQ(ev[3]["event"], "step_end");
  EXPECT_EQ(ev[3]["index"], 1);
  EXPECT_EQ(ev[3]["status"], "error");
  EXPECT_NE(err.find("ffdtool: error: "), std::string::npos) << err;
  EXPECT_EQ(test::run_tool("run " + test::quoted(test::data("bunny.obj")) + " " + test::quoted(dir + "/script.json") +
                           " -o " + test::quoted(dir + "/out.obj") + " --progress sometimes",
                           nullptr, &err),
            2);
  EXPECT_NE(err.find("--progress"), std::string::npos) << err;
}

}  // namespace
}  // namespace ffd
