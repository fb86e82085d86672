#include "run_input.h"

#include <stdlib.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "common/errors.h"
#include "script/runner.h"
#include "script/script.h"

namespace ffd::fuzz {
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

constexpr std::size_t kMaxSteps = 12, kMaxLattices = 4, kMaxCells = 8, kMaxRemesh = 3, kMaxLevel = 3;
constexpr std::size_t kMaxEditors = 3, kMaxHandles = 4, kMaxFrames = 4, kMaxSaves = 4;
constexpr std::size_t kMaxDragPoints = 16, kMaxMovePoints = 64;

// Counts of the costly things in a script, step by step.
struct Costs {
  std::size_t lattices = 0, remesh = 0, editors = 0, saves = 0, min_volume = 0;
};

std::size_t list_size(const json& step, const char* key) {
  const auto it = step.find(key);
  return it != step.end() && it->is_array() ? it->size() : 0;
}

// Why one step is over the budget, or "".
std::string step_over_budget(const json& step, Costs& c) {
  const std::string op = step.value("op", "");
  if (op == "lattice") {
    ++c.lattices;
    if (step.value("basis", "") == "octree") {
      // Octree lattices: levels + Catmull-Clark steps bound the finest subdivided grid.
      if (step.at("levels").get<int>() + step.at("cc_steps").get<int>() > 6)
        return "an octree lattice with levels + cc_steps above 6";
    } else {
      for (const json& n : step.at("cells"))
        if (n.get<std::size_t>() > kMaxCells) return "a lattice with more than 8 cells on an axis";
    }
    if (step.at("box").value("fit", "") == "min_volume") ++c.min_volume;
  } else if (op == "remesh") {
    ++c.remesh;
    if (step.at("max_level").get<std::size_t>() > kMaxLevel) return "remesh max_level above 3";
  } else if (op == "bcm") {
    ++c.editors;
    if (list_size(step, "handles") > kMaxHandles) return "a bcm editor with more than 4 handles";
  } else if (op == "transform") {
    if (list_size(step, "frames") > kMaxFrames) return "more than 4 frames";
    if (step.contains("save")) c.saves += std::max<std::size_t>(1, list_size(step, "frames"));
  } else if (op == "save") {
    ++c.saves;
  } else if (op == "drag") {
    if (list_size(step, "points") > kMaxDragPoints) return "more than 16 drag points";
  } else if (op == "move") {
    if (list_size(step, "points") > kMaxMovePoints) return "more than 64 moved points";
  }
  return "";
}

// The UV sphere: poles on the z axis, kRings - 1 rings of kSegments vertices between.
constexpr int kRings = 10, kSegments = 18;

int ring_vertex(int ring, int segment) {  // 1-based OBJ index, ring in [1, kRings - 1]
  return 2 + (ring - 1) * kSegments + (segment % kSegments);
}

}  // namespace

std::string over_budget(const json& resolved) {
  const json& steps = resolved.at("steps");
  if (steps.size() > kMaxSteps) return "more than 12 steps";
  Costs c;
  for (const json& step : steps) {
    std::string why = step_over_budget(step, c);
    if (!why.empty()) return why;
  }
  if (c.lattices > kMaxLattices) return "more than 4 lattices";
  if (c.remesh > kMaxRemesh) return "more than 3 remesh steps";
  if (c.editors > kMaxEditors) return "more than 3 bcm editors";
  if (c.saves > kMaxSaves) return "more than 4 saved meshes";
  if (c.min_volume > 0) return "a min_volume box";
  return "";
}

std::string sphere_obj() {
  const double pi = std::acos(-1.0);
  std::string s = "# fuzz_run's sphere\nv 0 0 1\n";
  char line[96];
  for (int r = 1; r < kRings; ++r)
    for (int k = 0; k < kSegments; ++k) {
      const double theta = pi * r / kRings, phi = 2 * pi * k / kSegments;
      std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", std::sin(theta) * std::cos(phi),
                    std::sin(theta) * std::sin(phi), std::cos(theta));
      s += line;
    }
  s += "v 0 0 -1\n";
  const int south = 2 + (kRings - 1) * kSegments;
  for (int k = 0; k < kSegments; ++k) {
    std::snprintf(line, sizeof line, "f 1 %d %d\n", ring_vertex(1, k), ring_vertex(1, k + 1));
    s += line;
    for (int r = 1; r + 1 < kRings; ++r) {
      const int a0 = ring_vertex(r, k), a1 = ring_vertex(r, k + 1);
      const int b0 = ring_vertex(r + 1, k), b1 = ring_vertex(r + 1, k + 1);
      std::snprintf(line, sizeof line, "f %d %d %d\nf %d %d %d\n", a0, b0, b1, a0, b1, a1);
      s += line;
    }
    std::snprintf(line, sizeof line, "f %d %d %d\n", ring_vertex(kRings - 1, k), south, ring_vertex(kRings - 1, k + 1));
    s += line;
  }
  return s;
}

RunSandbox::RunSandbox() {
  std::string pattern = (fs::temp_directory_path() / "ffd_fuzz_run.XXXXXX").string();
  if (!::mkdtemp(pattern.data())) throw std::runtime_error("fuzz_run: cannot create a temporary folder");
  folder_ = pattern;
  fs::create_directory(folder_ + "/out");
  std::ofstream(folder_ + "/mesh.obj", std::ios::binary) << sphere_obj();
}

RunSandbox::~RunSandbox() {
  std::error_code ec;
  fs::remove_all(folder_, ec);
}

RunSandbox::Outcome RunSandbox::run(std::string_view text) {
  error_.clear();
  try {
    return run_parsed(text);
  } catch (const Error& e) {
    error_ = e.what();
    return Outcome::Failed;
  }
}

RunSandbox::Outcome RunSandbox::run_parsed(std::string_view text) {
  const std::string script_path = folder_ + "/s.json";
  try {
    const Script script = parse_script(std::string(text), script_path);
    if (!over_budget(script.resolved).empty()) return Outcome::OverBudget;
  } catch (const InputError& e) {
    error_ = e.what();
    return Outcome::Refused;
  }
  std::ofstream(script_path, std::ios::binary | std::ios::trunc) << text;
  RunOptions options;
  options.mesh = folder_ + "/mesh.obj";
  options.script = script_path;
  options.output = folder_ + "/out/out.obj";
  options.stats = folder_ + "/out/stats.json";
  options.quiet = true;
  options.threads = 1;
  struct EmptyOut {  // on every way out of the run
    const std::string& folder;
    ~EmptyOut() {
      std::error_code ec;
      for (const auto& entry : fs::directory_iterator(folder + "/out", ec)) fs::remove_all(entry.path(), ec);
    }
  } empty_out{folder_};
  run_script(options);
  return Outcome::Ran;
}

}  // namespace ffd::fuzz
