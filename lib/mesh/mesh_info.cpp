#include "mesh/mesh_info.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "common/errors.h"
#include "mesh/halfedge_view.h"

namespace ffd {
namespace {

// Union-find over vertex indices, for connected pieces and boundary loops.
struct Pieces {
  std::vector<std::uint32_t> parent;
  explicit Pieces(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  std::uint32_t find(std::uint32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  }
  void join(std::uint32_t a, std::uint32_t b) { parent[find(a)] = find(b); }
};

// Face counts by degree, zero-area faces, lines, points.
void count_elements(const Mesh& mesh, MeshInfo& info) {
  const MeshElements& el = mesh.elements();
  const ConstVec3Array p = mesh.positions();
  for (std::size_t e = 0; e < el.size(); ++e) {
    if (el.kinds[e] == ElementKind::Line) ++info.lines;
    if (el.kinds[e] == ElementKind::Point) ++info.points;
    if (el.kinds[e] != ElementKind::Polygon) continue;
    ++info.faces_by_degree[el.degree(e)];
    const std::uint32_t* v = el.vertices(e);
    Eigen::Vector3d area = Eigen::Vector3d::Zero();
    for (std::uint32_t i = 1; i + 1 < el.degree(e); ++i)
      area += (p.col(v[i]) - p.col(v[0])).cross(p.col(v[i + 1]) - p.col(v[0]));
    if (!(area.norm() > 0)) ++info.degenerate_faces;
  }
}

// Edges (distinct vertex pairs of polygon sides), their lengths, boundary and
// non-manifold edges, boundary loops, pieces and isolated vertices.
void count_edges(const Mesh& mesh, MeshInfo& info) {
  const MeshElements& el = mesh.elements();
  const ConstVec3Array p = mesh.positions();
  std::vector<std::uint64_t> sides;
  sides.reserve(el.corners.size());
  Pieces pieces(mesh.num_vertices());
  std::vector<char> used(mesh.num_vertices(), 0);
  for (std::size_t e = 0; e < el.size(); ++e) {
    if (el.kinds[e] != ElementKind::Polygon) continue;
    const std::uint32_t* v = el.vertices(e);
    for (std::uint32_t i = 0, n = el.degree(e); i < n; ++i) {
      const std::uint32_t a = v[i], b = v[(i + 1) % n];
      used[a] = 1;
      pieces.join(a, b);
      if (a != b) sides.push_back((std::uint64_t(std::min(a, b)) << 32) | std::max(a, b));
    }
  }
  std::sort(sides.begin(), sides.end());
  Pieces loops(mesh.num_vertices());
  std::vector<char> on_boundary(mesh.num_vertices(), 0);
  double sum = 0;
  info.min_edge = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < sides.size();) {
    std::size_t j = i;
    while (j < sides.size() && sides[j] == sides[i]) ++j;
    const auto a = static_cast<std::uint32_t>(sides[i] >> 32), b = static_cast<std::uint32_t>(sides[i]);
    const double len = (p.col(a) - p.col(b)).norm();
    ++info.edges;
    sum += len;
    info.min_edge = std::min(info.min_edge, len);
    info.max_edge = std::max(info.max_edge, len);
    if (j - i == 1) {
      ++info.boundary_edges;
      loops.join(a, b);
      on_boundary[a] = on_boundary[b] = 1;
    }
    if (j - i > 2) ++info.non_manifold_edges;
    i = j;
  }
  if (info.edges == 0) info.min_edge = 0;
  info.mean_edge = info.edges ? sum / static_cast<double>(info.edges) : 0;
  for (std::uint32_t v = 0; v < mesh.num_vertices(); ++v) {
    if (!used[v]) ++info.isolated_vertices;
    if (used[v] && pieces.find(v) == v) ++info.components;
    if (on_boundary[v] && loops.find(v) == v) ++info.boundary_loops;
  }
}

}  // namespace

MeshInfo mesh_info(const Mesh& mesh) {
  MeshInfo info;
  info.vertices = mesh.num_vertices();
  info.faces = mesh.num_faces();
  info.has_uvs = mesh.has_uvs();
  info.has_normals = mesh.has_file_normals();
  info.has_colors = mesh.has_colors();
  const ConstVec3Array p = mesh.positions();
  if (p.cols() > 0) {
    info.min = p.rowwise().minCoeff();
    info.max = p.rowwise().maxCoeff();
    info.diagonal = (info.max - info.min).norm();
  }
  count_elements(mesh, info);
  count_edges(mesh, info);
  info.euler = static_cast<long>(info.vertices) - static_cast<long>(info.edges) + static_cast<long>(info.faces);
  try {
    check_two_manifold(mesh);
  } catch (const TopologyError& e) {
    info.manifold_problem = e.what();
  }
  return info;
}

}  // namespace ffd
