#include "warp/deformer.h"

namespace ffd {

std::string PointIndex::text() const {
  if (!grid) return std::to_string(n);
  return "[" + std::to_string(ijk[0]) + "," + std::to_string(ijk[1]) + "," + std::to_string(ijk[2]) + "]";
}

std::optional<std::string> index_form_problem(const PointIndex& index, bool grid, const std::string& noun) {
  if (grid && !index.grid) return "expected a lattice index [i, j, k]";
  if (!grid && index.grid) return "expected the number of one of its " + noun + " (an integer), found " + index.text();
  return std::nullopt;
}

Eigen::Matrix3Xd Deformer::points(int level, const std::vector<std::size_t>& ids) const {
  const Eigen::Matrix3Xd all = points(level);
  Eigen::Matrix3Xd out(3, static_cast<Eigen::Index>(ids.size()));
  for (std::size_t i = 0; i < ids.size(); ++i) out.col(static_cast<Eigen::Index>(i)) = all.col(static_cast<Eigen::Index>(ids[i]));
  return out;
}

}  // namespace ffd
