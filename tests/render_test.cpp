// The renderer (lib/render): what a picture of a real mesh must show, that it is the
// same on every thread count, and the heat map's colours.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <sstream>

#include "common/errors.h"
#include "mesh/mesh_compare.h"
#include "mesh/mesh_io.h"
#include "render/control_net.h"
#include "render/heatmap.h"
#include "render/png_io.h"
#include "render/render.h"
#include "test_meshes.h"
#include "warp/bspline_lattice.h"

namespace ffd {
namespace {

bool is_background(const Image& im, int x, int y) { return im.at(x, y) == Rgb{255, 255, 255}; }

double covered_fraction(const Image& im) {
  std::size_t n = 0;
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x) n += !is_background(im, x, y);
  return double(n) / (double(im.width) * im.height);
}

std::string encoded_png(const Image& im) {
  std::ostringstream os;
  write_png(os, im);
  return os.str();
}

Image render_on(int threads, const Mesh& mesh, const RenderOptions& o) {
  const int before = omp_get_max_threads();
  omp_set_num_threads(threads);
  Image im = render_mesh(mesh, o);
  omp_set_num_threads(before);
  return im;
}

// The bunny moved up by a lattice-free shear, so it renders differently.
Mesh sheared_bunny() {
  Mesh m = test::bunny();
  for (Eigen::Index v = 0; v < m.positions().cols(); ++v) m.positions()(0, v) += 0.4 * m.positions()(1, v);
  return m;
}

TEST(Render, TheBunnyFillsAFairShareOfTheAskedSizeWithManyGreys) {
  RenderOptions o;
  set_size(o, "640x480");
  const Image im = render_mesh(test::bunny(), o);
  ASSERT_EQ(im.width, 640);
  ASSERT_EQ(im.height, 480);
  ASSERT_EQ(im.rgb.size(), 3u * 640 * 480);
  const double covered = covered_fraction(im);
  EXPECT_GT(covered, 0.2);
  EXPECT_LT(covered, 0.8);
  std::set<int> greys;
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x) {
      const Rgb c = im.at(x, y);
      EXPECT_TRUE(c.r == c.g && c.g == c.b) << x << "," << y;  // shade mode is grey
      greys.insert(c.r);
    }
  EXPECT_GT(greys.size(), 100u);
  // The fit leaves a margin: no covered pixel on the image's border.
  for (int x = 0; x < im.width; ++x) EXPECT_TRUE(is_background(im, x, 0) && is_background(im, x, im.height - 1));
}

TEST(Render, OneAndTwoThreadsGiveTheSameBytes) {
  for (const bool perspective : {false, true}) {
    RenderOptions o;
    o.perspective = perspective;
    o.flat = perspective;
    set_size(o, "333x217");  // bands that do not divide the height
    const Mesh mesh = test::bunny();
    EXPECT_EQ(encoded_png(render_on(1, mesh, o)), encoded_png(render_on(2, mesh, o))) << perspective;
    EXPECT_EQ(encoded_png(render_on(2, mesh, o)), encoded_png(render_on(7, mesh, o))) << perspective;
  }
}

TEST(Render, ADeformedMeshAndOtherViewsRenderDifferently) {
  RenderOptions o;
  set_size(o, "320x240");
  const std::string base = encoded_png(render_mesh(test::bunny(), o));
  EXPECT_NE(base, encoded_png(render_mesh(sheared_bunny(), o)));
  for (const char* view : {"front", "side", "top", "10,-20"}) {
    RenderOptions v = o;
    set_view(v, view);
    EXPECT_NE(base, encoded_png(render_mesh(test::bunny(), v))) << view;
  }
  RenderOptions p = o;
  p.perspective = true;
  EXPECT_NE(base, encoded_png(render_mesh(test::bunny(), p)));
  RenderOptions n = o;
  n.color = ColorMode::Normals;
  const Image normals = render_mesh(test::bunny(), n);
  std::size_t coloured = 0;
  for (int y = 0; y < normals.height; ++y)
    for (int x = 0; x < normals.width; ++x) coloured += normals.at(x, y).r != normals.at(x, y).b;
  EXPECT_GT(coloured, 1000u);
}

// The checked-in picture (ffdtool render test_data/bunny.obj --size 320x240), compared
// pixel by pixel with a tolerance, so a harmless change (a rounding) does not fail it.
TEST(Render, MatchesTheCheckedInBunnyWithinAFewLevels) {
  const Image golden = read_png(test::data("expected/bunny_iso_320x240.png"));
  RenderOptions o;
  set_size(o, "320x240");
  const Image im = render_mesh(test::bunny(), o);
  ASSERT_EQ(im.width, golden.width);
  ASSERT_EQ(im.height, golden.height);
  std::size_t off = 0;
  double sum = 0;
  for (std::size_t i = 0; i < im.rgb.size(); ++i) {
    const int d = std::abs(int(im.rgb[i]) - int(golden.rgb[i]));
    sum += d;
    off += d > 24;
  }
  EXPECT_LT(double(off) / im.rgb.size(), 0.005);
  EXPECT_LT(sum / im.rgb.size(), 1.5);
}

TEST(Render, CgalMeshesRenderAndSurviveAGlbRoundTrip) {
  if (test::cgal_meshes().empty()) GTEST_SKIP() << "libcgal-demo is not installed";
  const std::string out = test::temp_folder("render_cgal");
  for (const char* name : {"elephant.off", "pig.stl", "cube.off"}) {
    RenderOptions o;
    set_size(o, "200x150");
    const Mesh mesh = read_mesh(test::cgal_mesh(name));
    const Image im = render_mesh(mesh, o);
    EXPECT_GT(covered_fraction(im), 0.1) << name;
    // The same mesh through a GLB: float32 positions, the same triangles, the same picture
    // but for a few pixels on silhouettes.
    const std::string glb = out + "/" + name + ".glb";
    write_mesh(glb, mesh);
    const Mesh back = read_mesh(glb);
    ASSERT_EQ(back.num_vertices(), mesh.num_vertices()) << name;
    EXPECT_EQ(back.faces(), mesh.faces()) << name;
    const double scale = mesh.positions().cwiseAbs().maxCoeff();
    EXPECT_LE((back.positions() - mesh.positions()).cwiseAbs().maxCoeff(), 1e-7 * scale) << name;
    const Image again = render_mesh(back, o);
    std::size_t off = 0;
    for (std::size_t i = 0; i < im.rgb.size(); ++i) off += std::abs(int(im.rgb[i]) - int(again.rgb[i])) > 24;
    EXPECT_LT(double(off) / im.rgb.size(), 0.01) << name;
  }
}

// --color level: a mesh read from a file keeps no levels, but a save with "colors":
// "level" wrote them as vertex colours, which are drawn; a mesh with neither is grey.
TEST(Render, LevelColoursComeFromTheFilesColoursWhenTheMeshHasNoLevels) {
  Mesh mesh = test::bunny();
  RenderOptions o;
  set_size(o, "160x120");
  o.color = ColorMode::Level;
  auto coloured = [](const Image& im) {
    std::size_t n = 0;
    for (int y = 0; y < im.height; ++y)
      for (int x = 0; x < im.width; ++x) n += im.at(x, y).r != im.at(x, y).b;
    return n;
  };
  EXPECT_EQ(coloured(render_mesh(mesh, o)), 0u);
  mesh.colors().assign(mesh.num_vertices(), Eigen::Vector3f(0.9f, 0.2f, 0.1f));
  EXPECT_GT(coloured(render_mesh(mesh, o)), 1000u);
}

TEST(Render, ControlNetIsDrawnOverTheMesh) {
  const Mesh mesh = test::bunny();
  std::vector<std::uint32_t> all(mesh.num_vertices());
  for (std::uint32_t v = 0; v < all.size(); ++v) all[v] = v;
  BSplineLattice lattice(fit_aabb(mesh.positions(), all, 0.05), {4, 4, 4}, 3);
  const Overlay net = control_net(lattice);
  EXPECT_EQ(net.points.size(), lattice.num_points());
  EXPECT_EQ(net.edges.size(), 3u * 6 * 7 * 7);  // 7 points a side: 6 edges along each axis per line
  RenderOptions o;
  set_size(o, "320x240");
  const Image im = render_mesh(mesh, o, nullptr, {net});
  std::size_t blue = 0;
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x) blue += im.at(x, y) == net.edge_color;
  EXPECT_GT(blue, 500u);
}

TEST(Render, BadViewsAndSizesAreInputErrors) {
  RenderOptions o;
  for (const char* v : {"", "north", "10", "10,95", "a,b", "1,2,3"}) EXPECT_THROW(set_view(o, v), InputError) << v;
  for (const char* s : {"", "640", "0x480", "640x8", "20000x20", "640x480x3", "axb"})
    EXPECT_THROW(set_size(o, s), InputError) << s;
}

TEST(Heatmap, NoColourForEqualMeshesAndColourOnlyBeyondTolerance) {
  const Mesh a = test::bunny();
  RenderOptions o;
  set_size(o, "320x240");
  const std::vector<double> same = vertex_distances(a, a, false);
  const Image equal = render_heatmap(a, same, 1e-9, 0.0, 0.0, o);
  for (int y = 0; y < equal.height; ++y)
    for (int x = 0; x < equal.width; ++x) {
      const Rgb c = equal.at(x, y);
      ASSERT_TRUE(c.r == c.g && c.g == c.b) << x << "," << y;
    }
  // Move the upper half: vertices beyond the tolerance are coloured, the rest stay grey.
  Mesh b = a.clone();
  const double mid = 0.5 * (a.positions().row(1).minCoeff() + a.positions().row(1).maxCoeff());
  for (Eigen::Index v = 0; v < b.positions().cols(); ++v)
    if (b.positions()(1, v) > mid) b.positions()(0, v) += 0.01 * (b.positions()(1, v) - mid);
  const std::vector<double> d = vertex_distances(a, b, false);
  double max = 0;
  for (double x : d) max = std::max(max, x);
  const std::vector<Eigen::Vector3f> colors = distance_colors(d, 1e-6, max);
  for (std::size_t v = 0; v < d.size(); ++v) {
    const bool grey = colors[v].x() == colors[v].y() && colors[v].y() == colors[v].z();
    EXPECT_EQ(grey, d[v] <= 1e-6) << v;
  }
  const Image differs = render_heatmap(b, d, 1e-6, max, max / 2, o);
  std::size_t coloured = 0;
  for (int y = 0; y < differs.height; ++y)
    for (int x = 0; x < differs.width; ++x) coloured += differs.at(x, y).r != differs.at(x, y).b;
  EXPECT_GT(coloured, 1000u);
}

TEST(Heatmap, ViridisRunsFromVioletToYellow) {
  EXPECT_LT(viridis(0).y(), 0.05f);
  EXPECT_GT(viridis(1).x(), 0.95f);
  EXPECT_GT(viridis(1).y(), 0.85f);
  for (double t = 0; t < 1; t += 0.05) EXPECT_LT(viridis(t).y(), viridis(t + 0.05).y() + 1e-6);  // green rises
}

TEST(RenderCli, WritesPngsAndRefusesBadArguments) {
  const std::string dir = test::temp_folder("render_cli");
  const std::string png = dir + "/b.png";
  ASSERT_EQ(test::run_tool("render " + test::quoted(test::data("bunny.obj")) + " -o " + png + " --size 200x100"), 0);
  const Image im = read_png(png);
  EXPECT_EQ(im.width, 200);
  EXPECT_EQ(im.height, 100);
  std::string err;
  EXPECT_EQ(test::run_tool("render " + test::quoted(test::data("bunny.obj")) + " -o " + dir + "/b.jpg", nullptr, &err), 2);
  EXPECT_NE(err.find("b.jpg"), std::string::npos);
  EXPECT_EQ(test::run_tool("render " + test::quoted(test::data("bunny.obj")) + " -o " + dir + "/c.png --view up", nullptr, &err), 2);
  EXPECT_FALSE(std::filesystem::exists(dir + "/c.png"));
  // compare --heatmap: written for a difference (exit 1) and for equal meshes (exit 0).
  EXPECT_EQ(test::run_tool("compare " + test::quoted(test::data("bunny.obj")) + " " + test::quoted(test::data("bunny.obj")) +
                           " --heatmap " + dir + "/same.png --size 160x120"), 0);
  EXPECT_EQ(read_png(dir + "/same.png").width, 160);
}

TEST(RenderCli, RunPreviewAndSavePreviewDrawTheLattice) {
  const std::string dir = test::temp_folder("render_preview");
  test::write_file(dir + "/s.json", R"({"version": 1, "steps": [
    {"op": "lattice", "name": "L", "basis": "bspline", "degree": 3, "box": {"fit": "aabb", "padding": 0.05}, "cells": [4, 4, 4]},
    {"op": "save", "path": "mid.obj", "preview": "mid.png"}]})");
  ASSERT_EQ(test::run_tool("run " + test::quoted(test::data("bunny.obj")) + " " + dir + "/s.json -o " + dir +
                           "/out.obj --quiet --preview " + dir + "/final.png"), 0);
  for (const char* name : {"mid.png", "final.png"}) {
    const Image im = read_png(dir + "/" + name);
    std::size_t blue = 0;
    for (int y = 0; y < im.height; ++y)
      for (int x = 0; x < im.width; ++x) blue += im.at(x, y) == Overlay{}.edge_color;
    EXPECT_GT(blue, 1000u) << name;
  }
}

}  // namespace
}  // namespace ffd
