#include "mesh/vtk_volume_io.h"

#include <array>

namespace ffd {
namespace {

// The node count of each VTK kind that has a fixed one (vtkCellType.h); 0: any count
// (poly-vertex, poly-line, strip, polygon, polyhedron, Lagrange and Bezier kinds).
std::uint64_t fixed_node_count(std::uint8_t type) {
  switch (type) {
    case 1: return 1;    // vertex
    case 3: return 2;    // line
    case 5: return 3;    // triangle
    case 8: return 4;    // pixel
    case 9: return 4;    // quad
    case 10: return 4;   // tetra
    case 11: return 8;   // voxel
    case 12: return 8;   // hexahedron
    case 13: return 6;   // wedge
    case 14: return 5;   // pyramid
    case 15: return 10;  // pentagonal prism
    case 16: return 12;  // hexagonal prism
    case 21: return 3;   // quadratic edge
    case 22: return 6;   // quadratic triangle
    case 23: return 8;   // quadratic quad
    case 24: return 10;  // quadratic tetra
    case 25: return 20;  // quadratic hexahedron
    case 26: return 15;  // quadratic wedge
    case 27: return 13;  // quadratic pyramid
    case 28: return 9;   // biquadratic quad
    case 29: return 27;  // triquadratic hexahedron
    default: return 0;
  }
}

// Per type: 0 for a type refused, 1 for any node count, else the count + 2 (at most 29).
const std::array<std::uint8_t, 256> kNodesNeeded = [] {
  std::array<std::uint8_t, 256> t{};
  for (int type = 0; type < 256; ++type) {
    const auto u = static_cast<std::uint8_t>(type);
    if (u == cell_type::kOtherCell || cell_type_dimension(u) < 0) continue;
    t[u] = static_cast<std::uint8_t>(fixed_node_count(u) + (fixed_node_count(u) ? 2 : 1));
  }
  return t;
}();

}  // namespace

bool vtk_cell_fits(std::uint8_t type, std::uint64_t nodes) {
  const std::uint8_t needed = kNodesNeeded[type];
  return needed == 1 ? nodes > 0 : needed > 1 && nodes + 2 == needed;
}

std::string vtk_cell_problem(std::uint8_t type, std::uint64_t nodes) {
  if (vtk_cell_fits(type, nodes)) return {};
  if (type == cell_type::kOtherCell || cell_type_dimension(type) < 0)
    return "unknown cell type " + std::to_string(type);
  const std::uint64_t needed = fixed_node_count(type);
  if (needed != 0 && nodes != needed)
    return "a " + cell_type_name(type) + " cell has " + std::to_string(needed) + " nodes, not " +
           std::to_string(nodes);
  if (nodes == 0) return "a " + cell_type_name(type) + " cell without nodes";
  return {};
}

}  // namespace ffd
