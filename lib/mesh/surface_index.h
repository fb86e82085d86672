// A mesh's surface for closest-point queries: its polygons as triangles (each fanned from
// its first corner) in CGAL's AABB tree. `compare` builds one per mesh and shares it
// between the Hausdorff distance and the per-vertex distances (mesh/hausdorff.h).
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "mesh/mesh.h"

namespace ffd {

class SurfaceIndex {
public:
  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

  /// Indexes `mesh`'s polygons (its lines and points are no surface). The mesh must
  /// outlive the index and keep its positions.
  explicit SurfaceIndex(const Mesh& mesh);
  ~SurfaceIndex();
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

  /// The squared distance from p to triangle t.
  double squared_distance(const Eigen::Vector3d& p, std::uint32_t t) const;

  struct Closest {
    double squared = std::numeric_limits<double>::infinity();
    std::uint32_t triangle = kNone;
  };
  /// The triangle closest to p and its squared distance, searched nearest box first from
  /// `hint` (a triangle near p, or kNone), which only makes the search shorter. Equal
  /// hints give equal answers; ties go to the triangle met first. Thread-safe.
  Closest closest(const Eigen::Vector3d& p, std::uint32_t hint = kNone) const;

private:
  const Mesh& mesh_;
  std::vector<std::array<std::uint32_t, 3>> triangles_;
  std::vector<std::uint32_t> vertex_triangle_;
  struct Tree;
  std::unique_ptr<Tree> tree_;
};

}  // namespace ffd
