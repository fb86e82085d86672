#include "warp/deformer.h"

namespace ffd {

std::string PointIndex::text() const {
  if (!grid) return std::to_string(n);
  return "[" + std::to_string(ijk[0]) + "," + std::to_string(ijk[1]) + "," + std::to_string(ijk[2]) + "]";
}

Eigen::Matrix3Xd Deformer::points(int level, const std::vector<std::size_t>& ids) const {
  const Eigen::Matrix3Xd all = points(level);
  Eigen::Matrix3Xd out(3, static_cast<Eigen::Index>(ids.size()));
  for (std::size_t i = 0; i < ids.size(); ++i) out.col(static_cast<Eigen::Index>(i)) = all.col(static_cast<Eigen::Index>(ids[i]));
  return out;
}

}  // namespace ffd
