// Vertex normals of a polygon mesh from given positions.
#pragma once

#include "mesh/mesh.h"

namespace ffd {

/// Angle-weighted vertex normals (Thürmer & Wüthrich) of `mesh`'s faces placed at
/// `positions` (3 × num_vertices), written unit-length into `out`. Polygon faces use
/// Newell's normal. Isolated vertices and vertices whose faces are all degenerate get 0.
void compute_vertex_normals(const Mesh& mesh, const Eigen::Ref<const Eigen::Matrix3Xd>& positions,
                            Eigen::Ref<Eigen::Matrix3Xd> out);

/// The same, returning a new array.
Eigen::Matrix3Xd vertex_normals(const Mesh& mesh, const Eigen::Ref<const Eigen::Matrix3Xd>& positions);

}  // namespace ffd
