// Boxes fitted to points: axis-aligned, along the principal components (Gottschalk's
// OBB, what Ono et al. use), or of least volume (CGAL's optimal bounding box).
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "warp/parallelepiped.h"

namespace ffd {

/// The box along the unit, right-handed axes `directions` (columns) around the columns of
/// `points` listed in `ids` (all when empty), padded like fit_aabb: `padding` × its largest
/// extent on every side, each extent at least 1e-6 of the largest. The axes are reordered
/// and signed to lie closest to x, y, z, so lattice index i still runs roughly along x.
/// \throw InputError when there are no points, or the box is not finite (coordinates near
/// the limits of double).
Parallelepiped fit_box_along(const Eigen::Ref<const Eigen::Matrix3Xd>& points, const std::vector<std::uint32_t>& ids,
                             const Eigen::Matrix3d& directions, double padding);

/// The box along the principal components of the points (the eigenvectors of their
/// covariance, computed on coordinates scaled to [-1, 1] so that no finite input
/// overflows), padded like fit_aabb. Fewer than 4 points get fit_aabb's box.
Parallelepiped fit_principal_box(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                                 const std::vector<std::uint32_t>& ids, double padding);

/// The box of least volume around the points (CGAL's Optimal_bounding_box on an
/// exact-predicates kernel, a fixed seed: deterministic), padded like fit_aabb. Fewer
/// than 4 points get fit_aabb's box.
Parallelepiped fit_min_volume_box(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                                  const std::vector<std::uint32_t>& ids, double padding);

}  // namespace ffd
