// Direct manipulation of a lattice (Hsu, Hughes & Kaufman 1992): object points go to
// target positions by the least-norm change of the movable control points.
#pragma once

#include <vector>

#include "warp/lattice.h"

namespace ffd {

struct DragResult {
  double max_residual = 0;      // largest |F(at_i) - to_i| after the change
  double rms_residual = 0;
  std::size_t points_changed = 0;  // control points that moved
  std::size_t unreachable = 0;     // object points no movable control point influences
};

/// Weights of control points (flat index, weight) at one object point.
using WeightRow = std::vector<std::pair<std::size_t, double>>;

/// The least-norm change of the control points that moves object point i by row i of E:
/// ΔP = B⁺ E, B holding the rows' weights (pseudo-inverse by a complete orthogonal
/// decomposition). One entry per control point some row weights, in flat order.
std::vector<std::pair<std::size_t, Eigen::Vector3d>> least_norm_change(const std::vector<WeightRow>& rows,
                                                                       const Eigen::MatrixXd& E);

/// Changes the movable control points of `lattice` by ΔP = B⁺ (to − F(at)), where B holds
/// the basis weights of the movable points at each object point (pseudo-inverse by a
/// complete orthogonal decomposition: the minimum-norm exact solution when the targets
/// are reachable, the minimum-norm least-squares one otherwise). `at` are positions in
/// the lattice's input space (where the points are before this lattice deforms them).
DragResult drag(Lattice& lattice, const std::vector<Eigen::Vector3d>& at,
                const std::vector<Eigen::Vector3d>& to);

}  // namespace ffd
