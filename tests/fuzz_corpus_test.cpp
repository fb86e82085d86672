// The fuzz targets' seed corpus and every fixed finding (tests/fuzz/corpus/<target>/,
// tests/fuzz/regressions/<target>/) through the normal build: each input is read and
// either accepted or refused with an InputError, as the libFuzzer targets require; the
// `run` target's scripts run on its sphere or fail with one of ffdtool's errors.
#include <gtest/gtest.h>

#include <filesystem>
#include <algorithm>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "common/errors.h"
#include "fuzz/compressed_input.h"
#include "fuzz/gltf_input.h"
#include "fuzz/reader_paths.h"
#include "fuzz/run_input.h"
#include "fuzz/volume_input.h"
#include "mesh/build_mesh.h"
#include "mesh/obj_io.h"
#include "mesh/off_io.h"
#include "mesh/ply_io.h"
#include "mesh/stl_io.h"
#include "script/script.h"
#include "test_meshes.h"

namespace ffd {
namespace {

namespace fs = std::filesystem;

using Reader = std::function<void(const std::string&)>;

// The inputs of a target's seed corpus and regressions, hidden files left out.
std::vector<fs::path> inputs_of(const std::string& target) {
  std::vector<fs::path> paths;
  for (const char* kind : {"corpus", "regressions"}) {
    const fs::path folder = fs::path(FFD_SOURCE_DIR) / "tests" / "fuzz" / kind / target;
    if (!fs::is_directory(folder)) {
      ADD_FAILURE() << folder << " is missing";
      continue;
    }
    for (const auto& entry : fs::directory_iterator(folder))
      if (entry.path().filename().string()[0] != '.') paths.push_back(entry.path());
  }
  std::sort(paths.begin(), paths.end());
  return paths;
}

Reader mesh_reader(PolygonSoup (*read)(std::string_view, const std::string&)) {
  return [read](const std::string& bytes) { build_mesh(read(bytes, "fuzz"), "fuzz"); };
}

TEST(FuzzCorpus, EveryInputIsReadOrRefusedWithAnInputError) {
  std::map<std::string, Reader> targets = {
      {"obj", [](const std::string& bytes) { fuzz::check_obj_paths_agree(bytes), mesh_reader(read_obj)(bytes); }},
      {"off", [](const std::string& bytes) { fuzz::check_off_paths_agree(bytes), mesh_reader(read_off)(bytes); }},
      {"ply", mesh_reader(read_ply)}, {"stl", mesh_reader(read_stl)},
      {"gltf", [](const std::string& bytes) { fuzz::check_gltf_round_trip(bytes); }},
      {"gltf_draco", [](const std::string& bytes) { fuzz::check_gltf_round_trip(fuzz::draco_glb(bytes)); }},
      {"gltf_meshopt", [](const std::string& bytes) { fuzz::check_gltf_round_trip(fuzz::meshopt_glb(bytes)); }},
      {"script", [](const std::string& text) { parse_script(text, "fuzz.json"); }}};
  for (const char* format : {"vtu", "vtk", "msh", "su2", "foam"})
    targets.emplace(format, [format](const std::string& bytes) { fuzz::check_volume_round_trip(format, bytes); });
  std::size_t inputs = 0;
  for (const auto& [name, read] : targets)
    for (const fs::path& path : inputs_of(name)) {
      ++inputs;
      try {
        read(test::read_file(path.string()));
      } catch (const InputError&) {
      } catch (const std::exception& e) {
        ADD_FAILURE() << path << ": threw something other than InputError: " << e.what();
      }
    }
  EXPECT_GE(inputs, 10u);
}

// fuzz_run's inputs: each script within the harness's budget runs on its sphere, or fails
// with one of ffdtool's errors; the seeds are all within the budget and valid.
TEST(FuzzCorpus, EveryRunScriptRunsOrFailsWithAnFfdError) {
  using Outcome = fuzz::RunSandbox::Outcome;
  fuzz::RunSandbox sandbox;
  std::size_t seeds_run = 0;
  for (const fs::path& path : inputs_of("run")) {
    const bool seed = path.parent_path().parent_path().filename() == "corpus";
    try {
      const Outcome outcome = sandbox.run(test::read_file(path.string()));
      if (seed) {
        EXPECT_EQ(outcome, Outcome::Ran) << path << ": " << sandbox.error();
      }
      seeds_run += seed && outcome == Outcome::Ran;
    } catch (const std::exception& e) {
      ADD_FAILURE() << path << ": threw something other than ffdtool's errors: " << e.what();
    }
  }
  EXPECT_GE(seeds_run, 5u);
}

}  // namespace
}  // namespace ffd
