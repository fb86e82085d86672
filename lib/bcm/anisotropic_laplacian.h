// The anisotropic Laplacian of Botsch & Kobbelt ("Anisotropic bending", Figure 3): the
// cotangent Laplacian of eq. 4 taken not on the surface but on a conformal map of the
// support, stretched along its principal axes to equal diameters, so that the basis
// function's iso-contours meet the outer boundary with about the same slope everywhere.
#pragma once

#include <Eigen/Core>

#include "bcm/cotan_laplacian.h"

namespace ffd {

/// The planar domain: per vertex (u, v, 0) of `triangles`' least-squares conformal map
/// (Lévy et al. 2002, CGAL's LSCM_parameterizer_3), rotated to its principal axes and
/// scaled along the minor one so that both axes span the same diameter. `positions` is
/// 3 × n; every vertex must lie in some triangle. \throw TopologyError about "laplacian"
/// (the anisotropic kind) when the triangles are not a topological disk (one piece, one
/// boundary loop, Euler characteristic 1); InputError about it when the parametrization fails.
Eigen::Matrix3Xd equal_diameter_conformal_map(const Eigen::Ref<const Eigen::Matrix3Xd>& positions,
                                              const std::vector<Triangle>& triangles);

/// The weights the anisotropic energy uses in eq. 5: the standard cotan_laplacian()
/// (negative weights kept) of `triangles` placed on equal_diameter_conformal_map() of
/// `domain` (the support with its handles and
/// rings, a disk), which must contain them. The result covers the vertices `triangles`
/// use, which must come first (0 .. n−1, n the largest index in `triangles` plus one).
/// Same preconditions and errors as equal_diameter_conformal_map().
Laplacian anisotropic_laplacian(const Eigen::Ref<const Eigen::Matrix3Xd>& positions, const std::vector<Triangle>& domain,
                                const std::vector<Triangle>& triangles);

}  // namespace ffd
