// Bernstein (Bézier) FFD, Sederberg & Parry 1986: one trivariate Bernstein polynomial
// over the whole box.
//
// Promises:
// - `cells` = (l, m, n) gives degrees l, m, n: (l+1)(m+1)(n+1) control points on the box's
//   regular grid, indices 0..l, 0..m, 0..n. Every point may move.
// - Points inside the box (faces included) deform; points outside are untouched. The warp
//   is continuous (C0) across the box's faces only while no point on the faces has moved:
//   moving a face point tears a mesh that leaves the box (boundary_continuity() says -1
//   and the run warns).
#pragma once

#include "warp/lattice.h"

namespace ffd {

class BernsteinLattice : public Lattice {
public:
  /// Highest degree per axis: Bernstein weights stay exact to rounding, but a larger
  /// Bézier lattice is better served by a B-spline one.
  static constexpr int kMaxDegree = 24;

  /// \throw InputError if a degree is below 1 or above kMaxDegree.
  BernsteinLattice(const Parallelepiped& box, Index3 degrees);

  Basis basis() const override { return Basis::Bernstein; }
  Index3 degree() const override { return cells_; }
  int boundary_continuity() const override { return boundary_moved() ? -1 : 0; }
  bool movable(const Index3& ijk) const override { return in_range(ijk); }
  void movable_span(int axis, int& lo, int& hi) const override;
  Index3 pieces() const override { return {1, 1, 1}; }
  void axis_weights(int axis, double u, int& first, double* w, double* dw) const override;

  /// Bernstein polynomials B_i^n(u), i = 0..n, by de Casteljau's recurrence (stable).
  static void bernstein(int n, double u, double* out);

  /// Batch evaluation, positions and normals: blocks of kBlock vertices, the Bernstein
  /// values and derivatives of each axis once per vertex, and the contraction and its three
  /// derivatives coordinate by coordinate across the block's vertices (vectorized), summed
  /// over k, then j, then i for every vertex whatever the block.
  void apply(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
             const Eigen::Ref<const Eigen::Matrix3Xd>& in_nrm, const std::vector<std::uint32_t>& ids,
             Eigen::Ref<Eigen::Matrix3Xd> out_pos, Eigen::Ref<Eigen::Matrix3Xd> out_nrm,
             WarpCounts& counts) const override;
  using Lattice::apply;

  /// Positions only (d(points), benchmarks): blocks of kBlock points, the Bernstein values
  /// of each axis once per point and the contraction coordinate by coordinate across the
  /// block's points (which the compiler vectorizes), in apply()'s order of summation.
  void apply_positions(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos, const std::vector<std::uint32_t>& ids,
                       Eigen::Ref<Eigen::Matrix3Xd> out_pos) const;
  /// apply_positions when the lattice cannot fold (Lattice::fold_free): apply() takes
  /// zero normals that way too, and counts no fold.
  bool apply_without_normals(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos, const std::vector<std::uint32_t>& ids,
                             Eigen::Ref<Eigen::Matrix3Xd> out_pos, WarpCounts& counts) const override;
  /// The changed-points scan and the positions in one pass over in_pos (Warp), where
  /// apply_without_normals() would take the points: no normals, and no fold possible.
  bool apply_changed(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos, const Eigen::Ref<const Eigen::Matrix3Xd>* in_nrm,
                     std::vector<std::uint32_t>& ids, Eigen::Ref<Eigen::Matrix3Xd> out_pos,
                     Eigen::Ref<Eigen::Matrix3Xd>* out_nrm, WarpCounts& counts) const override;
  static constexpr int kBlock = 16;

protected:
  double node(int axis, int i) const override { return static_cast<double>(i) / cells_[axis]; }
  void pieces_of_point(int axis, int i, int& lo, int& hi) const override { lo = hi = 0; }

private:
  /// apply_positions, returning how many of the points lie in the box (moved). With `ids`
  /// null: every column of in_pos, of which those in the box (changed_points()' list, in
  /// order) are appended to `found` and written.
  std::size_t positions(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos, const std::vector<std::uint32_t>* ids,
                        Eigen::Ref<Eigen::Matrix3Xd> out_pos, std::vector<std::uint32_t>* found = nullptr) const;
  /// The displacements as [i][j][k][x, y, z], the kernels' order.
  std::vector<double> packed_displacements() const;
  /// Degree 3 on every axis (PyGeM's and most users' lattices): kernels with the degree
  /// known when compiled.
  bool is_cubic() const { return cells_[0] == 3 && cells_[1] == 3 && cells_[2] == 3; }
};

}  // namespace ffd
