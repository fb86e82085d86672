// Benchmark helpers: timing, mesh loading, subdivision to a target size.
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Subdivision_method_3/subdivision_methods_3.h>

#include <algorithm>
#include <filesystem>

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

}  // namespace ffd::bench
