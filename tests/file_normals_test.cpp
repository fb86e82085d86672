// File normals carried into deformed space (lib/mesh/file_normals.cpp).
// - transformed_file_normals against one plain pass over the corners, written out here (a
//   map of (entry, vertex) pairs and a linear search of each entry's results): the same
//   table, bit for bit, and the same entry at every corner, on a grid whose corners mix
//   smooth, flat-shaded, shared and missing normals, for transforms that give every vertex
//   its own normal, merge some, return -0 and 0, or NaN; on one thread and two.
// - Runs (lib/script/runner.cpp): file normals at every vertex are written the same when
//   the run computes no vertex normals as when a step makes it compute them; where they
//   miss vertices, a PLY still gets the computed normals there.
#include <gtest/gtest.h>

#include <omp.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>

#include "common/numbers.h"
#include "mesh/build_mesh.h"
#include "mesh/file_normals.h"
#include "mesh/mesh_io.h"
#include "script/runner.h"
#include "test_meshes.h"

namespace ffd {
namespace {

// The grid's triangles in four kinds: past x = 0.7 no normals (so some vertices have none),
// else by face number 0 smooth (entry = the vertex's own), 1 flat-shaded (an entry per
// face), 2 one entry shared by every such face. The table ends with an entry no corner uses.
PolygonSoup mixed_normals_grid(int n) {
  PolygonSoup grid = test::grid_soup(n, [](double x, double y) { return 0.2 * std::sin(3 * x) * std::cos(2 * y); });
  const std::vector<test::SoupFace> faces = test::soup_faces(grid);
  PolygonSoup soup;
  soup.positions = grid.positions;
  for (const Eigen::Vector3d& p : grid.positions) soup.normals.push_back(Eigen::Vector3d(p.y() - 0.5, 0.3, 1).normalized());
  const auto shared = static_cast<std::int32_t>(soup.normals.size());
  soup.normals.push_back(Eigen::Vector3d(0, 0, 1));
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const std::vector<std::uint32_t>& v = faces[f].vertices;
    std::vector<std::int32_t> normals;
    const double x = (grid.positions[v[0]].x() + grid.positions[v[1]].x() + grid.positions[v[2]].x()) / 3;
    const std::size_t kind = x > 0.7 ? 3 : f % 3;
    if (kind == 0) normals = {static_cast<std::int32_t>(v[0]), static_cast<std::int32_t>(v[1]), static_cast<std::int32_t>(v[2])};
    if (kind == 1) {
      const auto own = static_cast<std::int32_t>(soup.normals.size());
      soup.normals.push_back(Eigen::Vector3d(0.1 * static_cast<double>(f % 5), -0.2, 1).normalized());
      normals = {own, own, own};
    }
    if (kind == 2) normals = {shared, shared, shared};
    test::add_face(soup, v, {}, normals);
  }
  soup.normals.push_back(Eigen::Vector3d(1, 0, 0));  // unreferenced
  return soup;
}

// What the writer did in one pass before: each (entry, vertex) pair transformed when a
// corner first meets it, and its result looked up among its entry's by a linear search.
CornerNormals one_pass_file_normals(const Mesh& mesh, const NormalTransform& transform) {
  const MeshElements& el = mesh.elements();
  const std::vector<Eigen::Vector3d>& table = mesh.file_normals();
  std::vector<std::vector<Eigen::Vector3d>> values(table.size());
  std::map<std::pair<std::int32_t, std::uint32_t>, std::size_t> memo;
  std::vector<std::pair<std::int64_t, std::size_t>> slot_of(el.corners.size(), {-1, 0});
  for (std::size_t c = 0; c < el.corners.size(); ++c) {
    const std::int32_t k = el.corner_normals[c];
    if (k < 0) continue;
    auto [it, inserted] = memo.try_emplace({k, el.corners[c]}, 0);
    if (inserted) {
      const Eigen::Vector3d n = transform ? transform(el.corners[c], table[k]) : table[k];
      std::vector<Eigen::Vector3d>& list = values[k];
      std::size_t slot = 0;
      while (slot < list.size() && list[slot] != n) ++slot;
      if (slot == list.size()) list.push_back(n);
      it->second = slot;
    }
    slot_of[c] = {k, it->second};
  }
  CornerNormals result;
  std::vector<std::size_t> first(values.size());
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (values[k].empty()) values[k].push_back(table[k]);
    first[k] = result.table.size();
    result.table.insert(result.table.end(), values[k].begin(), values[k].end());
  }
  result.corner.assign(el.corners.size(), -1);
  for (std::size_t c = 0; c < el.corners.size(); ++c)
    if (slot_of[c].first >= 0) result.corner[c] = static_cast<std::int64_t>(first[slot_of[c].first] + slot_of[c].second);
  return result;
}

void expect_same_bits(const CornerNormals& a, const CornerNormals& b, const char* what) {
  ASSERT_EQ(a.table.size(), b.table.size()) << what;
  for (std::size_t k = 0; k < a.table.size(); ++k)
    ASSERT_EQ(std::memcmp(a.table[k].data(), b.table[k].data(), 3 * sizeof(double)), 0) << what << ", entry " << k;
  EXPECT_EQ(a.corner, b.corner) << what;
}

TEST(TransformedFileNormals, AreWhatOnePassOverTheCornersGives) {
  const Mesh mesh = build_mesh(mixed_normals_grid(24), "grid.obj");
  const ConstVec3Array p = mesh.positions();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<std::pair<const char*, NormalTransform>> transforms = {
      {"none", nullptr},
      {"identity", [](std::uint32_t, const Eigen::Vector3d& n) { return n; }},
      {"every vertex its own", [&](std::uint32_t v, const Eigen::Vector3d& n) {
         return Eigen::Vector3d((n + 0.01 * Eigen::Vector3d(p.col(v))).normalized());
       }},
      {"some merged", [](std::uint32_t v, const Eigen::Vector3d& n) {
         return v % 3 == 0 ? n : Eigen::Vector3d(0, static_cast<double>(v % 2), 1);
       }},
      {"-0 and 0", [](std::uint32_t v, const Eigen::Vector3d& n) { return Eigen::Vector3d(v % 2 ? -0.0 : 0.0, n.y(), n.z()); }},
      {"NaN at some", [&](std::uint32_t v, const Eigen::Vector3d& n) { return v % 5 == 0 ? Eigen::Vector3d(nan, 0, 1) : n; }},
  };
  const int threads = omp_get_max_threads();
  for (const auto& [what, transform] : transforms) {
    const CornerNormals expected = one_pass_file_normals(mesh, transform);
    for (const int t : {1, 2}) {
      omp_set_num_threads(t);
      std::atomic<std::size_t> calls{0};
      const NormalTransform counted =
          transform ? NormalTransform([&, f = transform](std::uint32_t v, const Eigen::Vector3d& n) {
            ++calls;
            return f(v, n);
          })
                    : nullptr;
      expect_same_bits(transformed_file_normals(mesh, counted), expected, what);
      // One call per distinct (entry, vertex) pair: the shared entry's, one per vertex.
      if (transform) EXPECT_LT(calls.load(), mesh.elements().corners.size()) << what;
    }
  }
  omp_set_num_threads(threads);
  // The table grew past the shared entry's hash threshold and the identity kept it as read.
  EXPECT_GT(transformed_file_normals(mesh, transforms[2].second).table.size(), mesh.file_normals().size() + 100);
  EXPECT_EQ(transformed_file_normals(mesh, transforms[1].second).table, mesh.file_normals());
}

TEST(TransformedFileNormals, EveryVertexHasOneOnlyWhenNoVertexIsMissed) {
  PolygonSoup soup = mixed_normals_grid(6);
  EXPECT_FALSE(every_vertex_has_file_normal(build_mesh(soup, "grid.obj")));  // the fourth kind has none
  for (std::size_t c = 0; c < soup.elements.corner_normals.size(); ++c)
    if (soup.elements.corner_normals[c] < 0) soup.elements.corner_normals[c] = static_cast<std::int32_t>(soup.elements.corners[c]);
  EXPECT_TRUE(every_vertex_has_file_normal(build_mesh(soup, "grid.obj")));
  EXPECT_FALSE(every_vertex_has_file_normal(test::grid_mesh(4)));
}

std::string mixed_grid_obj(const PolygonSoup& soup) {
  std::string text;
  for (const Eigen::Vector3d& p : soup.positions) {
    text += "v";
    for (int a = 0; a < 3; ++a) text += " ", append_number(text, p[a]);
    text += "\n";
  }
  for (const Eigen::Vector3d& n : soup.normals) {
    text += "vn";
    for (int a = 0; a < 3; ++a) text += " ", append_number(text, n[a]);
    text += "\n";
  }
  for (const test::SoupFace& f : test::soup_faces(soup)) {
    text += "f";
    for (std::size_t c = 0; c < f.vertices.size(); ++c)
      text += " " + std::to_string(f.vertices[c] + 1) + (f.normals.empty() ? "" : "//" + std::to_string(f.normals[c] + 1));
    text += "\n";
  }
  return text;
}

// Runs `steps` on DIR/in.obj into DIR/NAME.EXT; returns the file's bytes.
std::string run_file_normals(const std::string& dir, const std::string& name, const std::string& ext, const std::string& steps) {
  test::write_file(dir + "/" + name + ".json", test::script_with(steps));
  RunOptions options;
  options.mesh = dir + "/in.obj";
  options.script = dir + "/" + name + ".json";
  options.output = dir + "/" + name + "." + ext;
  options.quiet = true;
  run_script(options);
  return test::read_file(options.output);
}

constexpr const char* kFileNormalMove = R"({"op": "lattice", "name": "l", "cells": [4, 4, 4]},
  {"op": "move", "lattice": "l", "points": [{"index": [2, 2, 2], "by": [0.05, -0.03, 0.1]}]})";
// The same, and a glTF saved on the way: glTF holds vertex normals, so this run computes them.
constexpr const char* kFileNormalMoveWithNormals = R"({"op": "lattice", "name": "l", "cells": [4, 4, 4]},
  {"op": "move", "lattice": "l", "points": [{"index": [2, 2, 2], "by": [0.05, -0.03, 0.1]}]},
  {"op": "save", "path": "normals.glb"})";

TEST(FileNormalRuns, AtEveryVertexTheyAreWrittenAsWhenTheRunComputesVertexNormals) {
  PolygonSoup soup = mixed_normals_grid(16);
  for (std::size_t c = 0; c < soup.elements.corner_normals.size(); ++c)
    if (soup.elements.corner_normals[c] < 0) soup.elements.corner_normals[c] = static_cast<std::int32_t>(soup.elements.corners[c]);
  const std::string dir = test::temp_folder("file_normal_runs_all");
  test::write_file(dir + "/in.obj", mixed_grid_obj(soup));
  for (const char* ext : {"obj", "off", "ply"}) {
    const std::string deferred = run_file_normals(dir, "deferred", ext, kFileNormalMove);
    EXPECT_EQ(deferred, run_file_normals(dir, "computed", ext, kFileNormalMoveWithNormals)) << ext;
    EXPECT_NE(deferred, run_file_normals(dir, "unmoved", ext, R"({"op": "lattice", "name": "l", "cells": [4, 4, 4]})")) << ext;
  }
}

TEST(FileNormalRuns, WhereTheyMissVerticesAPlyGetsTheComputedNormalsThere) {
  const PolygonSoup soup = mixed_normals_grid(16);
  const std::string dir = test::temp_folder("file_normal_runs_some");
  test::write_file(dir + "/in.obj", mixed_grid_obj(soup));
  const std::string plain = run_file_normals(dir, "plain", "ply", kFileNormalMove);
  EXPECT_EQ(plain, run_file_normals(dir, "computed", "ply", kFileNormalMoveWithNormals));
  const Mesh out = read_mesh(dir + "/plain.ply");
  std::vector<char> has(soup.positions.size(), 0);
  for (std::size_t c = 0; c < soup.elements.corners.size(); ++c)
    if (soup.elements.corner_normals[c] >= 0) has[soup.elements.corners[c]] = 1;
  std::size_t missed = 0;
  for (std::size_t v = 0; v < has.size(); ++v) {
    if (has[v]) continue;
    ++missed;
    EXPECT_NEAR(out.file_normals()[v].norm(), 1.0, 1e-6) << "vertex " << v;  // PLY stores floats
  }
  EXPECT_GT(missed, 0u);
}

}  // namespace
}  // namespace ffd
