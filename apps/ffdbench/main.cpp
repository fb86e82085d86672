// ffdbench [--suite NAME|all] [--quick] [--meshes DIR] [--test-data DIR] [--ffdtool PATH]
//          [--blender PATH] [-o FILE]
// Runs benchmark suites and prints one JSON object: suite -> rows with throughput,
// times and ratios against a baseline measured in the same run.
#include <cstdio>
#include <cstring>
#include <iostream>
#include <omp.h>

#include "bench.h"
#include "child_run.h"
#include "common/atomic_file.h"
#include "common/errors.h"
#include "script/runner.h"

int main(int argc, char** argv) {
  // Launcher mode (child_run.h): first, while this process is still small.
  if (argc > 1 && std::strcmp(argv[1], "--launch") == 0) return ffd::bench::launch_main(argc, argv);
  ffd::bench::Context ctx;
  ctx.meshes = "../shared/meshes";
  ctx.test_data = "test_data";
  std::string suite = "all", output;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "ffdbench: error: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--suite") suite = value();
    else if (a == "--quick") ctx.quick = true;
    else if (a == "--meshes") ctx.meshes = value();
    else if (a == "--test-data") ctx.test_data = value();
    else if (a == "--ffdtool") ctx.ffdtool = value();
    else if (a == "--blender") ctx.blender = value();
    else if (a == "-o") output = value();
    else if (a == "--help" || a == "-h") {
      std::printf("usage: ffdbench [--suite NAME|all] [--quick] [--meshes DIR] [--test-data DIR]\n"
                  "                [--ffdtool PATH] [--blender PATH] [-o FILE]\n"
                  "  --ffdtool PATH  ffdtool for the io suite (default: ../ffdtool/ffdtool beside ffdbench)\n"
                  "  --blender PATH  Blender for the io suite's side-by-side rows (default: blender on PATH)\n"
                  "suites:\n");
      for (const auto& s : ffd::bench::suites()) std::printf("  %-8s %s\n", s.name, s.what);
      return 0;
    } else {
      std::fprintf(stderr, "ffdbench: error: unknown argument '%s'\n", a.c_str());
      return 2;
    }
  }
  if (ctx.quick) ctx.repeats = 1;
  ctx.out["build"] = FFD_BUILD_FLAGS;
  ctx.out["cores"] = omp_get_num_procs();
  bool ran = false;
  try {
    for (const auto& s : ffd::bench::suites()) {
      if (suite != "all" && suite != s.name) continue;
      ran = true;
      std::fprintf(stderr, "ffdbench: suite %s\n", s.name);
      s.run(ctx);
    }
  } catch (const ffd::InputError& e) {
    std::fprintf(stderr, "ffdbench: error: %s\n", e.what());
    return 2;
  } catch (const ffd::Error& e) {  // IoError and the like: a failure while running
    std::fprintf(stderr, "ffdbench: error: %s\n", e.what());
    return 3;
  }
  if (!ran) {
    std::fprintf(stderr, "ffdbench: error: no suite named '%s'\n", suite.c_str());
    return 2;
  }
  ctx.out["peak_memory_bytes"] = ffd::peak_memory_bytes();
  const std::string text = ctx.out.dump(2) + "\n";
  if (output.empty()) {
    std::cout << text;
  } else {
    try {  // whole or not at all, like ffdtool's outputs; a failed write is exit 3
      ffd::write_file_atomically(output, [&](std::ostream& os) { os << text; });
    } catch (const ffd::Error& e) {
      std::fprintf(stderr, "ffdbench: error: %s\n", e.what());
      return 3;
    }
  }
  return 0;
}
