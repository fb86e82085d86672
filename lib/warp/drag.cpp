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

DragResult drag(Lattice& lattice, const std::vector<Eigen::Vector3d>& at,
                const std::vector<Eigen::Vector3d>& to) {
  DragResult result;
  const std::size_t m = at.size();
  std::vector<WeightRow> rows(m);
  Eigen::MatrixXd E(static_cast<Eigen::Index>(m), 3);
  for (std::size_t i = 0; i < m; ++i) {
    lattice.movable_weights(at[i], rows[i]);
    if (rows[i].empty()) ++result.unreachable;
    E.row(static_cast<Eigen::Index>(i)) = (to[i] - lattice.apply(at[i], nullptr)).transpose();
  }
  for (const auto& [flat, delta] : least_norm_change(rows, E)) {
    if (delta.isZero(0.0)) continue;
    const Index3 ijk = lattice.index(flat);
    lattice.move_point(ijk, lattice.point(ijk) + delta);
    ++result.points_changed;
  }
  double sum = 0;
  for (std::size_t i = 0; i < m; ++i) {
    const double r = (lattice.apply(at[i], nullptr) - to[i]).norm();
    result.max_residual = std::max(result.max_residual, r);
    sum += r * r;
  }
  result.rms_residual = m ? std::sqrt(sum / m) : 0.0;
  return result;
}

}  // namespace ffd
