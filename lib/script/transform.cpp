#include "script/transform.h"

namespace ffd {

Eigen::Vector3d Transform::apply(const Eigen::Vector3d& p, const Eigen::Vector3d& fallback_center) const {
  const Eigen::Vector3d c = center ? *center : fallback_center;
  return c + rotation * (scale.asDiagonal() * (p - c)) + translate;
}

}  // namespace ffd
