// The vertex colours a writer emits: the mesh's own or a replacement array.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "mesh/mesh.h"

namespace ffd {

/// Null when there are no colours to write; else one colour per vertex.
using VertexColors = const std::vector<Eigen::Vector3f>*;

/// The mesh's own colours, one per vertex (empty if it has none).
std::vector<Eigen::Vector3f> color_array(const Mesh& mesh);

}  // namespace ffd
