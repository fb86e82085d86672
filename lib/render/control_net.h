// A deformer's control net as an overlay: one level's points where they are now (rest +
// moved) and the net's edges (a lattice's neighbours along each axis, an octree level's
// cell edges), in the deformer's input space.
#pragma once

#include "render/render.h"
#include "warp/deformer.h"

namespace ffd {

/// Every point of `level` of `deformer` (a B-spline's border points included) and its edges.
Overlay control_net(const Deformer& deformer, int level);

/// The net of the deformer's default level (the finest).
inline Overlay control_net(const Deformer& deformer) { return control_net(deformer, deformer.default_level()); }

}  // namespace ffd
