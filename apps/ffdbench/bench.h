// ffdbench: benchmark suites that print one JSON table. Every target is reported as a
// ratio against a baseline measured in the same run, on the same machine.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mesh/mesh.h"

namespace ffd::bench {

struct Context {
  std::string meshes;  // folder with armadillo.off, bunny00.off, refined_elephant.off
  std::string test_data;
  bool quick = false;  // smaller sizes and fewer repeats, for a smoke run
  int repeats = 5;
  nlohmann::ordered_json out = nlohmann::ordered_json::object();
};

struct Suite {
  const char* name;
  const char* what;
  void (*run)(Context&);
};

/// All suites, in the order `--suite all` runs them.
const std::vector<Suite>& suites();

/// Median wall time in ms of `repeats` runs of `fn` (after one warm-up run).
double median_ms(int repeats, const std::function<void()>& fn);

/// A mesh from the benchmark mesh folder (by file name), or the bundled bunny for
/// "bunny.obj". \throw InputError if missing.
Mesh load(const Context& ctx, const std::string& name);

/// `mesh` refined by Loop subdivision until it has at least `min_vertices` vertices
/// (CGAL's Subdivision_method_3), with rest = current positions and fresh normals.
Mesh subdivided(const Mesh& mesh, std::size_t min_vertices);

// Suites (one file each).
void bench_ffd(Context& ctx);
void bench_remesh(Context& ctx);
void bench_bcm(Context& ctx);

}  // namespace ffd::bench
