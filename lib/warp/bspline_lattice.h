// Uniform B-spline FFD of degree 1-3 with Gain & Dodgson's deformable / influenced /
// phantom zones (section 2, figure 2).
//
// Promises:
// - `cells` = l × m × n uniform knot spans across the box; control point i along an axis
//   sits at its Greville abscissa: the grid node i for degrees 1 and 3, the cell centre
//   i + 1/2 for degree 2. Index ranges: cubic -1..l+1, quadratic -1..l, linear 0..l.
// - Only points whose whole support lies inside the box move (the deformable zone:
//   cubic 2..l-2, quadratic 1..l-2, linear 1..l-1); the influenced zone (two cells for
//   cubic) and the phantom layer stay fixed. So the displacement vanishes with its first
//   degree-1 derivatives on the box's faces: identity outside (bit for bit), C^(degree-1)
//   across the faces. A cubic lattice needs l >= 4 for any movable point.
// - Evaluation is per cell in power form: each altered cell keeps the polynomial
//   coefficients of its displacement, evaluated by Horner's rule for eight vertices of
//   one cell at a time, one per SIMD lane (value and Jacobian together); cells without
//   moved points are skipped (the paper's bit index).
#pragma once

#include "warp/lattice.h"

namespace ffd {

class BSplineLattice : public Lattice {
public:
  /// \throw InputError if degree is not 1, 2 or 3 or a cell count is below 1.
  BSplineLattice(const Parallelepiped& box, Index3 cells, int degree);

  Basis basis() const override { return Basis::BSpline; }
  Index3 degree() const override { return {degree_, degree_, degree_}; }
  int boundary_continuity() const override { return degree_ - 1; }
  bool movable(const Index3& ijk) const override;
  void movable_span(int axis, int& lo, int& hi) const override;
  Index3 pieces() const override { return cells_; }
  void axis_weights(int axis, double u, int& first, double* w, double* dw) const override;

  void prepare() override;
  void apply(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
             const Eigen::Ref<const Eigen::Matrix3Xd>& in_nrm, const std::vector<std::uint32_t>& ids,
             Eigen::Ref<Eigen::Matrix3Xd> out_pos, Eigen::Ref<Eigen::Matrix3Xd> out_nrm,
             WarpCounts& counts) const override;
  using Lattice::apply;

  /// Positions, and where the lattice may fold (not Lattice::fold_free) the fold count
  /// from det J, without the normals: apply()'s positions and counts for zero normals.
  bool apply_without_normals(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos, const std::vector<std::uint32_t>& ids,
                             Eigen::Ref<Eigen::Matrix3Xd> out_pos, WarpCounts& counts) const override;

  /// The changed-points scan and the evaluation in one pass over in_pos (Warp).
  bool apply_changed(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos, const Eigen::Ref<const Eigen::Matrix3Xd>* in_nrm,
                     std::vector<std::uint32_t>& ids, Eigen::Ref<Eigen::Matrix3Xd> out_pos,
                     Eigen::Ref<Eigen::Matrix3Xd>* out_nrm, WarpCounts& counts) const override;

  /// Positions only, for callers that need no normals (benchmarks, drag residuals).
  void apply_positions(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                       const std::vector<std::uint32_t>& ids,
                       Eigen::Ref<Eigen::Matrix3Xd> out_pos) const;

  /// The movable index range along an axis of `cells` cells for this degree (empty when
  /// lo > hi), without building a lattice: used to check scripts before a run.
  static void movable_span(int degree, int cells, int& lo, int& hi) {
    lo = degree - degree / 2;
    hi = cells - 1 - degree / 2;
  }
  /// Inclusive control index range along an axis of `cells` cells.
  static void index_span(int degree, int cells, int& first, int& last) {
    first = -(degree / 2);
    last = cells - 1 + degree - degree / 2;
  }

  /// Power-basis matrix M (row p = coefficient of local^p, column = control point of the
  /// cell) of the uniform B-spline of this degree; weights w_i(σ) = Σ_p M(p,i) σ^p.
  static Eigen::MatrixXd power_matrix(int degree);

protected:
  double node(int axis, int i) const override;
  void pieces_of_point(int axis, int i, int& lo, int& hi) const override;
  void piece_changed(std::size_t piece) override;

private:
  /// Which points an evaluation visits: the listed ids, or (ids null) every column of
  /// in_pos that changed_points() would list, appended to `found` as it would append them.
  struct Visit {
    const std::vector<std::uint32_t>* ids = nullptr;
    std::vector<std::uint32_t>* found = nullptr;
  };
  // in_nrm / out_nrm null: positions only, and with `count_folds` the folds counted too.
  template <int D>
  void evaluate(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos, const Eigen::Ref<const Eigen::Matrix3Xd>* in_nrm,
                const Visit& visit, Eigen::Ref<Eigen::Matrix3Xd>& out_pos, Eigen::Ref<Eigen::Matrix3Xd>* out_nrm,
                WarpCounts& counts, bool count_folds = false) const;
  /// evaluate<D> for the lattice's degree.
  void evaluate_degree(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos, const Eigen::Ref<const Eigen::Matrix3Xd>* in_nrm,
                       const Visit& visit, Eigen::Ref<Eigen::Matrix3Xd>& out_pos,
                       Eigen::Ref<Eigen::Matrix3Xd>* out_nrm, WarpCounts& counts, bool count_folds = false) const;
  void compute_block(std::size_t piece) const;

  int degree_;
  Eigen::MatrixXd power_;                // (degree+1)^2
  Eigen::Matrix3d local_to_world_jac_;   // dσ/dx: diag(cells) · inverse axes
  // Power-form cache, refreshed lazily (prepare(), or the first evaluation after a move).
  mutable std::vector<std::int32_t> block_of_;  // per cell: block number, -1 = no displacement
  // per block: [xyz][p][q][r] power coefficients (the kernel broadcasts each one)
  mutable std::vector<double> blocks_;
  mutable std::vector<std::int32_t> free_blocks_;
  mutable std::vector<std::uint8_t> stale_;     // cells whose block must be recomputed
  mutable std::vector<std::size_t> stale_list_;
  void refresh_blocks() const;
};

}  // namespace ffd
