#include "compare_command.h"

#include <cstdio>
#include <ctime>
#include <filesystem>
#include <iostream>

#include <nlohmann/json.hpp>

#include "batch/folder_compare.h"
#include "common/errors.h"
#include "common/junit.h"
#include "common/timer.h"
#include "mesh/mesh_io.h"

namespace ffdcli {
namespace fs = std::filesystem;
using Status = ffd::PairResult::Status;

CLI::App* add_compare(CLI::App& app, CompareArgs& c) {
  CLI::App* cmd = app.add_subcommand("compare", "Compare two meshes, or two folders pair by pair (exit 0 same, 1 different)");
  cmd->add_option("a", c.a, "First mesh, or folder")->required();
  cmd->add_option("b", c.b, "Second mesh, or folder (its files paired with A's by relative path)")->required();
  cmd->add_option("--tolerance", c.compare.tolerance, "Largest distance still 'same', in mesh units")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--metric", c.compare.metric, "vertex: vertex i against vertex i; hausdorff: surfaces")
      ->check(CLI::IsMember({"vertex", "hausdorff"}))
      ->capture_default_str();
  cmd->add_option("--error-bound", c.compare.error_bound,
                  "hausdorff: the reported distance is within this of the true one (default: tolerance / 10)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--threads", c.compare.threads, "hausdorff: threads for a pair (default: all cores); same result")
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("--json", c.json, "Print the result as JSON");
  cmd->add_option("--heatmap", c.heatmap, "Also draw B coloured by its distance to A (grey within tolerance) to this PNG");
  cmd->add_option("--heatmap-dir", c.heatmap_dir, "Folders: a heat map per differing pair, as DIR/PATH.png");
  cmd->add_flag("--recursive", c.recursive, "Folders: their subfolders' files too");
  cmd->add_option("--jobs", c.jobs, "Folders: pairs at once (default: one per core); same output")->check(CLI::PositiveNumber);
  cmd->add_option("--junit", c.junit, "Also write a JUnit XML report (a test case per pair) to this file");
  add_picture_options(cmd, c.picture);
  return cmd;
}

namespace {

nlohmann::ordered_json difference_json(const ffd::MeshDifference& d, const ffd::CompareOptions& options) {
  const bool within = ffd::within_tolerance(d, options.tolerance);
  nlohmann::ordered_json j = {{"metric", d.metric}, {"comparable", d.comparable}, {"within_tolerance", within},
                              {"tolerance", options.tolerance}, {"same_connectivity", d.same_connectivity}};
  if (d.comparable) {
    j["max"] = d.max;
    j["mean"] = d.mean;
    j["rms"] = d.rms;
    if (d.metric == "vertex") j["worst_vertex"] = d.worst_vertex;
    if (d.metric == "hausdorff") {
      j["error_bound"] = d.error_bound;
      j["max_upper"] = d.max_upper;
      j["points_measured"] = d.points;
    }
  }
  if (!d.reason.empty()) j["reason"] = d.reason;
  return j;
}

void print_difference(const ffd::MeshDifference& d, const ffd::CompareOptions& options) {
  if (!d.comparable) {
    std::printf("not comparable: %s\n", d.reason.c_str());
  } else {
    std::printf("%s distance: max %.6g, mean %.6g, rms %.6g", d.metric.c_str(), d.max, d.mean, d.rms);
    if (d.metric == "vertex") std::printf(" (worst: vertex %zu)", d.worst_vertex);
    if (d.metric == "hausdorff") std::printf(" (max within %.3g: at most %.6g)", d.error_bound, d.max_upper);
    std::printf("\n");
    if (d.metric == "vertex" && !d.same_connectivity) std::printf("connectivity differs: %s\n", d.reason.c_str());
  }
  std::printf("%s (tolerance %g)\n", ffd::within_tolerance(d, options.tolerance) ? "same" : "different",
              options.tolerance);
}

ffd::JUnitSuite junit_suite(const CompareArgs& c, double seconds) {
  ffd::JUnitSuite suite;
  suite.name = "ffdtool compare " + c.a + " " + c.b;
  suite.seconds = seconds;
  suite.timestamp = ffd::junit_timestamp(std::time(nullptr));
  suite.hostname = ffd::junit_hostname();
  return suite;
}

ffd::JUnitCase junit_case(const ffd::PairResult& r) {
  ffd::JUnitCase t;
  t.name = r.path;
  t.classname = "ffdtool.compare";
  t.seconds = r.ms / 1000;
  t.outcome = r.status == Status::Same    ? ffd::JUnitCase::Outcome::Passed
              : r.status == Status::Error ? ffd::JUnitCase::Outcome::Error
                                          : ffd::JUnitCase::Outcome::Failed;  // different, or on one side only
  t.message = r.status == Status::OnlyInA ? "only in A (missing from B)"
              : r.status == Status::OnlyInB ? "only in B (missing from A)"
                                            : r.message;
  return t;
}

int command_compare_pair(const CompareArgs& c) {
  if (!c.heatmap_dir.empty() || c.recursive || c.jobs)
    throw ffd::InputError(std::string(!c.heatmap_dir.empty() ? "--heatmap-dir" : c.recursive ? "--recursive" : "--jobs") +
                          " is for comparing two folders; " + c.a + " and " + c.b + " are files");
  if (!c.heatmap.empty()) check_heatmap_path(c.heatmap);
  ffd::Stopwatch clock;
  ffd::PairResult r;
  r.path = c.b;
  const auto [a, b] = ffd::read_mesh_pair(c.a, c.b);
  ffd::MeshDifference d = ffd::compare_meshes(a, b, c.compare);
  if (!c.heatmap.empty()) write_heatmap(c.heatmap, b, d, c.compare.tolerance, c.picture);
  const bool within = ffd::within_tolerance(d, c.compare.tolerance);
  if (c.json)
    std::cout << difference_json(d, c.compare).dump(2) << "\n";
  else
    print_difference(d, c.compare);
  if (!c.junit.empty()) {
    r.status = within ? Status::Same : Status::Different;
    r.message = within ? "" : ffd::difference_line(d, c.compare.tolerance);
    r.ms = clock.ms();
    ffd::JUnitSuite suite = junit_suite(c, r.ms / 1000);
    suite.cases.push_back(junit_case(r));
    ffd::write_junit(c.junit, suite);
  }
  return within ? 0 : 1;
}

}  // namespace

namespace {

const char* status_word(Status s) {
  switch (s) {
    case Status::Same: return "same";
    case Status::Different: return "different";
    case Status::OnlyInA: return "only_in_a";
    case Status::OnlyInB: return "only_in_b";
    case Status::Error: return "error";
  }
  return "";
}

nlohmann::ordered_json folder_json(const ffd::FolderComparison& f, const CompareArgs& c) {
  nlohmann::ordered_json pairs = nlohmann::ordered_json::array();
  for (const ffd::PairResult& r : f.pairs) {
    nlohmann::ordered_json j = {{"path", r.path}, {"status", status_word(r.status)}};
    if (r.status == Status::Same || r.status == Status::Different) j["difference"] = difference_json(r.difference, c.compare);
    if (!r.message.empty()) j["message"] = r.message;
    pairs.push_back(j);
  }
  nlohmann::ordered_json j = {{"a", c.a}, {"b", c.b}, {"metric", c.compare.metric}, {"tolerance", c.compare.tolerance},
                              {"pairs", f.pairs.size()}, {"same", f.same}, {"different", f.different},
                              {"missing", f.only_in_a + f.only_in_b}, {"only_in_a", f.only_in_a},
                              {"only_in_b", f.only_in_b}, {"errors", f.errors}};
  if (f.worst < f.pairs.size()) j["worst"] = {{"path", f.pairs[f.worst].path}, {"max", f.pairs[f.worst].difference.max}};
  j["results"] = pairs;
  return j;
}

// A line per pair that is not the same, then the summary.
void print_folder(const ffd::FolderComparison& f, const CompareArgs& c) {
  for (const ffd::PairResult& r : f.pairs) {
    if (r.status == Status::Same) continue;
    const std::string what = r.status == Status::OnlyInA   ? "only in " + c.a + " (missing from " + c.b + ")"
                             : r.status == Status::OnlyInB ? "only in " + c.b + " (missing from " + c.a + ")"
                                                           : r.message;
    std::printf("%-9s %s: %s\n", r.status == Status::Error ? "error" : r.status == Status::Different ? "different" : "missing",
                r.path.c_str(), what.c_str());
  }
  std::printf("compare: %zu pairs: %zu same, %zu different, %zu missing, %zu errors", f.pairs.size(), f.same,
              f.different, f.only_in_a + f.only_in_b, f.errors);
  if (f.worst < f.pairs.size())
    std::printf("; worst %s distance %.6g (%s)", c.compare.metric.c_str(), f.pairs[f.worst].difference.max,
                f.pairs[f.worst].path.c_str());
  std::printf(" (tolerance %g)\n", c.compare.tolerance);
}

// DIR/PATH.png for a differing pair's heat map.
std::function<void(const ffd::PairResult&, const ffd::Mesh&)> heatmap_writer(const CompareArgs& c) {
  if (c.heatmap_dir.empty()) return nullptr;
  return [&c](const ffd::PairResult& r, const ffd::Mesh& b) {
    const fs::path png = fs::path(c.heatmap_dir) / (r.path + ".png");
    std::error_code ec;
    fs::create_directories(png.parent_path(), ec);
    if (!r.difference.distances.empty()) write_heatmap(png.string(), b, r.difference, c.compare.tolerance, c.picture);
  };
}

int command_compare_folders(const CompareArgs& c) {
  if (!c.heatmap.empty())
    throw ffd::InputError("--heatmap draws one pair; for folders give --heatmap-dir DIR (a picture per differing pair)");
  std::error_code ec;
  if (!c.heatmap_dir.empty() && fs::exists(c.heatmap_dir, ec) && !fs::is_directory(c.heatmap_dir, ec))
    throw ffd::InputError(ffd::At{c.heatmap_dir}, "--heatmap-dir names a file, not a folder");
  ffd::Stopwatch clock;
  ffd::FolderCompareOptions options{c.compare, c.recursive, c.jobs, heatmap_writer(c)};
  const ffd::FolderComparison f = ffd::compare_folders(c.a, c.b, options);
  for (const ffd::PairResult& r : f.pairs)  // a mesh that cannot be read: its error line, as elsewhere
    if (r.status == Status::Error) std::fprintf(stderr, "ffdtool: error: %s\n", r.message.c_str());
  if (c.json)
    std::cout << folder_json(f, c).dump(2) << "\n";
  else
    print_folder(f, c);
  if (!c.junit.empty()) {
    ffd::JUnitSuite suite = junit_suite(c, clock.ms() / 1000);
    for (const ffd::PairResult& r : f.pairs) suite.cases.push_back(junit_case(r));
    ffd::write_junit(c.junit, suite);
  }
  if (f.errors) return 2;
  return f.different || f.only_in_a || f.only_in_b ? 1 : 0;
}

}  // namespace

int command_compare(const CompareArgs& c) {
  if (!c.junit.empty()) ffd::require_output_folder(c.junit, "the JUnit report");
  std::error_code ec;
  const bool folder_a = fs::is_directory(c.a, ec), folder_b = fs::is_directory(c.b, ec);
  if (folder_a != folder_b) {
    const std::string& file = folder_a ? c.b : c.a;
    const std::string& folder = folder_a ? c.a : c.b;
    if (!fs::exists(file, ec)) throw ffd::InputError(ffd::At{file}, "no such file or folder");
    throw ffd::InputError(ffd::At{file}, "is a file, but " + folder + " is a folder: compare two meshes or two folders");
  }
  return folder_a ? command_compare_folders(c) : command_compare_pair(c);
}

}  // namespace ffdcli
