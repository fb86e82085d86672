// Applying a warp to points that are not a mesh's: the Python module's d(points) and
// ffdbench's row that the module is measured against.
#pragma once

#include <Eigen/Core>

#include "warp/warp.h"

namespace ffd {

/// out.col(i) = F(in.col(i)) for every column; when `jacobians` is given, it gets dF/dx at
/// each point as 9 doubles, row-major (J(r, c) at 9 i + 3 r + c); the positions are the
/// same bits with or without them. `in` and `out` may not
/// overlap. The warp must be prepared (Warp::prepare) after its last change. Each point
/// is computed on its own, so the result is the same for any thread count.
void warp_points(const Warp& warp, const Eigen::Ref<const Eigen::Matrix3Xd>& in, Eigen::Ref<Eigen::Matrix3Xd> out,
                 double* jacobians = nullptr);

}  // namespace ffd
