// The python suite: what the Python module costs over the library, and what it gains a
// Python user over PyGeM and over files.
// - The C++ kernel, warp_points (lib/warp/warp_points.h: what the module's d(points)
//   calls), on 100k and 1M points uniform in [0,1]^3 for a cubic B-spline lattice of 4^3
//   cells and a degree-3 Bernstein lattice (4^3 points) on that box, one point of each
//   moved by (0.1, 0.1, 0.1), 1 and 2 threads; then scripts/bench_python.py, as a child
//   process of Debian's python3 with the build's module, times d(points) on the same
//   points (a raw float64 file), PyGeM's FFD on them (when PYGEM_SOURCE names PyGeM's
//   source tree: github mathLab/PyGeM), and ffdtool.run on a 1M-vertex UV sphere in
//   memory against `ffdtool run` from and to OBJ files. The kernel runs before and after
//   the Python side; the faster median of the two is the one compared.
// - Reported: the module's overhead over the kernel (module / kernel - 1, both writing into
//   one array; d(points) into a new array each call beside it), the cost of one call on
//   one point (the binding's own work), PyGeM / module for the Bernstein lattice, and the
//   file round trip (process - in memory).
// --quick: 10x fewer points and a 100k-vertex sphere.
#include <omp.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>

#include "bench.h"
#include "child_run.h"
#include "common/errors.h"
#include "mesh/build_mesh.h"
#include "mesh/mesh_io.h"
#include "warp/lattice_spec.h"
#include "warp/warp_points.h"

namespace ffd::bench {
namespace {

using json = nlohmann::ordered_json;

Eigen::Matrix3Xd uniform_points(Eigen::Index n) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Eigen::Matrix3Xd out(3, n);
  for (Eigen::Index i = 0; i < n; ++i) out.col(i) = Eigen::Vector3d(u(rng), u(rng), u(rng));
  return out;
}

/// The suite's lattice of `basis`, one point moved (as bench_python.py makes it).
std::unique_ptr<Lattice> moved_lattice(Lattice::Basis basis) {
  const bool bspline = basis == Lattice::Basis::BSpline;
  const LatticeSpec spec{basis, 3, bspline ? Index3{4, 4, 4} : Index3{3, 3, 3}};
  std::unique_ptr<Lattice> lattice = make_lattice(spec, Parallelepiped::from_min_max(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()));
  const Index3 ijk = bspline ? Index3{2, 2, 2} : Index3{1, 1, 1};
  const std::size_t id = *lattice->find_point(0, PointIndex{true, ijk, 0});
  lattice->move_points(0, {id}, {lattice->points(0, {id}).col(0) + Eigen::Vector3d::Constant(0.1)});
  lattice->prepare();
  return lattice;
}

json kernel_rows(const Context& ctx, const Eigen::Matrix3Xd& points) {
  json rows = json::array();
  for (const auto& [kind, basis] : {std::pair{"bspline", Lattice::Basis::BSpline}, {"bernstein", Lattice::Basis::Bernstein}}) {
    const std::unique_ptr<Lattice> lattice = moved_lattice(basis);
    for (const Eigen::Index n : {points.cols() / 10, points.cols()}) {
      Eigen::Matrix3Xd out(3, n);
      for (int threads : {1, 2}) {
        omp_set_num_threads(threads);
        const double ms = median_ms(ctx.repeats, [&] { warp_points(*lattice, points.leftCols(n), out); });
        rows.push_back({{"kind", kind}, {"points", n}, {"threads", threads}, {"ms", ms}});
      }
    }
  }
  omp_set_num_threads(omp_get_num_procs());
  return rows;
}

/// Runs bench_python.py on the suite's files; its JSON.
json python_side(const Context& ctx, const TempFolder& dir, const std::string& ffdtool) {
  const std::string module_dir = FFD_PYTHON_MODULE_DIR;
  if (!std::filesystem::exists(module_dir + "/ffdtool/__init__.py"))
    throw InputError("the Python module is not built (" + module_dir + "): build with FFD_BUILD_PYTHON");
  setenv("PYTHONPATH", module_dir.c_str(), 1);
  const char* pygem = std::getenv("PYGEM_SOURCE");
  std::vector<std::string> argv = {"/usr/bin/python3", std::string(FFD_SOURCE_ROOT) + "/scripts/bench_python.py",
                                   "--points", dir.file("points.f64"), "--mesh", dir.file("sphere.obj"),
                                   "--script", dir.file("script.json"), "--ffdtool", ffdtool,
                                   "--repeats", std::to_string(ctx.repeats)};
  if (pygem && *pygem) argv.insert(argv.end(), {"--pygem", pygem});
  const ChildRun run = run_measured(argv, dir.path.string());
  if (!run.ok) throw InputError("bench_python.py failed: " + last_line(run.err));
  return json::parse(run.out);
}

void write_inputs(const Context& ctx, const TempFolder& dir, const Eigen::Matrix3Xd& points) {
  std::ofstream(dir.file("points.f64"), std::ios::binary)
      .write(reinterpret_cast<const char*>(points.data()), static_cast<std::streamsize>(points.size() * sizeof(double)));
  const int slices = ctx.quick ? 400 : 1265, stacks = ctx.quick ? 250 : 791;
  write_mesh(dir.file("sphere.obj"), build_mesh(uv_sphere(slices, stacks, Eigen::Vector3d::Constant(0.5), 0.4), "sphere"));
  std::ofstream(dir.file("script.json")) << R"({"version": 1, "steps": [
    {"op": "lattice", "name": "L", "cells": [4, 4, 4], "box": {"min": [0, 0, 0], "max": [1, 1, 1]}},
    {"op": "move", "lattice": "L", "points": [{"index": [2, 2, 2], "by": [0.1, 0.1, 0.1]}]}]})";
}

/// The ratios the suite is for, from the kernel's rows and the Python side's.
json ratios(const json& kernel, const json& py) {
  json out = json::array();
  for (std::size_t i = 0; i < kernel.size(); ++i) {
    const double k = kernel[i]["ms"], m = py["module"][i]["ms"];
    json row = {{"kind", kernel[i]["kind"]}, {"points", kernel[i]["points"]}, {"threads", kernel[i]["threads"]},
                {"kernel_ms", k}, {"module_ms", m}, {"module_overhead", m / k - 1},
                {"module_new_array_ms", py["module"][i]["new_array_ms"]},
                {"kernel_before_ms", kernel[i]["before_ms"]}, {"kernel_after_ms", kernel[i]["after_ms"]}};
    if (py.contains("pygem") && kernel[i]["kind"] == "bernstein")
      for (const auto& p : py["pygem"])
        if (p["points"] == kernel[i]["points"]) row["pygem_over_module"] = p["ms"].get<double>() / m;
    out.push_back(row);
  }
  return out;
}

}  // namespace

void bench_python(Context& ctx) {
  const TempFolder dir("python");
  const Eigen::Matrix3Xd points = uniform_points(ctx.quick ? 100'000 : 1'000'000);
  write_inputs(ctx, dir, points);
  // The kernel before and after the Python side, the faster of the two kept: a shared
  // machine's speed drifts over the minutes between them.
  json kernel = kernel_rows(ctx, points);
  const json py = python_side(ctx, dir, ffdtool_path(ctx.ffdtool));
  const json after = kernel_rows(ctx, points);
  for (std::size_t i = 0; i < kernel.size(); ++i) {
    kernel[i]["before_ms"] = kernel[i]["ms"];
    kernel[i]["after_ms"] = after[i]["ms"];
    kernel[i]["ms"] = std::min(kernel[i]["ms"].get<double>(), after[i]["ms"].get<double>());
  }
  const json table = ratios(kernel, py);
  for (const auto& r : table)
    std::fprintf(stderr, "ffdbench: python: %-9s %7lld points, %d thread(s): kernel %.2f ms, module %.2f ms (%+.1f%%)\n",
                 r["kind"].get<std::string>().c_str(), r["points"].get<long long>(), r["threads"].get<int>(),
                 r["kernel_ms"].get<double>(), r["module_ms"].get<double>(), 100 * r["module_overhead"].get<double>());
  std::fprintf(stderr, "ffdbench: python: one call on one point: %.1f us\n", py["call_overhead_us"].get<double>());
  ctx.out["python"] = {{"kernel_vs_module", table}, {"call_overhead_us", py["call_overhead_us"]},
                       {"pygem", py.value("pygem", json::array())}, {"run", py["run"]}};
}

}  // namespace ffd::bench
