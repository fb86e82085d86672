// A mesh's surface for closest-point queries: its polygons as triangles (each fanned from
// its first corner) in CGAL's AABB tree. `compare` builds one per mesh and shares it
// between the Hausdorff distance and the per-vertex distances (mesh/hausdorff.h).
//
// The triangles are numbered along a Morton curve through their centroids, and the
// points (the vertices they use) as the triangles first use them: whatever order the
// file has, a pass in that order visits nearby places one after another, so the tree's
// build and a run of searches stay in cache (a 1.7M-vertex mesh whose file scatters its
// triangles took 10 s to compare in file order, 5.8 s in this one). mesh_vertex() and
// fan_index() give the mesh's numbers back.
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

  /// The mesh's vertex count (used by a triangle or not).
  std::size_t num_mesh_vertices() const { return point_of_vertex_.size(); }
  /// The points: the vertices the triangles use, in the index's order.
  std::size_t num_points() const { return mesh_vertex_.size(); }
  Eigen::Vector3d point(std::uint32_t p) const { return positions_.col(mesh_vertex_[p]); }
  /// The mesh vertex point p is, and the point mesh vertex v is (kNone when no polygon uses it).
  std::uint32_t mesh_vertex(std::uint32_t p) const { return mesh_vertex_[p]; }
  std::uint32_t point_of_vertex(std::uint32_t v) const { return point_of_vertex_[v]; }
  /// A triangle that has point p as a corner.
  std::uint32_t triangle_of_point(std::uint32_t p) const { return point_triangle_[p]; }

  std::size_t num_triangles() const { return triangles_.size(); }
  /// Triangle t's corners (points).
  const std::array<std::uint32_t, 3>& triangle(std::uint32_t t) const { return triangles_[t]; }
  /// Triangle t's place among the mesh's fanned polygons (polygon by polygon, fan by fan),
  /// and the triangle at place f.
  std::uint32_t fan_index(std::uint32_t t) const { return fan_index_[t]; }
  std::uint32_t triangle_at_fan_index(std::uint32_t f) const { return triangle_at_fan_[f]; }

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
  // Numbers the points and triangles (mesh_vertex_, triangles_ and the maps); the
  // temporaries are freed on return, before the tree is built.
  void number_in_morton_order(const Mesh& mesh);

  ConstVec3Array positions_;
  std::vector<std::uint32_t> mesh_vertex_, point_of_vertex_, point_triangle_;
  std::vector<std::array<std::uint32_t, 3>> triangles_;
  std::vector<std::uint32_t> fan_index_, triangle_at_fan_;
  struct Tree;
  std::unique_ptr<Tree> tree_;
};

}  // namespace ffd
