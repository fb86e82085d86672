#include "warp/drag.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace ffd {

std::vector<std::pair<std::size_t, Eigen::Vector3d>> least_norm_change(const std::vector<WeightRow>& rows,
                                                                       const Eigen::MatrixXd& E) {
  std::map<std::size_t, Eigen::Index> column;  // the points that influence any object point
  for (const WeightRow& row : rows)
    for (const auto& [flat, w] : row) column.emplace(flat, 0);
  Eigen::Index next = 0;
  for (auto& [flat, c] : column) c = next++;
  std::vector<std::pair<std::size_t, Eigen::Vector3d>> change;
  if (next == 0) return change;
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(rows.size()), next);
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (const auto& [flat, w] : rows[i]) B(static_cast<Eigen::Index>(i), column[flat]) += w;
  const Eigen::MatrixXd dP = B.completeOrthogonalDecomposition().solve(E);
  for (const auto& [flat, c] : column) change.push_back({flat, dP.row(c).transpose()});
  return change;
}

DragResult drag(Deformer& deformer, int level, const std::vector<Eigen::Vector3d>& at,
                const std::vector<Eigen::Vector3d>& to, MoveReport* moved) {
  DragResult result;
  const std::size_t m = at.size();
  std::vector<WeightRow> rows(m);
  Eigen::MatrixXd E(static_cast<Eigen::Index>(m), 3);
  for (std::size_t i = 0; i < m; ++i) {
    deformer.movable_weights(level, at[i], rows[i]);
    if (rows[i].empty()) ++result.unreachable;
    E.row(static_cast<Eigen::Index>(i)) = (to[i] - deformer.apply(at[i], nullptr)).transpose();
  }
  std::vector<std::size_t> ids;
  std::vector<Eigen::Vector3d> deltas;
  for (const auto& [id, delta] : least_norm_change(rows, E)) {
    if (delta.isZero(0.0)) continue;
    ids.push_back(id);
    deltas.push_back(delta);
  }
  const Eigen::Matrix3Xd now = deformer.points(level, ids);
  std::vector<Eigen::Vector3d> targets;
  for (std::size_t i = 0; i < ids.size(); ++i) targets.push_back(now.col(static_cast<Eigen::Index>(i)) + deltas[i]);
  const MoveReport report = deformer.move_points(level, ids, targets);
  if (moved) *moved = report;
  result.points_changed = ids.size();
  double sum = 0;
  for (std::size_t i = 0; i < m; ++i) {
    const double r = (deformer.apply(at[i], nullptr) - to[i]).norm();
    result.max_residual = std::max(result.max_residual, r);
    sum += r * r;
  }
  result.rms_residual = m ? std::sqrt(sum / static_cast<double>(m)) : 0.0;
  return result;
}

}  // namespace ffd
