// Direct manipulation of one level of an octree lattice (Hsu, Hughes & Kaufman 1992, as
// warp/drag.h does for tensor-product lattices).
#pragma once

#include <vector>

#include "multires/octree_lattice.h"
#include "warp/drag.h"

namespace ffd {

/// Moves the points of `level` by the least-norm change that takes the object points `at`
/// (in the lattice's input space) to `to`: ΔP = B⁺ (to − F(at)), B holding the weights of
/// the level's points at each object point (OctreeLattice::point_weights: the trilinear
/// weights in the subdivided cell carried back through the Catmull-Clark steps).
DragResult drag(OctreeLattice& lattice, int level, const std::vector<Eigen::Vector3d>& at,
                const std::vector<Eigen::Vector3d>& to, OctreeMove* move = nullptr);

}  // namespace ffd
