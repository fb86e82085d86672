// What the ops that create scattered-point deformers (rbf, idw, cage) share: the shape
// the script checks know them by, and their control points from the grammar's `points`.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "script/scene.h"
#include "script/script_checks.h"
#include "script/script_values.h"

namespace ffd {

/// One level, points named by their number: `count` of them ("cage vertices 0 to 7"),
/// or, when `count` is 0 (known only when the step runs), any non-negative number.
DeformerShape scattered_shape(const std::string& kind, std::size_t count, const std::string& noun);

/// Checks what the script decides of `source`: a selection's indices are vertex numbers.
void check_point_source(const PointSource& source);

/// The points of `source`: its list or file, or the selected vertices' current positions.
std::vector<Eigen::Vector3d> rest_points(const PointSource& source, const Scene& scene);

}  // namespace ffd
