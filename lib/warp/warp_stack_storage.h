// The warp stack's per-vertex data as Surface_mesh properties, for code that holds the
// CGAL side of a Mesh (mesh_storage.h) and adds vertices while it reads them (remeshing):
// a property stays valid through connectivity changes, Mesh's 3 × n views do not.
#pragma once

#include "mesh/mesh_storage.h"
#include "warp/warp_stack.h"

namespace ffd {

/// Warp k's input positions on the mesh `storage` belongs to: where each vertex is before
/// warp k acts (the rest positions for k = 0, else what the warps below k made of them).
/// \pre k < the size of the warp stack acting on the mesh.
inline Vec3Property warp_input_positions(MeshStorage& storage, std::size_t k) {
  return k == 0 ? storage.rest : storage.vec3_attribute(WarpStack::input_attribute(k));
}

}  // namespace ffd
