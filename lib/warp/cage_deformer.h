// CageDeformer: a closed triangle cage whose vertices are the control points, and mean
// value coordinates (warp/mean_value.h) carrying their moves to space:
//   F(x) = x + sum_j w_j(x) (p_j - r_j),
// r_j the cage's rest vertices, p_j where they are now. By the coordinates' linear
// precision (sum_j w_j(x) r_j = x) this is sum_j w_j(x) p_j, Ju et al.'s map; written as
// a displacement an unmoved cage is the identity bit for bit.
//
// Promises:
// - The cage is a closed, consistently oriented triangle mesh; polygon faces are split
//   into a fan from their first corner ((a, b, c, d) -> (a, b, c), (a, c, d)), as OBJ and
//   PLY readers do, so a non-planar polygon's shape follows that diagonal.
// - Linear in the cage's vertices: dF/dp_j = w_j(x) I.
// - Binding: bind() stores the coordinates (and their gradients, when normals need the
//   Jacobian) of given positions, so a pose costs one small product per point. A point
//   whose input differs from the position it was bound at is evaluated afresh: moves of
//   the warps under the cage stay right.
// - The batch evaluation computes the Jacobian where a normal needs it or the gradients
//   are bound; a point bound without gradients and without a normal gets no Jacobian, and
//   is not among the inverted Jacobians the warp counts.
// - Global: a move re-evaluates every point. A pose of a few cage vertices (under a
//   quarter) sums over those only.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "warp/mean_value.h"
#include "warp/scattered_deformer.h"

namespace ffd {

class CageDeformer : public ScatteredDeformer {
public:
  /// The cage: its vertices and its faces (polygons, counter-clockwise seen from outside).
  /// \throw InputError about "cage": no faces, a face with fewer than 3 corners or a
  /// repeated corner, two vertices at one place, an edge with no neighbour (open), used
  /// twice in one direction (inconsistent orientation, or more than two faces on it),
  /// naming the first such edge by its vertex numbers and its face; or a cage that encloses
  /// no volume. Faces may all point inward: the coordinates do not change.
  CageDeformer(std::vector<Eigen::Vector3d> rest, std::vector<std::vector<std::uint32_t>> faces);

  const std::vector<std::vector<std::uint32_t>>& faces() const { return faces_; }
  std::size_t num_triangles() const { return rest_cage_.triangles.size(); }

  /// What bind() stored.
  enum class Binding { None, Weights, WeightsAndGradients };
  /// Stores the coordinates of columns `positions`, and their gradients when
  /// `gradients`, as far as they fit in `max_bytes` (8 bytes per point and cage vertex for
  /// the coordinates, 12 more for the gradients, kept in single precision: they serve
  /// only normals, which are renormalized, and the sign of det J).
  /// Also counts, in `outside`, the positions outside the rest cage (count_outside's
  /// count, from the same angles where they are bound).
  Binding bind(const Eigen::Ref<const Eigen::Matrix3Xd>& positions, bool gradients, std::size_t max_bytes,
               std::size_t& outside);
  /// How many of `positions` lie outside the rest cage (winding number below 1/2).
  std::size_t count_outside(const Eigen::Ref<const Eigen::Matrix3Xd>& positions) const;

  std::string kind() const override { return "cage"; }
  void movable_weights(int level, const Eigen::Vector3d& x, PointWeights& out) const override;
  /// The cage's edges, each once.
  std::vector<std::array<std::uint32_t, 2>> net_edges(int) const override;
  std::vector<std::vector<std::uint32_t>> net_faces(int) const override { return faces_; }

  Eigen::Vector3d apply(const Eigen::Vector3d& x, Eigen::Matrix3d* jacobian) const override;
  void apply(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos, const Eigen::Ref<const Eigen::Matrix3Xd>& in_nrm,
             const std::vector<std::uint32_t>& ids, Eigen::Ref<Eigen::Matrix3Xd> out_pos,
             Eigen::Ref<Eigen::Matrix3Xd> out_nrm, WarpCounts& counts) const override;

private:
  void update_after_move() override;
  /// F at x from coordinates w, and J from their gradients g (3 x m) when both are given.
  template <class G>
  Eigen::Vector3d displaced(const Eigen::Vector3d& x, const Eigen::Ref<const Eigen::VectorXd>& w, const G* g,
                            Eigen::Matrix3d* jacobian) const;

  std::vector<std::vector<std::uint32_t>> faces_;
  MeanValueCage rest_cage_;
  Eigen::Matrix3Xd moves_;             // p_j - r_j as columns
  Eigen::Matrix3Xf moves_float_;       // the same, for the Jacobian from bound gradients
  std::vector<Eigen::Index> moved_ids_;  // the cage vertices off their rest positions
  Eigen::Matrix3Xd bound_positions_;   // the positions bind() was given
  Eigen::MatrixXd bound_weights_;      // m x n: column v the coordinates of point v
  Eigen::MatrixXf bound_gradients_;    // 3m x n: column v the gradients, 3 per cage vertex; or empty
};

}  // namespace ffd
