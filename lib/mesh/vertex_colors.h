// The vertex colours a writer emits: the mesh's own or a replacement array.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "mesh/mesh.h"

namespace ffd {

/// Null when there are no colours to write; else one colour per vertex.
using VertexColors = const std::vector<Eigen::Vector3f>*;

/// A colour channel in [0, 1] as the byte 0..255 the PLY and COFF writers store (clamped,
/// rounded to nearest).
inline std::uint8_t color_byte(float c) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(c, 0.0f, 1.0f) * 255.0f));
}

/// The mesh's own colours, one per vertex (empty if it has none).
std::vector<Eigen::Vector3f> color_array(const Mesh& mesh);

}  // namespace ffd
