// Benchmark helpers: timing, mesh loading, subdivision to a target size.
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Subdivision_method_3/subdivision_methods_3.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "bench.h"
#include "common/errors.h"
#include "common/timer.h"
#include "mesh/mesh_io.h"
#include "mesh/halfedge_view_cgal.h"

namespace ffd::bench {

double median_ms(int repeats, const std::function<void()>& fn) {
  fn();
  std::vector<double> times;
  for (int i = 0; i < std::max(1, repeats); ++i) {
    Stopwatch clock;
    fn();
    times.push_back(clock.ms());
  }
  std::sort(times.begin(), times.end());
  return times[times.size() / 2];
}

Mesh load(const Context& ctx, const std::string& name) {
  if (name == "bunny.obj") return read_mesh(ctx.test_data + "/bunny.obj");
  const std::string path = ctx.meshes + "/" + name;
  if (!std::filesystem::exists(path))
    throw InputError(path + ": benchmark mesh missing (scripts/bench.sh fetches the meshes)");
  return read_mesh(path);
}

Mesh subdivided(const Mesh& mesh, std::size_t min_vertices) {
  SurfaceMesh sm = surface_mesh(mesh);
  while (sm.number_of_vertices() < min_vertices)
    CGAL::Subdivision_method_3::Loop_subdivision(sm, CGAL::parameters::number_of_iterations(1));
  return mesh_from_surface(sm, mesh.source());
}

namespace {

/// x rounded to 6 decimals, as float exporters (Blender's) write coordinates.
double round6(double x) { return std::round(x * 1e6) / 1e6; }

}  // namespace

PolygonSoup height_field(int n) {
  PolygonSoup soup;
  soup.positions.reserve(static_cast<std::size_t>(n) * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = double(i) / (n - 1), y = double(j) / (n - 1);
      const double z = 0.08 * std::sin(2 * M_PI * x) * std::cos(2 * M_PI * y) +
                       0.03 * std::sin(7 * x + 1) * std::cos(5 * y + 0.5);
      soup.positions.emplace_back(round6(x), round6(y), round6(z));
    }
  soup.elements.reserve(2 * static_cast<std::size_t>(n - 1) * (n - 1), 3);
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const std::uint32_t a = j * n + i, b = a + 1, c = a + n, d = c + 1;
      soup.elements.add_polygon({a, b, d});
      soup.elements.add_polygon({a, d, c});
    }
  return soup;
}

double mb_per_s(double bytes, double ms) { return bytes / 1e3 / ms; }

std::string last_line(const std::string& text) {
  std::istringstream is(text);
  std::string line, last;
  while (std::getline(is, line))
    if (!line.empty()) last = line;
  return last;
}

std::string ffdtool_path(const std::string& configured) {
  std::string path = configured;
  if (path.empty()) {
    std::error_code ec;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    path = (self.parent_path() / ".." / "ffdtool" / "ffdtool").lexically_normal().string();
  }
  if (::access(path.c_str(), X_OK) != 0)
    throw InputError(path + ": no ffdtool there (build it with scripts/build.sh, or pass --ffdtool PATH)");
  return path;
}

TempFolder::TempFolder(const std::string& suite)
    : path(std::filesystem::temp_directory_path() / ("ffdbench-" + suite + "-" + std::to_string(::getpid()))) {
  std::filesystem::create_directories(path);
}

TempFolder::~TempFolder() {
  std::error_code ec;
  std::filesystem::remove_all(path, ec);
}

// A UV sphere: `slices` around, `stacks` from pole to pole, outward triangles.
PolygonSoup uv_sphere(int slices, int stacks, const Eigen::Vector3d& centre, double radius) {
  PolygonSoup soup;
  soup.positions.push_back(centre + Eigen::Vector3d(0, 0, radius));
  for (int i = 1; i < stacks; ++i)
    for (int j = 0; j < slices; ++j) {
      const double t = M_PI * i / stacks, p = 2 * M_PI * j / slices;
      soup.positions.push_back(centre + radius * Eigen::Vector3d(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)));
    }
  soup.positions.push_back(centre - Eigen::Vector3d(0, 0, radius));
  const auto ring = [&](int i, int j) { return static_cast<std::uint32_t>(1 + (i - 1) * slices + (j % slices)); };
  const std::uint32_t south = static_cast<std::uint32_t>(soup.positions.size() - 1);
  for (int j = 0; j < slices; ++j) {
    soup.elements.add_polygon({0, ring(1, j), ring(1, j + 1)});
    soup.elements.add_polygon({south, ring(stacks - 1, j + 1), ring(stacks - 1, j)});
    for (int i = 1; i + 1 < stacks; ++i) {
      soup.elements.add_polygon({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
      soup.elements.add_polygon({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
    }
  }
  return soup;
}

}  // namespace ffd::bench
