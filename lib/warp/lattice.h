// Lattice: a tensor-product control lattice over a parallelepiped, the common part of
// the Bernstein (Sederberg & Parry) and uniform B-spline (Gain & Dodgson) FFDs.
//
// Promises:
// - Displacement form: F(x) = x + sum_ijk B_i(u) B_j(v) B_k(w) (P_ijk - P°_ijk), where P°
//   is the rest lattice. By linear precision this is eq. 1 of Gain & Dodgson; written this
//   way an unmoved lattice is the identity exactly, and so are cells with no moved point.
// - Points outside the box (beyond a 1e-9 tolerance in box coordinates, so points on its
//   faces count as inside) are never touched: F(x) = x bit for bit.
// - Control point (i,j,k) sits at origin + axes · (node_i/l, node_j/m, node_k/n) at rest,
//   where node is the basis's Greville abscissa (linear precision).
// - Only movable points may move; which ones is the basis's rule (see subclasses).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "warp/deformer.h"
#include "warp/parallelepiped.h"

namespace ffd {

using Index3 = std::array<int, 3>;

/// Tolerance, in box coordinates, within which a point outside the box counts as inside.
constexpr double kBoxTolerance = 1e-9;

class Lattice : public Deformer {
public:
  enum class Basis { Bernstein, BSpline };

  Lattice(const Parallelepiped& box, Index3 cells);

  virtual Basis basis() const = 0;
  /// Polynomial degree along each axis.
  virtual Index3 degree() const = 0;
  /// C^k continuity of the warp across the box's faces; -1 when it can tear there.
  virtual int boundary_continuity() const = 0;

  const Parallelepiped& box() const { return box_; }
  const Index3& cells() const { return cells_; }

  /// Inclusive index range of the control points along `axis` (B-spline border points
  /// outside the box have indices below 0 or above cells).
  int first_index(int axis) const { return first_[axis]; }
  int last_index(int axis) const { return first_[axis] + count_[axis] - 1; }
  std::size_t num_points() const { return displacement_.size(); }
  bool in_range(const Index3& ijk) const;
  std::size_t flat(const Index3& ijk) const;
  Index3 index(std::size_t flat) const;

  virtual bool movable(const Index3& ijk) const = 0;
  /// "i in [2, 4], j in [2, 4], k in [2, 6]", for error messages.
  std::string movable_range() const;
  /// The movable index range along `axis` (empty when lo > hi).
  virtual void movable_span(int axis, int& lo, int& hi) const = 0;

  Eigen::Vector3d rest_point(const Index3& ijk) const;
  Eigen::Vector3d point(const Index3& ijk) const { return rest_point(ijk) + displacement_[flat(ijk)]; }
  const Eigen::Vector3d& displacement(std::size_t flat) const { return displacement_[flat]; }
  /// Moves a movable point to `position`. \throw std::logic_error if it is not movable
  /// (the script checks that first and reports it as an input error).
  void move_point(const Index3& ijk, const Eigen::Vector3d& position);
  /// True if any point on the box's faces (or beyond) was moved: then a Bernstein warp
  /// tears where the mesh leaves the box.
  bool boundary_moved() const;

  /// The basis weights at x of the movable points with non-zero weight: (flat, weight),
  /// flat indices ascending.
  void movable_weights(const Eigen::Vector3d& x, PointWeights& out) const;

  // Deformer: one level, ids are flat indices (every point, border points included).
  std::string kind() const override { return basis() == Basis::Bernstein ? "bernstein" : "bspline"; }
  std::size_t num_points(int) const override { return num_points(); }
  Eigen::Matrix3Xd points(int level) const override;
  Eigen::Matrix3Xd points(int level, const std::vector<std::size_t>& ids) const override;
  bool point_movable(int, std::size_t id) const override { return movable(index(id)); }
  std::optional<std::size_t> find_point(int level, const PointIndex& index) const override;
  std::string missing_point(int level, const PointIndex& index) const override;
  PointIndex point_index(int, std::size_t id) const override { return {true, index(id), 0}; }
  std::string movable_text(int) const override { return movable_range(); }
  MoveReport move_points(int level, const std::vector<std::size_t>& ids,
                         const std::vector<Eigen::Vector3d>& targets) override;
  void movable_weights(int, const Eigen::Vector3d& x, PointWeights& out) const override { movable_weights(x, out); }
  /// Neighbours along each axis, (f, next) in flat order of f, then axis.
  std::vector<std::array<std::uint32_t, 2>> net_edges(int level) const override;
  double scale() const override { return box_.extents().norm(); }
  bool tears() const override { return boundary_continuity() < 0; }
  bool in_support(const Eigen::Vector3d& x) const override { return inside(box_.to_local(x)); }
  std::string tearing_warning(const std::string& name, std::size_t outside) const override;

  // Warp
  Eigen::Vector3d apply(const Eigen::Vector3d& x, Eigen::Matrix3d* jacobian) const override;
  void apply(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
             const Eigen::Ref<const Eigen::Matrix3Xd>& in_nrm, const std::vector<std::uint32_t>& ids,
             Eigen::Ref<Eigen::Matrix3Xd> out_pos, Eigen::Ref<Eigen::Matrix3Xd> out_nrm,
             WarpCounts& counts) const override;
  void changed_points(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                      std::vector<std::uint32_t>& ids) const override;
  bool has_changes() const override { return any_changed_; }
  void clear_changes() override;
  /// True when [a, b] meets the box grown by kBoxTolerance in box coordinates (a slab
  /// test): outside that, apply() leaves points untouched.
  bool can_act_on_segment(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const override;
  /// The smallest cell extent: min over the axes of box edge length / cells.
  double feature_size() const override;
  /// Whether det J > 0 at every point of the box, by a bound on the derivatives (then a
  /// batch apply needs no Jacobian for points whose normals are zero).
  bool fold_free() const;

  /// Number of polynomial pieces per axis: the B-spline's cells, one for Bernstein.
  virtual Index3 pieces() const = 0;
  /// The piece of box coordinate u along `axis`, and the local coordinate within it.
  void locate(int axis, double u, int& piece, double& local) const;
  /// Whether box coordinates u lie inside the box (within kBoxTolerance).
  static bool inside(const Eigen::Vector3d& u) {
    return (u.array() >= -kBoxTolerance).all() && (u.array() <= 1 + kBoxTolerance).all();
  }

  /// Basis values along `axis` at box coordinate u: the index of the first control point
  /// with a non-zero weight, the weights w, and dw/du. Arrays hold order(axis) values.
  virtual void axis_weights(int axis, double u, int& first, double* w, double* dw) const = 0;
  /// Number of non-zero basis functions along `axis` at any u (degree + 1).
  int order(int axis) const { return degree()[axis] + 1; }

  /// The piece, of n along an axis, that holds s = u * n for box coordinate u (the end
  /// pieces hold what lies outside within the tolerance): locate()'s rule, for the scans
  /// that inline it.
  static int piece_at(double s, int n) { return std::clamp(static_cast<int>(std::floor(s)), 0, n - 1); }

protected:
  /// Whether every piece changed since clear_changes() (then the changed points are the
  /// points inside the box).
  bool all_pieces_changed() const {
    return std::all_of(changed_piece_.begin(), changed_piece_.end(), [](std::uint8_t c) { return c != 0; });
  }
  /// Greville abscissa of control index i along `axis`, in box coordinates.
  virtual double node(int axis, int i) const = 0;
  /// Inclusive range of pieces along `axis` that control index i influences.
  virtual void pieces_of_point(int axis, int i, int& lo, int& hi) const = 0;
  /// Called once the index ranges are known, by subclass constructors.
  void init_points(Index3 first, Index3 count);
  std::size_t flat_piece(const Index3& p) const {
    const Index3 n = pieces();
    return (static_cast<std::size_t>(p[2]) * n[1] + p[1]) * n[0] + p[0];
  }
  /// Called for each piece whose displacement polynomial changed.
  virtual void piece_changed(std::size_t flat_piece) {}

  Parallelepiped box_;
  Index3 cells_;
  Index3 first_{0, 0, 0};
  Index3 count_{0, 0, 0};
  std::vector<Eigen::Vector3d> displacement_;
  std::vector<std::uint8_t> changed_piece_;  // bit index: pieces altered since clear_changes
  bool any_changed_ = false;
};

}  // namespace ffd
