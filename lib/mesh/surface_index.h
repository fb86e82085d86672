// A mesh's surface for closest-point queries: its polygons as triangles (each fanned from
// its first corner) in a bounding volume hierarchy (mesh/triangle_bvh.h). `compare`
// builds one per mesh and shares it between the Hausdorff distance and the per-vertex
// distances (mesh/hausdorff.h).
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "mesh/mesh.h"
#include "mesh/triangle_bvh.h"

namespace ffd {

class SurfaceIndex {
public:
  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

  /// Indexes `mesh`'s polygons (its lines and points are no surface). The mesh must
  /// outlive the index and keep its positions.
  explicit SurfaceIndex(const Mesh& mesh);
  SurfaceIndex(const SurfaceIndex&) = delete;
  SurfaceIndex& operator=(const SurfaceIndex&) = delete;

  const Mesh& mesh() const { return mesh_; }
  std::size_t num_triangles() const { return triangles_.size(); }
  /// The vertex ids of triangle t.
  const std::array<std::uint32_t, 3>& triangle(std::uint32_t t) const { return triangles_[t]; }
  /// Vertex v's position.
  Eigen::Vector3d vertex(std::uint32_t v) const { return mesh_.positions().col(v); }
  /// A triangle that uses vertex v, or kNone when no polygon does.
  std::uint32_t triangle_of_vertex(std::uint32_t v) const { return vertex_triangle_[v]; }

  /// The triangles in the tree's leaf order (nearby triangles together).
  const std::vector<std::uint32_t>& spatial_order() const { return tree_.leaf_order(); }

  /// The squared distance from p to triangle t.
  double squared_distance(const Eigen::Vector3d& p, std::uint32_t t) const { return tree_.squared_distance(p, t); }

  using Closest = TriangleBvh::Closest;
  /// The triangle closest to p and its squared distance, searched nearest box first from
  /// `hint` (a triangle near p, or kNone), which only makes the search shorter. Equal
  /// hints give equal answers; ties go to the triangle met first. Thread-safe.
  Closest closest(const Eigen::Vector3d& p, std::uint32_t hint = kNone) const { return tree_.closest(p, hint); }

private:
  const Mesh& mesh_;
  std::vector<std::array<std::uint32_t, 3>> triangles_;
  std::vector<std::uint32_t> vertex_triangle_;
  TriangleBvh tree_;
};

}  // namespace ffd
