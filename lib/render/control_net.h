// A lattice's control net as an overlay: its points where they are now (rest + moved)
// and the edges between neighbours along each axis, in the lattice's input space.
#pragma once

#include "multires/octree_lattice.h"
#include "render/render.h"
#include "warp/lattice.h"

namespace ffd {

/// Every control point of `lattice` (B-spline border points included) and its axis edges.
Overlay control_net(const Lattice& lattice);

/// The points of one level of an octree lattice as shown (rest + deformation) and the
/// edges of its cells (each once), in the lattice's input space.
Overlay control_net(const OctreeLattice& lattice, int level);

}  // namespace ffd
