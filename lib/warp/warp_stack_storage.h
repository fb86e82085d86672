// The warp stack's per-vertex data as Surface_mesh properties, for code that works on a
// Mesh's halfedge view (halfedge_view_cgal.h) and adds vertices while it reads them
// (remeshing): a property stays valid through connectivity changes.
#pragma once

#include "mesh/halfedge_view_cgal.h"
#include "warp/warp_stack.h"

namespace ffd {

/// Warp k's input positions on the view's mesh: where each vertex is before warp k acts
/// (the rest positions for k = 0, else what the warps below k made of them).
/// \pre k < the size of the warp stack acting on the mesh.
inline Vec3Property warp_input_positions(HalfedgeView& view, std::size_t k) {
  return k == 0 ? view.rest : view.vec3_attribute(WarpStack::input_attribute(k));
}

/// The same for warp k's input normals (the rest normals for k = 0).
inline Vec3Property warp_input_normals(HalfedgeView& view, std::size_t k) {
  return k == 0 ? view.rest_normal : view.vec3_attribute(WarpStack::input_normal_attribute(k));
}

}  // namespace ffd
