#include "mesh/mesh_compare.h"

#include <cmath>
#include <limits>
#include <memory>

namespace ffd {

namespace {

// True when both meshes have the same elements: kinds, sizes and vertex indices.
bool same_elements(const Mesh& a, const Mesh& b) {
  const MeshElements &ea = a.elements(), &eb = b.elements();
  return ea.kinds == eb.kinds && ea.offsets == eb.offsets && ea.corners == eb.corners;
}

}  // namespace

MeshDifference compare_vertices(const Mesh& a, const Mesh& b) {
  MeshDifference d;
  d.metric = "vertex";
  if (a.num_vertices() != b.num_vertices()) {
    d.comparable = false;
    d.reason = "vertex counts differ (" + std::to_string(a.num_vertices()) + " vs " +
               std::to_string(b.num_vertices()) + "); use --metric hausdorff";
    return d;
  }
  d.distances = vertex_distances(a, b, false);
  double sum = 0, sum2 = 0;
  for (std::size_t i = 0; i < d.distances.size(); ++i) {
    const double e = d.distances[i];
    sum += e;
    sum2 += e * e;
    if (e > d.max) {
      d.max = e;
      d.worst_vertex = i;
    }
  }
  const double n = std::max<double>(1, static_cast<double>(d.distances.size()));
  d.mean = sum / n;
  d.rms = std::sqrt(sum2 / n);
  d.same_connectivity = same_elements(a, b);
  if (!d.same_connectivity)
    d.reason = "face lists differ (" + std::to_string(a.num_faces()) + " vs " + std::to_string(b.num_faces()) +
               " faces)";
  return d;
}

namespace {

// Adds the distances that are known (not NaN) to the sums and the count.
void add_distances(const std::vector<double>& distances, double& sum, double& sum2, std::size_t& n) {
  for (const double e : distances) {
    if (std::isnan(e)) continue;
    sum += e;
    sum2 += e * e;
    ++n;
  }
}

// Both meshes' indexes, built at once (a tree build is sequential).
std::pair<std::unique_ptr<SurfaceIndex>, std::unique_ptr<SurfaceIndex>> index_both(const Mesh& a, const Mesh& b) {
  std::unique_ptr<SurfaceIndex> ia, ib;
#pragma omp parallel sections num_threads(2)
  {
#pragma omp section
    ia = std::make_unique<SurfaceIndex>(a);
#pragma omp section
    ib = std::make_unique<SurfaceIndex>(b);
  }
  return {std::move(ia), std::move(ib)};
}

}  // namespace

MeshDifference compare_hausdorff(const Mesh& a, const Mesh& b, const HausdorffOptions& options) {
  MeshDifference d;
  d.metric = "hausdorff";
  d.error_bound = options.error_bound;
  if (a.num_faces() == 0 || b.num_faces() == 0) {
    d.comparable = false;
    d.reason = "the Hausdorff metric needs faces on both meshes";
    return d;
  }
  const auto [ia, ib] = index_both(a, b);
  const bool matched = a.num_vertices() == b.num_vertices();
  const DirectedHausdorff ab = directed_hausdorff(*ia, *ib, options, matched);
  DirectedHausdorff ba = directed_hausdorff(*ib, *ia, options, matched, ab.lower);
  d.max = std::max(ab.lower, ba.lower);
  d.max_upper = std::max(ab.upper, ba.upper);
  d.larger = d.max > options.tolerance;
  d.points = ab.points + ba.points;
  double sum = 0, sum2 = 0;
  std::size_t n = 0;
  add_distances(ab.vertex_distances, sum, sum2, n);
  add_distances(ba.vertex_distances, sum, sum2, n);
  d.distances = std::move(ba.vertex_distances);
  d.mean = n ? sum / n : 0;
  d.rms = n ? std::sqrt(sum2 / n) : 0;
  d.same_connectivity = same_elements(a, b);
  return d;
}

namespace {

double bbox_diagonal(const Mesh& m) {
  if (m.num_vertices() == 0) return 0;
  const ConstVec3Array p = m.positions();
  return (p.rowwise().maxCoeff() - p.rowwise().minCoeff()).norm();
}

}  // namespace

MeshDifference compare_meshes(const Mesh& a, const Mesh& b, const CompareOptions& options) {
  if (options.metric == "vertex") return compare_vertices(a, b);
  HausdorffOptions h{options.tolerance, options.error_bound, options.threads};
  if (!(h.error_bound > 0)) h.error_bound = options.tolerance > 0 ? options.tolerance / 10 : 1e-6 * bbox_diagonal(a);
  // Below 1e-9 of the mesh's size the bounds are rounding, and the splits would not end.
  h.error_bound = std::max(h.error_bound, 1e-9 * bbox_diagonal(a));
  return compare_hausdorff(a, b, h);
}

bool within_tolerance(const MeshDifference& d, double tolerance) {
  if (!d.comparable) return false;
  if (d.metric == "vertex") return d.same_connectivity && d.max <= tolerance;
  return !d.larger;
}

std::vector<double> vertex_distances(const Mesh& a, const Mesh& b, bool hausdorff) {
  if (hausdorff) {
    if (!a.num_faces() || !b.num_faces()) return {};
    const SurfaceIndex ia(a), ib(b);
    return directed_hausdorff(ib, ia, HausdorffOptions{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(), 0}, false)
        .vertex_distances;
  }
  if (a.num_vertices() != b.num_vertices()) return {};
  std::vector<double> out(b.num_vertices());
  for (std::size_t v = 0; v < out.size(); ++v) {
    const auto i = static_cast<Eigen::Index>(v);
    out[v] = (a.positions().col(i) - b.positions().col(i)).norm();
  }
  return out;
}

}  // namespace ffd
