// ffdbench --suite compare: what `ffdtool compare --metric hausdorff` costs a user, as
// whole processes (wall and peak resident set), against reading the same two meshes in
// this run and against CGAL's approximate_Hausdorff_distance with 1M samples a side.
//
// Pairs (binary PLY): UV spheres of 100k and 1M vertices against themselves after a
// B-spline FFD (ffdtool run), the 1M pair again as OBJ, the 100k sphere against the 1M
// one, and the armadillo refined by Loop subdivision past 1M vertices against its FFD. Target: 1M vs 1M in at most 3x the time
// to read both meshes, at most 400 bytes of peak memory per vertex of both.
// With FFD_COMPARE_BEFORE=PATH (an older ffdtool), its compare runs the same pairs.
//
// Then a folder: CGAL's sample meshes (Debian's libcgal-demo) against their FFD by
// `ffdtool batch`, compared with --jobs 1 and --jobs 2.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "bench.h"
#include "child_run.h"
#include "common/errors.h"
#include "common/timer.h"
#include "mesh/build_mesh.h"
#include "mesh/halfedge_view_cgal.h"
#include "mesh/mesh_io.h"

#include <CGAL/Polygon_mesh_processing/distance.h>

namespace ffd::bench {
namespace {

using json = nlohmann::ordered_json;
namespace fs = std::filesystem;

const char* kFfd = R"({"version": 1, "steps": [
  {"op": "lattice", "name": "b", "cells": [4, 4, 4]},
  {"op": "move", "lattice": "b", "points": [{"index": [2, 2, 2], "by": [0.004, 0.008, -0.004]}]}]})";

void write_binary_ply(const std::string& path, const Mesh& mesh) {
  WriteOptions binary;
  binary.encoding = WriteOptions::Encoding::Binary;
  write_mesh(path, mesh, binary);
}

// `mesh` written to NAME.ply and its FFD to NAME_ffd.ply; its vertex count.
std::size_t write_pair(const std::string& ffdtool, const TempFolder& dir, const std::string& name, const Mesh& mesh) {
  write_binary_ply(dir.file(name + ".ply"), mesh);
  const ChildRun run = run_measured({ffdtool, "run", dir.file(name + ".ply"), dir.file("ffd.json"), "-o",
                                     dir.file(name + "_ffd.ply"), "--quiet"},
                                    dir.path.string());
  if (!run.ok) throw InputError("ffdtool run failed on " + name + ": " + last_line(run.err));
  return mesh.num_vertices();
}

// CGAL's symmetric approximate distance with 1M random samples on each mesh's faces.
json cgal_peer(const std::string& a, const std::string& b) {
  const SurfaceMesh ma = surface_mesh(read_mesh(a)), mb = surface_mesh(read_mesh(b));
  Stopwatch clock;
  const auto samples = CGAL::parameters::number_of_points_on_faces(1000000).random_seed(1);
  const double h = CGAL::Polygon_mesh_processing::approximate_symmetric_Hausdorff_distance<CGAL::Sequential_tag>(
      ma, mb, samples, samples);
  return {{"what", "CGAL approximate_symmetric_Hausdorff_distance, 1M samples a side, sequential, in process"},
          {"ms", clock.ms()}, {"distance", h}};
}

// One pair: reading both meshes here, then `compare` as a process (and the older one's).
json pair_row(const std::string& ffdtool, const TempFolder& dir, const std::string& a, const std::string& b,
              std::size_t vertices, double tolerance, int repeats, const std::string& format = "ply") {
  std::fprintf(stderr, "ffdbench: compare: %s vs %s (%s)\n", a.c_str(), b.c_str(), format.c_str());
  const std::string pa = dir.file(a + "." + format), pb = dir.file(b + "." + format);
  const double read_ms = median_ms(repeats, [&] {
    read_mesh(pa);
    read_mesh(pb);
  });
  const auto compare = [&](const std::string& program) {
    const ChildRun run = run_measured({program, "compare", pa, pb, "--metric", "hausdorff", "--tolerance",
                                       std::to_string(tolerance), "--json"},
                                      dir.path.string());
    if (run.out.empty()) throw InputError(program + " compare failed: " + last_line(run.err));
    const json out = json::parse(run.out);
    return json{{"wall_ms", run.ms}, {"peak_bytes", run.peak_bytes},
                {"bytes_per_vertex", static_cast<double>(run.peak_bytes) / static_cast<double>(vertices)},
                {"times_reading", run.ms / read_ms}, {"max", out["max"]}, {"max_upper", out.value("max_upper", json())},
                {"within_tolerance", out["within_tolerance"]}};
  };
  json row = {{"a", a}, {"b", b}, {"format", format}, {"vertices_both", vertices}, {"tolerance", tolerance},
              {"read_both_ms", read_ms}, {"compare", compare(ffdtool)}};
  if (const char* before = std::getenv("FFD_COMPARE_BEFORE")) row["before"] = compare(before);
  row["cgal"] = cgal_peer(pa, pb);
  return row;
}

json pair_rows(const std::string& ffdtool, const TempFolder& dir, const Context& ctx) {
  std::ofstream(dir.file("ffd.json")) << kFfd;
  const bool quick = ctx.quick;
  const std::size_t small = write_pair(ffdtool, dir, "sphere_100k", build_mesh(uv_sphere(quick ? 126 : 400, quick ? 80 : 250, Eigen::Vector3d::Zero(), 1), "s"));
  const std::size_t large = write_pair(ffdtool, dir, "sphere_1m", build_mesh(uv_sphere(quick ? 400 : 1265, quick ? 250 : 791, Eigen::Vector3d::Zero(), 1), "s"));
  const Mesh armadillo = subdivided(load(ctx, "armadillo.off"), quick ? 100000 : 1000000);
  const std::size_t real = write_pair(ffdtool, dir, "armadillo_1m", armadillo);
  const double diagonal = 2 * std::sqrt(3.0);  // the spheres' box
  json rows = json::array();
  rows.push_back(pair_row(ffdtool, dir, "sphere_100k", "sphere_100k_ffd", 2 * small, 1e-3 * diagonal, ctx.repeats));
  rows.push_back(pair_row(ffdtool, dir, "sphere_1m", "sphere_1m_ffd", 2 * large, 1e-3 * diagonal, ctx.repeats));
  // The same pair as OBJ text, which takes longer to read than binary PLY.
  for (const char* name : {"sphere_1m", "sphere_1m_ffd"})
    write_mesh(dir.file(std::string(name) + ".obj"), read_mesh(dir.file(std::string(name) + ".ply")));
  rows.push_back(pair_row(ffdtool, dir, "sphere_1m", "sphere_1m_ffd", 2 * large, 1e-3 * diagonal, ctx.repeats, "obj"));
  rows.push_back(pair_row(ffdtool, dir, "sphere_100k", "sphere_1m", small + large, 1e-3 * diagonal, ctx.repeats));
  const ConstVec3Array p = armadillo.positions();
  const double armadillo_diagonal = (p.rowwise().maxCoeff() - p.rowwise().minCoeff()).norm();
  rows.push_back(pair_row(ffdtool, dir, "armadillo_1m", "armadillo_1m_ffd", 2 * real, 1e-3 * armadillo_diagonal, ctx.repeats));
  return rows;
}

// CGAL's sample meshes in IN/, their FFD by `batch` in OUT/, then `compare IN OUT`.
json folder_rows(const std::string& ffdtool, const TempFolder& dir) {
  const std::string tarball = "/usr/share/doc/libcgal-dev/data.tar.gz";
  if (!fs::exists(tarball)) return {{"skipped", tarball + " is missing (scripts/setup.sh installs libcgal-demo)"}};
  fs::create_directories(dir.file("cgal"));
  if (std::system(("tar -xzf " + tarball + " -C " + dir.file("cgal") + " data/meshes").c_str()) != 0)
    throw InputError("cannot extract " + tarball);
  const std::string in = dir.file("cgal/data/meshes"), out = dir.file("cgal_ffd");
  const ChildRun batch = run_measured({ffdtool, "batch", dir.file("ffd.json"), in, "-o", out, "--progress", "none"},
                                      dir.path.string());
  json rows = {{"batch_ms", batch.ms}, {"batch_exit", batch.exit}};
  for (const char* jobs : {"1", "2"}) {
    std::fprintf(stderr, "ffdbench: compare: CGAL's meshes, --jobs %s\n", jobs);
    const ChildRun run = run_measured({ffdtool, "compare", in, out, "--metric", "hausdorff", "--tolerance", "1e-3",
                                       "--jobs", jobs, "--json"},
                                      dir.path.string());
    if (run.out.empty()) throw InputError("compare of the folders failed: " + last_line(run.err));
    const json j = json::parse(run.out);
    rows[std::string("jobs_") + jobs] = {{"wall_ms", run.ms}, {"peak_bytes", run.peak_bytes}, {"pairs", j["pairs"]},
                                         {"same", j["same"]}, {"different", j["different"]},
                                         {"missing", j["missing"]}, {"errors", j["errors"]}};
  }
  return rows;
}

}  // namespace

void bench_compare(Context& ctx) {
  const std::string ffdtool = ffdtool_path(ctx.ffdtool);
  const TempFolder dir("compare");
  json pairs = pair_rows(ffdtool, dir, ctx);
  for (json& row : pairs)
    if (row["a"] == "sphere_1m" && row["b"] == "sphere_1m_ffd")  // both formats
      row["target"] = {{"times_reading", 3}, {"bytes_per_vertex", 400},
                       {"met", row["compare"]["times_reading"].get<double>() <= 3 &&
                                   row["compare"]["bytes_per_vertex"].get<double>() <= 400}};
  ctx.out["compare"] = {{"pairs", pairs}, {"folder", folder_rows(ffdtool, dir)}};
}

}  // namespace ffd::bench
