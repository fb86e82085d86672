// The fuzz targets' seed corpus and every fixed finding (tests/fuzz/corpus/<target>/,
// tests/fuzz/regressions/<target>/) through the normal build: each input is read and
// either accepted or refused with an InputError, as the libFuzzer targets require.
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <map>
#include <string>

#include "common/errors.h"
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

Reader mesh_reader(PolygonSoup (*read)(std::string_view, const std::string&)) {
  return [read](const std::string& bytes) { build_mesh(read(bytes, "fuzz"), "fuzz"); };
}

TEST(FuzzCorpus, EveryInputIsReadOrRefusedWithAnInputError) {
  const std::map<std::string, Reader> targets = {
      {"obj", mesh_reader(read_obj)}, {"off", mesh_reader(read_off)},
      {"ply", mesh_reader(read_ply)}, {"stl", mesh_reader(read_stl)},
      {"script", [](const std::string& text) { parse_script(text, "fuzz.json"); }}};
  std::size_t inputs = 0;
  for (const auto& [name, read] : targets)
    for (const char* kind : {"corpus", "regressions"}) {
      const fs::path folder = fs::path(FFD_SOURCE_DIR) / "tests" / "fuzz" / kind / name;
      ASSERT_TRUE(fs::is_directory(folder)) << folder;
      for (const auto& entry : fs::directory_iterator(folder)) {
        if (entry.path().filename().string()[0] == '.') continue;
        ++inputs;
        const std::string bytes = test::read_file(entry.path().string());
        try {
          read(bytes);
        } catch (const InputError&) {
        } catch (const std::exception& e) {
          ADD_FAILURE() << entry.path() << ": threw something other than InputError: " << e.what();
        }
      }
    }
  EXPECT_GE(inputs, 10u);
}

}  // namespace
}  // namespace ffd
