// The 9-dof manipulator: p -> center + R·S·(p - center) + translate.
#pragma once

#include <optional>

#include <Eigen/Dense>

namespace ffd {

struct Transform {
  Eigen::Vector3d translate = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();
  std::optional<Eigen::Vector3d> center;  // default: centroid of what it acts on

  /// The affine map with `fallback_center` used when no center was given.
  Eigen::Vector3d apply(const Eigen::Vector3d& p, const Eigen::Vector3d& fallback_center) const;
  /// The linear part R·S.
  Eigen::Matrix3d linear() const { return rotation * scale.asDiagonal(); }
};

}  // namespace ffd
