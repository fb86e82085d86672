#include "multires/octree_drag.h"

#include <algorithm>
#include <cmath>

namespace ffd {

DragResult drag(OctreeLattice& lattice, int level, const std::vector<Eigen::Vector3d>& at,
                const std::vector<Eigen::Vector3d>& to, OctreeMove* move) {
  DragResult result;
  const std::size_t m = at.size();
  std::vector<WeightRow> rows(m);
  Eigen::MatrixXd E(static_cast<Eigen::Index>(m), 3);
  std::vector<std::pair<std::int32_t, double>> weights;
  for (std::size_t i = 0; i < m; ++i) {
    lattice.point_weights(level, at[i], weights);
    for (const auto& [p, w] : weights) rows[i].push_back({static_cast<std::size_t>(p), w});
    if (rows[i].empty()) ++result.unreachable;
    E.row(static_cast<Eigen::Index>(i)) = (to[i] - lattice.apply(at[i], nullptr)).transpose();
  }
  const Eigen::Matrix3Xd shown = lattice.points(level);
  std::vector<std::int32_t> ids;
  std::vector<Eigen::Vector3d> targets;
  for (const auto& [p, delta] : least_norm_change(rows, E)) {
    if (delta.isZero(0.0)) continue;
    ids.push_back(static_cast<std::int32_t>(p));
    targets.push_back(shown.col(static_cast<Eigen::Index>(p)) + delta);
  }
  const OctreeMove moved = lattice.move_points(level, ids, targets);
  if (move) *move = moved;
  result.points_changed = ids.size();
  double sum = 0;
  for (std::size_t i = 0; i < m; ++i) {
    const double r = (lattice.apply(at[i], nullptr) - to[i]).norm();
    result.max_residual = std::max(result.max_residual, r);
    sum += r * r;
  }
  result.rms_residual = m ? std::sqrt(sum / static_cast<double>(m)) : 0.0;
  return result;
}

}  // namespace ffd
