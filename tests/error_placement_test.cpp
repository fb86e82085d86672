// Every error type an op can raise below lib/script reaches the user as one line naming
// the script and the JSON pointer of the key it concerns (placed by the op tables, not by
// reading messages), with exit 2 for input and topology errors and 3 for solver and I/O
// failures, and nothing written.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <string>

#include "common/errors.h"
#include "script/runner.h"
#include "script/scene.h"
#include "script/script.h"
#include "test_meshes.h"

namespace ffd {
namespace {

using test::data;
using test::files_in;
using test::quoted;
using test::read_file;
using test::script_with;
using test::temp_folder;
using test::write_file;

struct LimitedRun {
  int exit = -1;
  std::string err;
};

// Runs `ffdtool run MESH dir/s.json -o dir/out/out.obj` with `limits` (shell commands such
// as "ulimit -v 100000") applied first.
LimitedRun run_limited(const std::string& dir, const std::string& mesh, const std::string& limits) {
  const std::string command = "(" + limits + "; exec " FFD_TOOL " run " + quoted(mesh) + " " +
                              quoted(dir + "/s.json") + " -o " + quoted(dir + "/out/out.obj") + " --quiet) 2>" +
                              quoted(dir + "/stderr");
  const int status = std::system(command.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_file(dir + "/stderr")};
}

// Checks one error line "ffdtool: error: <place>: ..." naming `place` and `mentions`.
void expect_error(const LimitedRun& o, int exit, const std::string& place, const std::string& mention) {
  EXPECT_EQ(o.exit, exit) << o.err;
  EXPECT_EQ(o.err.rfind("ffdtool: error: " + place + ": ", 0), 0u) << o.err;
  EXPECT_NE(o.err.find(mention), std::string::npos) << o.err;
  EXPECT_EQ(o.err.find('\n'), o.err.size() - 1) << "not one line: " << o.err;
}

// A folder with s.json = `script` and an empty out/.
std::string case_folder(const std::string& name, const std::string& script) {
  const std::string dir = temp_folder(name);
  write_file(dir + "/s.json", script);
  std::filesystem::create_directories(dir + "/out");
  return dir;
}

// InputError about an argument of the BCM editor (element 0 of its handles).
TEST(ErrorPlacement, InputErrorAboutAnAlgorithmsArgumentNamesItsKey) {
  const std::string dir = case_folder("place_input", script_with(R"({"op": "bcm", "name": "e",
      "support": {"sphere": {"center": [1.24, 6.29, 1.05], "radius": 1.0}},
      "handles": [{"name": "h", "select": {"sphere": {"center": [0, 9.65, -1.36], "radius": 0.5}}}]})"));
  const LimitedRun o = run_limited(dir, data("bunny.obj"), "true");
  expect_error(o, 2, dir + "/s.json: /steps/0/handles/0/select", "outside the support");
  EXPECT_TRUE(files_in(dir + "/out").empty());
}

// InputError from the warp code building a box, which knows nothing of keys: the lattice
// op says the box is what it concerns.
TEST(ErrorPlacement, InputErrorFromTheWarpCodeNamesTheBox) {
  const std::string dir = case_folder("place_box", script_with(R"({"op": "lattice", "name": "b", "cells": [4, 4, 4],
      "box": {"origin": [0, 0, 0], "axes": [[1, 0, 0], [2, 0, 0], [0, 0, 1]]}})"));
  const LimitedRun o = run_limited(dir, data("bunny.obj"), "true");
  expect_error(o, 2, dir + "/s.json: /steps/0/box", "degenerate");
}

// A lattice frozen by a surface edit, then moved: the scene says "lattice", the op table
// places it at the step's lattice key.
TEST(ErrorPlacement, AFrozenLatticeNamesTheLatticeKey) {
  const std::string dir = case_folder("place_frozen", script_with(R"({"op": "lattice", "name": "b", "cells": [4, 4, 4]},
      {"op": "bcm", "name": "e", "support": {"sphere": {"center": [1.24, 6.29, 1.05], "radius": 2.0}},
       "handles": [{"name": "h", "select": {"near": [1.24, 6.29, 1.05]}}]},
      {"op": "move", "lattice": "b", "points": [{"index": [2, 2, 2], "by": [0, 0, 1]}]})"));
  const LimitedRun o = run_limited(dir, data("bunny.obj"), "true");
  expect_error(o, 2, dir + "/s.json: /steps/2/lattice", "frozen into the mesh by the surface edit at /steps/1");
}

// The remesher's own InputError about its l_max option: after a surface edit froze the
// lattice, "auto" has no lattice cell to take.
TEST(ErrorPlacement, TheRemeshersErrorNamesLMax) {
  const std::string dir = case_folder("place_l_max", script_with(R"({"op": "lattice", "name": "b", "cells": [4, 4, 4]},
      {"op": "bcm", "name": "e", "support": {"sphere": {"center": [1.24, 6.29, 1.05], "radius": 2.0}},
       "handles": [{"name": "h", "select": {"near": [1.24, 6.29, 1.05]}}]},
      {"op": "remesh"})"));
  expect_error(run_limited(dir, data("bunny.obj"), "true"), 2, dir + "/s.json: /steps/2/l_max", "no lattice");
}

// TopologyError (quads where the k-harmonic system needs triangles): exit 2 at the
// support, and the type that reaches the runner is TopologyError.
TEST(ErrorPlacement, TopologyErrorIsAnInputErrorAtTheSupport) {
  const std::string script = script_with(R"({"op": "bcm", "name": "e", "support": {"box": {"min": [2, 2, -1], "max": [6, 6, 1]}},
      "handles": [{"name": "h", "select": {"near": [4, 4, 0]}}]})");
  const std::string dir = case_folder("place_topology", script);
  write_file(dir + "/quads.obj", test::grid_obj(8, true));
  expect_error(run_limited(dir, dir + "/quads.obj", "true"), 2, dir + "/s.json: /steps/0/support", "4 sides");

  const Script parsed = parse_script(script, "s.json");
  Scene scene;
  scene.mesh = read_mesh(dir + "/quads.obj");
  StepContext ctx;
  try {
    run_step(parsed, *parsed.steps[0], scene, ctx);
    FAIL() << "quads were accepted";
  } catch (const TopologyError& e) {
    EXPECT_EQ(e.subject().argument, "support");
    EXPECT_EQ(e.place(), "s.json: /steps/0/support");
  }
}

// SolverError: the sparse Cholesky factor does not fit in the memory the run may use.
// Between plenty and too little for anything, some limit leaves room for the system but
// not for its factor; every limit either succeeds or fails with one line.
TEST(ErrorPlacement, SolverErrorExitsThreeAtTheStep) {
#ifdef FFD_SANITIZE
  GTEST_SKIP() << "an ASan build cannot start under ulimit -v: its shadow memory is address space";
#endif
  const std::string dir = case_folder("place_solver", script_with(R"({"op": "bcm", "name": "e", "detail": false,
      "support": {"box": {"min": [2, 2, -1], "max": [198, 198, 1]}},
      "handles": [{"name": "h", "select": {"sphere": {"center": [100, 100, 0], "radius": 3}}}]})"));
  write_file(dir + "/grid.obj", test::grid_obj(200));
  bool solver_failed = false;
  for (int kb = 240000; kb >= 60000 && !solver_failed; kb -= 10000) {
    const LimitedRun o = run_limited(dir, dir + "/grid.obj",
                                  "export OMP_NUM_THREADS=1 MALLOC_ARENA_MAX=1; ulimit -v " + std::to_string(kb));
    ASSERT_TRUE(o.exit == 0 || o.exit == 3) << "limit " << kb << " KB: exit " << o.exit << ": " << o.err;
    if (o.exit == 0) {
      std::filesystem::remove(dir + "/out/out.obj");
      continue;
    }
    EXPECT_EQ(o.err.find('\n'), o.err.size() - 1) << "not one line: " << o.err;
    EXPECT_TRUE(files_in(dir + "/out").empty()) << "limit " << kb << " KB left files behind";
    if (o.err.find("sparse Cholesky") == std::string::npos) continue;
    expect_error(o, 3, dir + "/s.json: /steps/0", "out of memory");
    solver_failed = true;
  }
  EXPECT_TRUE(solver_failed) << "no memory limit made the factorization fail";
}

// IoError: a save that cannot be written (the file size limit stands in for a full disk)
// exits 3 naming the file, and leaves nothing behind.
TEST(ErrorPlacement, IoErrorExitsThreeNamingTheFile) {
  const std::string dir = case_folder("place_io", script_with(R"({"op": "lattice", "name": "b", "cells": [4, 4, 4]},
      {"op": "save", "path": "mid.obj"})"));
  const LimitedRun o = run_limited(dir, data("bunny.obj"), "trap '' XFSZ; ulimit -f 64");
  expect_error(o, 3, dir + "/out/mid.obj", "cannot write: File too large");
  EXPECT_TRUE(files_in(dir + "/out").empty());
}

}  // namespace
}  // namespace ffd
