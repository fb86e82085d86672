// Direct manipulation (Hsu, Hughes & Kaufman 1992) for every deformer: object points go to
// target positions by the least-norm change of one level's movable control points.
#pragma once

#include <vector>

#include "warp/deformer.h"

namespace ffd {

struct DragResult {
  double max_residual = 0;      // largest |F(at_i) - to_i| after the change
  double rms_residual = 0;
  std::size_t points_changed = 0;  // control points that moved
  std::size_t unreachable = 0;     // object points no movable control point influences
};

/// Weights of control points (id, weight) at one object point.
using WeightRow = PointWeights;

/// The least-norm change of the control points that moves object point i by row i of E:
/// ΔP = B⁺ E, B holding the rows' weights (pseudo-inverse by a complete orthogonal
/// decomposition). One entry per control point some row weights, ids ascending.
std::vector<std::pair<std::size_t, Eigen::Vector3d>> least_norm_change(const std::vector<WeightRow>& rows,
                                                                       const Eigen::MatrixXd& E);

/// Changes the movable points of `level` by ΔP = B⁺ (to − F(at)), where B holds their
/// weights at each object point (Deformer::movable_weights; the pseudo-inverse gives the
/// minimum-norm exact solution when the targets are reachable, the minimum-norm
/// least-squares one otherwise). `at` are positions in the deformer's input space (where
/// the points are before it deforms them). `moved`, when given, gets the move's report.
DragResult drag(Deformer& deformer, int level, const std::vector<Eigen::Vector3d>& at,
                const std::vector<Eigen::Vector3d>& to, MoveReport* moved = nullptr);

/// drag at the deformer's default level (the finest).
inline DragResult drag(Deformer& deformer, const std::vector<Eigen::Vector3d>& at,
                       const std::vector<Eigen::Vector3d>& to) {
  return drag(deformer, deformer.default_level(), at, to);
}

}  // namespace ffd
