#include "script/transform.h"

#include <cmath>

namespace ffd {

Eigen::Vector3d Transform::apply(const Eigen::Vector3d& p, const Eigen::Vector3d& fallback_center) const {
  const Eigen::Vector3d c = center ? *center : fallback_center;
  return c + rotation * (scale.asDiagonal() * (p - c)) + translate;
}

Eigen::Vector3d parse_vec3(const nlohmann::json& j) {
  return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

bool parse_transform(const nlohmann::json& j, Transform& out) {
  out = Transform{};
  if (j.contains("translate")) out.translate = parse_vec3(j["translate"]);
  if (j.contains("scale")) {
    const nlohmann::json& s = j["scale"];
    out.scale = s.is_number() ? Eigen::Vector3d::Constant(s.get<double>()) : parse_vec3(s);
  }
  if (j.contains("center")) out.center = parse_vec3(j["center"]);
  if (j.contains("rotate")) {
    const Eigen::Vector3d axis = parse_vec3(j["rotate"]["axis"]);
    if (!(axis.norm() > 0)) return false;
    const double radians = j["rotate"]["degrees"].get<double>() * M_PI / 180.0;
    out.rotation = Eigen::AngleAxisd(radians, axis.normalized()).toRotationMatrix();
  }
  return true;
}

}  // namespace ffd
