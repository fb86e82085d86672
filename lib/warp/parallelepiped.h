// A parallelepiped in world space: the box a lattice is built on.
#pragma once

#include <Eigen/Dense>

namespace ffd {

/// origin + axes · u for u in [0,1]^3. The axes are the box's edge vectors (columns),
/// any three linearly independent vectors: an axis-aligned box has a diagonal `axes`.
class Parallelepiped {
public:
  Parallelepiped() = default;
  /// \throw InputError when the axes are (nearly) linearly dependent.
  Parallelepiped(const Eigen::Vector3d& origin, const Eigen::Matrix3d& axes);
  /// The axis-aligned box [min, max]. \throw InputError if any extent is not positive.
  static Parallelepiped from_min_max(const Eigen::Vector3d& min, const Eigen::Vector3d& max);

  const Eigen::Vector3d& origin() const { return origin_; }
  const Eigen::Matrix3d& axes() const { return axes_; }
  /// d u / d x: the inverse of `axes`.
  const Eigen::Matrix3d& inverse_axes() const { return inverse_; }

  /// Box coordinates u of a world point (inside: every u_i in [0,1]).
  Eigen::Vector3d to_local(const Eigen::Vector3d& x) const { return inverse_ * (x - origin_); }
  Eigen::Vector3d to_world(const Eigen::Vector3d& u) const { return origin_ + axes_ * u; }
  /// Lengths of the three edges.
  Eigen::Vector3d extents() const { return axes_.colwise().norm(); }
  /// Whether the segment [a, b] meets the box grown by `tolerance` in box coordinates (a
  /// slab test).
  bool segment_meets(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double tolerance) const;

private:
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d axes_ = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d inverse_ = Eigen::Matrix3d::Identity();
};

/// The componentwise least and greatest coordinates of a set of points.
struct PointBounds {
  Eigen::Vector3d lo, hi;
};

/// The bounds of the columns of `points` listed in `ids` (all when empty).
/// \throw InputError when there are no points.
PointBounds point_bounds(const Eigen::Ref<const Eigen::Matrix3Xd>& points, const std::vector<std::uint32_t>& ids);

/// The axis-aligned box around `bounds`, grown by `padding` × its largest extent on every
/// side, so that a flat mesh still gets a solid box.
Parallelepiped aabb_around(const PointBounds& bounds, double padding);

/// aabb_around(point_bounds(points, ids), padding).
Parallelepiped fit_aabb(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                        const std::vector<std::uint32_t>& ids, double padding);

/// Oriented boxes: warp/box_fit.h.

}  // namespace ffd
