// A lattice's control net as an overlay: its points where they are now (rest + moved)
// and the edges between neighbours along each axis, in the lattice's input space.
#pragma once

#include "render/render.h"
#include "warp/lattice.h"

namespace ffd {

/// Every control point of `lattice` (B-spline border points included) and its axis edges.
Overlay control_net(const Lattice& lattice);

}  // namespace ffd
