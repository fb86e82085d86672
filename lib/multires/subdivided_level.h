// SubdividedLevel: a level of an octree lattice made by local subdivision (Ono et al.
// section 2.2, Figure 3) of chosen cells of a grid level, and its deformation by
// Catmull-Clark subdivision volumes on the general CellComplex.
//
// Cells next to the subdivided ones are not hexahedra (their split faces and edges give
// extraordinary points), and neither are the cells Catmull-Clark makes at those points.
// MacCracken & Joy parameterize hexahedra trilinearly and other cells by tetrahedra; a
// trilinear hexahedron beside a tetrahedralized cell would not agree on their shared face
// (bilinear against piecewise linear), and the deformation would tear there. So every
// cell of such a level is split into the tetrahedra (cell centroid, face centroid, edge)
// and a vertex takes barycentric coordinates in its tetrahedron: continuous everywhere,
// and the same trilinear-free rule on both sides of every face.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include "multires/cell_complex.h"
#include "warp/parallelepiped.h"

namespace ffd {

class SubdividedLevel {
public:
  /// The cells of `grid` flagged in `cells` subdivided; rest positions by the octree rules
  /// from `grid_rest`. Points are grid nodes at twice the grid's resolution.
  SubdividedLevel(const Parallelepiped& box, int source_level, const GridComplex& grid, const Eigen::Matrix3Xd& grid_rest,
                  const std::vector<std::uint8_t>& cells, int cc_steps);

  int source_level() const { return source_; }
  int resolution() const { return resolution_; }
  const CellComplex& complex() const { return sub_[0]; }
  const std::vector<GridIndex>& nodes() const { return nodes_; }
  std::size_t subdivided_cells() const { return subdivided_; }
  /// Index of the point at node `n` (twice the source resolution), or -1.
  std::int32_t point_index(const GridIndex& n) const;
  /// The octree rules from the source level's points: this level's = from_source * source's.
  const Eigen::SparseMatrix<double, Eigen::RowMajor>& from_source() const { return from_source_; }
  const Eigen::Matrix3Xd& rest() const { return fine_[0]; }
  const Eigen::Matrix3Xd& delta() const { return delta_; }
  bool moved() const { return moved_; }

  /// Where a point lies: the tetrahedron (cell centroid, face centroid, the face's edge
  /// from loop[slot] to loop[slot + 1]) of a cell of C^step, and its barycentric coordinates.
  struct Location {
    int step = -1;
    std::int32_t cell = -1, face = -1, slot = -1;
    Eigen::Vector4d lambda = Eigen::Vector4d::Zero();  // (cell centroid, face centroid, a, b)
  };
  /// The tetrahedron of the finest C^k (the minimal cell) that holds x; false when none does.
  bool locate(const Eigen::Vector3d& x, Location& where) const;
  /// Where face f is among the faces of cell c of C^k, and the face at that place: a byte
  /// where a location is kept for every vertex (the octree lattice's tags).
  std::uint8_t face_place(int k, std::int32_t c, std::int32_t f) const;
  std::int32_t face_at(int k, std::int32_t c, std::uint8_t place) const;
  /// This level's F(x) - x at `where`, and its part of dF/dx - I when asked.
  Eigen::Vector3d displacement(const Location& where, Eigen::Matrix3d* jacobian) const;

  /// Bounds, in box coordinates, of a region where a move changed the displacement.
  using Bounds = std::pair<Eigen::Vector3d, Eigen::Vector3d>;
  /// Adds `change` to the moves of points `ids` and re-subdivides the moves (the whole
  /// level); returns the bounds of the rest cells, at every step, whose points the change
  /// reaches (vertices elsewhere keep their positions).
  std::vector<Bounds> move(const std::vector<std::int32_t>& ids, const Eigen::Matrix3Xd& change);
  /// The weights of this level's points at x (empty when x is in no cell).
  void point_weights(const Eigen::Vector3d& x, std::vector<std::pair<std::int32_t, double>>& out) const;
  /// Each edge of the level once, as point pairs.
  const std::vector<std::array<std::int32_t, 2>>& edges() const { return sub_[0].edges; }
  std::size_t bytes() const;

private:
  using Tet = Location;
  bool in_tet(int k, std::int32_t c, std::int32_t f, std::int32_t slot, const Eigen::Vector3d& x, Tet& where) const;
  /// Point weights of tet `where`'s barycentric coordinates, on C^k's points.
  void tet_weights(const Tet& where, std::vector<std::pair<std::int32_t, double>>& out) const;
  /// Box-coordinate bounds of cell c of C^k at rest.
  Bounds cell_bounds(int k, std::size_t c) const;
  void build_buckets(int k);

  Parallelepiped box_;
  int source_ = 0, resolution_ = 1;
  std::size_t subdivided_ = 0;
  std::vector<GridIndex> nodes_;
  Eigen::SparseMatrix<double, Eigen::RowMajor> from_source_;
  std::vector<CellComplex> sub_;
  std::vector<std::vector<std::vector<std::int32_t>>> cell_points_;  // per step, per cell
  std::vector<Eigen::Matrix3Xd> cell_centroids_, face_centroids_;    // per step, at rest
  std::vector<Eigen::SparseMatrix<double, Eigen::RowMajor>> steps_;  // C^k = steps_[k-1] * C^(k-1)
  std::vector<Eigen::Matrix3Xd> fine_, disp_;
  Eigen::Matrix3Xd delta_;
  struct Buckets {
    int n = 1;
    std::vector<std::int32_t> offsets, cells;
  };
  std::vector<Buckets> buckets_;
  bool moved_ = false;
};

}  // namespace ffd
