#include "mesh/volume_mesh.h"

#include <algorithm>
#include <iterator>

namespace ffd {

std::string cell_type_name(std::uint8_t type) {
  using namespace cell_type;
  switch (type) {
    case kOtherCell: return "other";
    case kVertex: return "vertex";
    case kLine: return "line";
    case kTriangle: return "triangle";
    case kPolygon: return "polygon";
    case kQuad: return "quad";
    case kTetra: return "tetra";
    case kHexahedron: return "hexahedron";
    case kWedge: return "wedge";
    case kPyramid: return "pyramid";
    case kQuadraticEdge: return "quadratic line";
    case kQuadraticTriangle: return "quadratic triangle";
    case kQuadraticQuad: return "quadratic quad";
    case kQuadraticTetra: return "quadratic tetra";
    case kQuadraticHexahedron: return "quadratic hexahedron";
    case kQuadraticWedge: return "quadratic wedge";
    case kQuadraticPyramid: return "quadratic pyramid";
    case kBiquadraticQuad: return "biquadratic quad";
    case kTriquadraticHexahedron: return "triquadratic hexahedron";
    case kPolyhedron: return "polyhedron";
    default: return "VTK type " + std::to_string(type);
  }
}

int cell_type_dimension(std::uint8_t type) {
  // VTK's numbers by dimension (vtkCellType.h): linear, quadratic, Lagrange and Bezier kinds.
  static constexpr std::uint8_t kOne[] = {3, 4, 21, 35, 68, 75};
  static constexpr std::uint8_t kTwo[] = {5, 6, 7, 8, 9, 22, 23, 28, 30, 34, 36, 69, 70, 76, 77};
  static constexpr std::uint8_t kThree[] = {10, 11, 12, 13, 14, 15, 16, 24, 25, 26, 27, 29, 31, 32, 33, 37,
                                            42, 71, 72, 73, 74, 78, 79, 80, 81};
  auto in = [type](const auto& list) { return std::find(std::begin(list), std::end(list), type) != std::end(list); };
  if (type == cell_type::kVertex || type == 2) return 0;
  if (in(kOne)) return 1;
  if (in(kTwo)) return 2;
  if (in(kThree)) return 3;
  return -1;
}

void VolumeCells::add(std::uint8_t cell_type, const std::uint32_t* nodes, std::size_t count) {
  type.push_back(cell_type);
  node.insert(node.end(), nodes, nodes + count);
  offset.push_back(node.size());
  if (!face_offset.empty()) face_offset.push_back(face.size());
}

void VolumeCells::add_polyhedron(const std::vector<std::uint32_t>& nodes, const std::vector<std::uint32_t>& faces) {
  if (face_offset.empty()) face_offset.assign(type.size(), 0);
  face_offset.push_back(face.size());
  face.insert(face.end(), faces.begin(), faces.end());
  type.push_back(cell_type::kPolyhedron);
  node.insert(node.end(), nodes.begin(), nodes.end());
  offset.push_back(node.size());
}

std::string volume_format_name(VolumeFormat format) {
  switch (format) {
    case VolumeFormat::Vtu: return "VTK XML unstructured grid";
    case VolumeFormat::Vtk: return "legacy VTK unstructured grid";
    case VolumeFormat::Msh: return "Gmsh MSH";
    case VolumeFormat::Su2: return "SU2";
    case VolumeFormat::Foam: return "OpenFOAM polyMesh";
  }
  return "volume mesh";
}

}  // namespace ffd
